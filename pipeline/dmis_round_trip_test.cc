// The lab's round trip: plan -> DMIS program (.dmi) -> a simulated CMM answering it (the virtual
// CMM of testpieces::SimulatePiece: Table 2 errors, 0.5 um noise, random placement; it probes
// each F(<feature>_<k>) of the program's DCC part at the planned point and reports
// FA(<feature>_<k>) with 6 decimals, as CMM software prints) -> the .dmo read through the
// point-file dispatch -> identification. The same simulated points, rounded to the same 6
// decimals, go through the contract CSV. Both readers then hold the same doubles (coordinates
// parse identically; normals are normalised by the same rule), so the identification must agree
// to 1e-9 um / urad (exact up to nothing but summation order, which is the same): any larger
// difference is a reader or label-mapping fault, not numerics.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <random>
#include <sstream>

#include "pipeline/identify_stage.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/io/dmis_reader.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/point_io.h"
#include "pipeline/testing/turning_fixture.h"
#include "testpieces/dmis_program.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;
using test_support::AcTable;
using test_support::RandomTable2;
using test_support::ToErrorState;
using test_support::Turning;

std::string Fixed6(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  return buf;
}

// The virtual CMM runs the program: for every `F(label)=FEAT/POINT,CART,x,y,z,...` after
// MODE/AUTO it probes the plan point at that nominal (same feature, within 1 um) and answers
// FA(label) with the simulated measurement.
std::string AnswerProgram(const std::string& dmi, const testpieces::SimulatedPiece& sim) {
  const PointSet plan = testpieces::PlanPointSet(sim.truth.plan);
  std::istringstream in(dmi);
  std::string line, out = "$$ virtual CMM output\nFILNAM/'turning',05.3\nUNITS/MM,ANGDEC\n";
  bool dcc = false;
  while (std::getline(in, line)) {
    if (line.rfind("MODE/AUTO", 0) == 0) dcc = true;
    if (!dcc || line.rfind("F(", 0) != 0 || line.find("=FEAT/POINT,CART,") == std::string::npos) continue;
    const std::string label = line.substr(2, line.find(')') - 2);
    std::vector<double> v;
    std::stringstream nums(line.substr(line.find("CART,") + 5));
    for (std::string cell; std::getline(nums, cell, ',');) v.push_back(std::stod(cell));
    const Eigen::Vector3d nominal(v[0], v[1], v[2]);
    const std::string feature = DmisFeatureOfLabel(label);
    std::size_t hit = plan.size();
    for (std::size_t i = 0; i < plan.size(); ++i)
      if (plan.feature_names[static_cast<std::size_t>(plan.feature[i])] == feature &&
          (plan.xyz_mm[i] - nominal).norm() < 1e-3)
        hit = i;
    if (hit == plan.size()) {
      ADD_FAILURE() << "the program probes " << label << " at a point the plan does not hold";
      continue;
    }
    const Eigen::Vector3d& p = sim.points.xyz_mm[hit];
    const Eigen::Vector3d& n = sim.points.normal[hit];
    out += "FA(" + label + ")=FEAT/POINT,CART," + Fixed6(p.x()) + "," + Fixed6(p.y()) + ",$\n  " + Fixed6(p.z()) + "," +
           Fixed6(n.x()) + "," + Fixed6(n.y()) + "," + Fixed6(n.z()) + "\n";
  }
  return out + "ENDFIL\n";
}

TEST(DmisRoundTrip, PlanProgramVirtualCmmIdentifiesAsTheCsv) {
  const fs::path dir = fs::temp_directory_path() / ("tpcal_dmis_round_trip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937_64 rng(17);
  const auto truth = RandomTable2(rng);
  testpieces::PieceSimOptions o;
  o.noise_um = 0.5;
  o.seed = 1717;
  o.random_placement = true;
  auto sim = testpieces::SimulatePiece(Turning(), AcTable(), ToErrorState(truth), o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();

  auto dmi = testpieces::FormatDmisProgram(Turning(), sim->truth.plan);
  ASSERT_TRUE(dmi.ok()) << dmi.status().ToString();
  EXPECT_NE(dmi->find("D(TPCAL_DATUM)=DATSET/DAT(A),ZDIR,ZORIG,DAT(B),XORIG,YORIG,DAT(C),XDIR"), std::string::npos);
  const std::string dmo_path = (dir / "answer.dmo").string();
  ASSERT_TRUE(WriteFileAtomic(dmo_path, AnswerProgram(*dmi, *sim)).ok());

  // The same points through the CSV, rounded as the CMM printed them.
  const std::string csv_path = (dir / "points.csv").string();
  PointWriteOptions wo;
  wo.fixed_decimals = 6;
  ASSERT_TRUE(WritePointCsv(csv_path, sim->points, wo).ok());

  auto dmo = ReadPointFile(dmo_path);
  ASSERT_TRUE(dmo.ok()) << dmo.status().ToString();
  auto csv = ReadPointFile(csv_path);
  ASSERT_TRUE(csv.ok()) << csv.status().ToString();
  ASSERT_EQ(dmo->points.size(), csv->points.size());
  EXPECT_EQ(dmo->points.feature_names, csv->points.feature_names);
  for (std::size_t i = 0; i < csv->points.size(); ++i) {
    ASSERT_EQ(dmo->points.feature[i], csv->points.feature[i]) << i;
    ASSERT_EQ(dmo->points.xyz_mm[i], csv->points.xyz_mm[i]) << i;
    ASSERT_EQ(dmo->points.normal[i], csv->points.normal[i]) << i;
  }

  auto a = RunIdentifyStage(Turning(), AcTable(), dmo->points);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  auto b = RunIdentifyStage(Turning(), AcTable(), csv->points);
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  ASSERT_EQ(a->identification.parameters.size(), b->identification.parameters.size());
  for (std::size_t k = 0; k < a->identification.parameters.size(); ++k) {
    const auto& pa = a->identification.parameters[k];
    const auto& pb = b->identification.parameters[k];
    EXPECT_EQ(pa.name, pb.name);
    EXPECT_EQ(pa.identifiable, pb.identifiable) << pa.name;
    EXPECT_NEAR(pa.value, pb.value, 1e-9) << pa.name;
  }
  // And the identification is a real one: identifiable Table 2 values within 3 u of the truth.
  int checked = 0;
  for (const auto& p : a->identification.parameters) {
    if (!p.identifiable || truth.count(p.name) == 0) continue;
    ++checked;
    EXPECT_NEAR(p.value, truth.at(p.name), std::max(0.05, 3 * p.u)) << p.name;
  }
  EXPECT_GE(checked, 8);

  // A label the plan does not know: file:line, nothing read.
  auto bytes = ReadFileBytes(dmo_path);
  ASSERT_TRUE(bytes.ok());
  std::string bad(bytes->view());
  bad += "FA(XX_1)=FEAT/POINT,CART,1,2,3,0,0,1\n";
  DmisReadOptions known;
  for (const auto& f : testpieces::PlanPointSet(sim->truth.plan).feature_names) known.known_features.push_back(f);
  auto r = ParseDmisOutput(bad, "answer.dmo", known);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().ToString().find("answer.dmo:"), std::string::npos);
  EXPECT_NE(r.status().message().find("feature 'XX' is not in the plan"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
