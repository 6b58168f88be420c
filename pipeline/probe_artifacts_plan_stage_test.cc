// The probe-artifacts plan stage (pipeline/probe_artifacts_plan_stage.h). Truth: seed 000's plan
// (testpieces::MakeProbeArtifactsPlan with its defaults: A 0, -30, -60, -90 deg, C every 60 deg,
// seed 000's three columns) on the nominal A/C table. The plan file carries the nominal contacts
// rounded to 1e-4 mm, so a value read back is within 0.05 um (5e-5 mm) of the plan's contact; the
// approach is rounded to 1e-12 (within 1e-12 per component). The nominal contact is what the
// virtual touch reports under zero errors (kinematics::SimulateTouch, exact to 1e-9 mm).
#include "pipeline/probe_artifacts_plan_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/probe_artifact_identification.h"
#include "kinematics/probe_touch.h"

namespace tpcal::pipeline {
namespace {

constexpr double kProbePlanRounding_mm = 5e-5;  // 4 decimals written
constexpr double kProbePlanApproachRounding = 1e-12;
constexpr double kProbePlanTouchExact_mm = 1e-9;  // zero-error touch: rounding of ~150 mm coordinates

ProbeArtifactsPlanRequest ProbePlanTestRequest() {
  ProbeArtifactsPlanRequest r;
  r.csv_path = "plan.csv";
  return r;
}

TEST(ProbeArtifactsPlanStage, PlanFileReadsBackAsTheNominalContacts) {
  auto r = RunProbeArtifactsPlanStage(ProbePlanTestRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->machine, "ac_table");
  ASSERT_EQ(r->files.size(), 1u);
  EXPECT_EQ(r->files[0].path, "plan.csv");
  auto file = ParseProbePoints(r->csv, "plan.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_TRUE(file->is_plan);
  EXPECT_FALSE(file->has_t);
  EXPECT_EQ(file->rotary_axes, (std::vector<char>{'A', 'C'}));
  ASSERT_EQ(file->rows.size(), r->plan.touches.size());
  ASSERT_EQ(r->plan.poses.size(), 24u);
  // Every touch of the plan is a row or a skipped line: 24 poses x 3 boxes x 5 faces.
  EXPECT_EQ(r->plan.touches.size() + r->plan.skipped.size(), 24u * 3u * 5u);
  EXPECT_EQ(r->skipped_lines.size(), r->plan.skipped.size());
  std::set<std::pair<double, double>> poses;
  for (std::size_t i = 0; i < file->rows.size(); ++i) {
    const ProbePointRow& row = file->rows[i];
    const testpieces::PlannedTouch& t = r->plan.touches[i];
    EXPECT_EQ(row.rotary_deg.at('A'), ProbeRotaryDeg(t.rotary.a_rad)) << i;
    EXPECT_EQ(row.rotary_deg.at('C'), ProbeRotaryDeg(t.rotary.c_rad)) << i;
    poses.insert({row.rotary_deg.at('A'), row.rotary_deg.at('C')});
    EXPECT_EQ(row.artifact, r->plan.artifacts.boxes[t.artifact].name) << i;
    EXPECT_EQ(row.face, kinematics::BoxFaceName(t.face)) << i;
    EXPECT_LE((row.point_mm - t.contact_mm).cwiseAbs().maxCoeff(), kProbePlanRounding_mm) << i;
    EXPECT_LE((row.approach - t.approach).cwiseAbs().maxCoeff(), kProbePlanApproachRounding) << i;
  }
  // The commands are the seed's grid, written exactly ("-30", "60").
  for (const auto& [a, c] : poses) {
    EXPECT_TRUE(a == 0.0 || a == -30.0 || a == -60.0 || a == -90.0) << a;
    EXPECT_EQ(std::fmod(c, 60.0), 0.0) << c;
  }
  EXPECT_EQ(poses.size(), 24u);  // every pose has a touch (the tops at A = 0 at least)
}

TEST(ProbeArtifactsPlanStage, NominalContactIsTheErrorFreeTouch) {
  auto r = RunProbeArtifactsPlanStage(ProbePlanTestRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  const kinematics::ErrorState zero(*m);
  for (const testpieces::PlannedTouch& t : r->plan.touches) {
    const kinematics::FaceGeometry face = kinematics::FaceOf(r->plan.artifacts.boxes[t.artifact], t.face);
    auto c = kinematics::SimulateTouch(*m, zero, t.rotary, face, t.target_part_mm, kinematics::TouchOptions{});
    ASSERT_TRUE(c.ok()) << c.status().ToString();
    EXPECT_LE((*c - t.contact_mm).cwiseAbs().maxCoeff(), kProbePlanTouchExact_mm);
  }
}

// The plan is what an error-free machine reports: read back and identified
// (kinematics::IdentifyProbeArtifacts), every identifiable map entry is zero within 4 u (u from
// the file's 0.1 um rounding) + 1e-3 um / urad for the printed digits.
TEST(ProbeArtifactsPlanStage, PlanIdentifiesAnErrorFreeMachine) {
  auto r = RunProbeArtifactsPlanStage(ProbePlanTestRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto file = ParseProbePoints(r->csv, "plan.csv");
  ASSERT_TRUE(file.ok());
  const kinematics::ArtifactSet artifacts = kinematics::Seed000Artifacts();
  std::vector<kinematics::ProbeTouch> touches;
  for (const ProbePointRow& row : file->rows) {
    kinematics::ProbeTouch t;
    t.rotary.a_rad = DegToRad(row.rotary_deg.at('A'));
    t.rotary.c_rad = DegToRad(row.rotary_deg.at('C'));
    t.artifact = artifacts.Find(row.artifact);
    ASSERT_GE(t.artifact, 0) << row.artifact;
    auto face = kinematics::BoxFaceFromName(row.face);
    ASSERT_TRUE(face.has_value()) << row.face;
    t.face = *face;
    t.contact_mm = row.point_mm;
    t.approach = row.approach;
    t.line = row.line;
    touches.push_back(t);
  }
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  auto id = kinematics::IdentifyProbeArtifacts(*m, artifacts, touches);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  int identified = 0;
  for (const kinematics::ErrorMapEntry& e : id->maps.entries) {
    if (!e.identifiable) continue;
    ++identified;
    EXPECT_LT(std::abs(e.value), 4.0 * e.u + 1e-3) << e.coefficient << " " << e.value << " +- " << e.u;
  }
  EXPECT_GT(identified, 0);
}

// A -90 deg, C 0: the columns lie on their side; the face turned down is skipped, named in a line.
TEST(ProbeArtifactsPlanStage, SkippedTouchesAreListedWithTheirReason) {
  auto r = RunProbeArtifactsPlanStage(ProbePlanTestRequest());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_FALSE(r->skipped_lines.empty());
  bool faces_down = false;
  for (const std::string& line : r->skipped_lines) {
    EXPECT_EQ(line.rfind("A ", 0), 0u) << line;
    EXPECT_NE(line.find(" skipped: "), std::string::npos) << line;
    faces_down = faces_down || line.find("skipped: faces down") != std::string::npos;
  }
  EXPECT_TRUE(faces_down);
  testpieces::SkippedTouch s;
  s.rotary.a_rad = DegToRad(-90.0), s.rotary.c_rad = DegToRad(60.0);
  s.artifact = 0, s.face = kinematics::BoxFace::kMinusX, s.reason = "faces down";
  EXPECT_EQ(SkippedTouchLine(r->plan, s), "A -90 C 60: artifact 1 face -X skipped: faces down");
}

TEST(ProbeArtifactsPlanStage, ProgramDialectFromTheExtensionAndItsFiles) {
  ProbeArtifactsPlanRequest r = ProbePlanTestRequest();
  r.nc.output = "PA.ngc";
  r.nc.date = "none";
  auto linuxcnc = RunProbeArtifactsPlanStage(r);
  ASSERT_TRUE(linuxcnc.ok()) << linuxcnc.status().ToString();
  ASSERT_EQ(linuxcnc->files.size(), 3u);
  EXPECT_EQ(linuxcnc->files[1].path, "PA.ngc");
  EXPECT_EQ(linuxcnc->files[2].path, "PA.ngc.tbl");
  const std::string& text = linuxcnc->files[1].text;
  std::size_t probes = 0;
  for (std::size_t p = text.find("G38.2"); p != std::string::npos; p = text.find("G38.2", p + 1)) ++probes;
  EXPECT_EQ(probes, linuxcnc->plan.touches.size());
  r.nc.output = "PA.mpf";
  auto sinumerik = RunProbeArtifactsPlanStage(r);
  ASSERT_TRUE(sinumerik.ok()) << sinumerik.status().ToString();
  ASSERT_EQ(sinumerik->files.size(), 2u);
  EXPECT_NE(sinumerik->files[1].text.find("MEAS=1 G1"), std::string::npos);
}

TEST(ProbeArtifactsPlanStage, BadInputNamesTheOptionOrFileLine) {
  ProbeArtifactsPlanRequest r = ProbePlanTestRequest();
  r.nc.output = "PA.txt";
  auto dialect = RunProbeArtifactsPlanStage(r);
  ASSERT_FALSE(dialect.ok());
  EXPECT_NE(dialect.status().ToString().find("--dialect: needed for --nc PA.txt"), std::string::npos)
      << dialect.status().ToString();
  r = ProbePlanTestRequest();
  r.nc.dialect = "fanuc";
  auto no_nc = RunProbeArtifactsPlanStage(r);
  ASSERT_FALSE(no_nc.ok());
  EXPECT_NE(no_nc.status().ToString().find("--dialect needs --nc PROGRAM"), std::string::npos);
  // A stroke violation names the block at the program's path: the sample A/C table's strokes
  // cannot reach a column 2 m off the table centre.
  const auto dir = std::filesystem::temp_directory_path() / "tpcal_probe_plan_stage_test";
  std::filesystem::create_directories(dir);
  const std::string far = (dir / "far.yaml").string();
  std::ofstream(far) << "artifacts:\n  - {name: \"far\", base_centre_mm: [2000, 0, 0], size_mm: [30, 30, 60]}\n";
  r = ProbePlanTestRequest();
  r.machine_path = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml";
  r.artifacts_path = far;
  r.nc.output = "PA.ngc";
  auto strokes = RunProbeArtifactsPlanStage(r);
  ASSERT_FALSE(strokes.ok());
  EXPECT_EQ(strokes.status().file(), "PA.ngc") << strokes.status().ToString();
  // A malformed artifact file: file:line.
  const std::string artifacts = (dir / "a.yaml").string();
  std::ofstream(artifacts) << "schema: tpcal.artifacts/1\nartifacts:\n  - {name: \"1\", base_centre_mm: [100, 0, 0], "
                              "size_mm: [30, 0, 60]}\n";
  r = ProbePlanTestRequest();
  r.artifacts_path = artifacts;
  auto bad = RunProbeArtifactsPlanStage(r);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().file(), artifacts) << bad.status().ToString();
  EXPECT_EQ(bad.status().line(), 3u) << bad.status().ToString();
  // Not an A/C table.
  r = ProbePlanTestRequest();
  r.machine_path = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/bc_table.yaml";
  auto bc = RunProbeArtifactsPlanStage(r);
  ASSERT_FALSE(bc.ok());
  EXPECT_EQ(bc.status().file(), r.machine_path) << bc.status().ToString();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
