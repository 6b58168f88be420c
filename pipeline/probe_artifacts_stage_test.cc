// The identification stage of a probing test of artifacts (pipeline/probe_artifacts_stage.h).
// Truth: location errors and error motions of the A/C table (below), seed 000's default plan
// (testpieces/probe_artifacts_plan.h: A 0, -30, -60, -90 deg, C every 60 deg, the touches the
// probe reaches) through the virtual touch (kinematics/probe_touch.h), noise-free and written
// with 17 digits. The maps it writes as tpcal.errors/1, read back and put through the chain,
// give the identified poses again: the maps are exact at their nodes, the separation is linear, so
// they agree to second order, (50 urad)^2 x 300 mm + 50 urad x 20 um = 2e-3 um.
#include "pipeline/probe_artifacts_stage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/probe_touch.h"
#include "kinematics/table_poses.h"
#include "pipeline/io/probepts_io.h"
#include "testpieces/probe_artifacts_plan.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

kinematics::MachineModel PaStageMachine() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

kinematics::ErrorState PaStageTruth(const kinematics::MachineModel& m) {
  auto e = kinematics::ParseErrorState(
      "E_X0C_um: 10\nE_B0A_urad: -20\nE_Y0A_um: 6\n"
      "effects:\n"
      "  - rotary_error_motion: {symbol: E_AA, positions_deg: [-90, 0], values_urad: [35, 0], periodic: false}\n"
      "  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 2, cos_um: 1.5, sin_um: -0.8}]}\n",
      "truth.yaml", m);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return *e;
}

// The plan's touches simulated under `truth` with `touch`'s stylus, as a probed-point file.
std::string PaStageFile(const kinematics::MachineModel& m, const kinematics::ErrorState& truth,
                        const kinematics::TouchOptions& touch = {}) {
  auto plan = testpieces::MakeProbeArtifactsPlan(m, kinematics::Seed000Artifacts());
  EXPECT_TRUE(plan.ok());
  ProbePointFile file;
  file.rotary_axes = {'A', 'C'};
  for (const testpieces::PlannedTouch& t : plan->touches) {
    const kinematics::FaceGeometry g = kinematics::FaceOf(plan->artifacts.boxes[t.artifact], t.face);
    auto c = kinematics::SimulateTouch(m, truth, t.rotary, g, t.target_part_mm, touch);
    EXPECT_TRUE(c.ok());
    ProbePointRow row;
    row.rotary_deg = {{'A', RadToDeg(t.rotary.a_rad)}, {'C', RadToDeg(t.rotary.c_rad)}};
    row.artifact = plan->artifacts.boxes[t.artifact].name;
    row.face = kinematics::BoxFaceName(t.face);
    row.point_mm = *c;
    row.approach = t.approach;
    file.rows.push_back(row);
  }
  return FormatProbePoints(file);
}

ProbeArtifactsRequest PaStageRequest(const std::string& path, const std::string& machine_path = "") {
  ProbeArtifactsRequest r;
  r.path = path;
  r.machine_path = machine_path;
  return r;
}

std::string PaStageWrite(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "tpcal_probe_artifacts_stage";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

TEST(ProbeArtifactsStage, TheWrittenMapsReproduceTheIdentifiedPoses) {
  const kinematics::MachineModel m = PaStageMachine();
  const kinematics::ErrorState truth = PaStageTruth(m);
  auto report = RunProbeArtifactsStage(PaStageRequest(PaStageWrite("sim.csv", PaStageFile(m, truth))));
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->result.poses.poses.size(), 24u);
  EXPECT_TRUE(report->result.maps.not_identifiable.empty());
  for (const kinematics::TablePose& p : report->result.poses.poses) {
    kinematics::AxisState s, ref;
    s.a_rad = DegToRad(p.a_deg);
    s.c_rad = DegToRad(p.c_deg);
    const kinematics::Vector6d exact = kinematics::TablePoseError(m, truth, s, ref);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(p.value(c), exact(c), 5e-3) << p.a_deg << " " << p.c_deg << " " << c;
  }
  auto maps = kinematics::ParseErrorState(report->errors_yaml, "maps.yaml", m);
  ASSERT_TRUE(maps.ok()) << maps.status().ToString();
  for (const kinematics::TablePose& p : report->result.poses.poses) {
    kinematics::AxisState s;
    s.a_rad = DegToRad(p.a_deg);
    s.c_rad = DegToRad(p.c_deg);
    const kinematics::Vector6d again = kinematics::AbsoluteTablePoseError(m, *maps, s);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(again(c), p.value(c), 2e-3) << p.a_deg << " " << p.c_deg << " " << c;
  }
  EXPECT_NE(report->errors_yaml.find("zero-mean"), std::string::npos);
}

// The stylus radius places the squareness's columns (a touch's linear command is its contact
// minus radius x approach). Truth: location errors of the table above plus squareness of 150, -120 and 100 urad,
// touched noise-free with a 10 mm stylus. Taken as 10 mm the squareness comes back to 0.05 urad
// (second order: (150 urad)^2 x 300 mm = 7e-3 um over lever arms of 100 mm or more); taken as
// the default 3 mm, the 7 mm error moves every command by 7 mm along its approach (a shear of
// 150 urad there is 1 um), and the fit leaves it in the squareness: 1.75 urad on E_C(0X)Y
// (measured; bound 0.5 urad on the worst of the three).
TEST(ProbeArtifactsStage, TheStylusRadiusPlacesTheSquarenessColumns) {
  const kinematics::MachineModel m = PaStageMachine();
  auto sq = kinematics::ParseErrorState(
      "E_X0C_um: 10\nE_B0A_urad: -20\nE_Y0A_um: 6\nE_C(0X)Y_urad: 150\nE_B(0X)Z_urad: -120\nE_A(0Y)Z_urad: 100\n",
      "truth.yaml", m);
  ASSERT_TRUE(sq.ok()) << sq.status().ToString();
  const std::map<std::string, double> expected = {{"E_C(0X)Y", 150.0}, {"E_B(0X)Z", -120.0}, {"E_A(0Y)Z", 100.0}};
  kinematics::TouchOptions stylus;
  stylus.probe_radius_mm = 10.0;
  const std::string path = PaStageWrite("stylus10.csv", PaStageFile(m, *sq, stylus));
  ProbeArtifactsRequest right = PaStageRequest(path), wrong = PaStageRequest(path);
  right.probe_radius_mm = 10.0;
  auto good = RunProbeArtifactsStage(right), bad = RunProbeArtifactsStage(wrong);
  ASSERT_TRUE(good.ok()) << good.status().ToString();
  ASSERT_TRUE(bad.ok()) << bad.status().ToString();
  double worst_wrong = 0.0;
  for (std::size_t k = 0; k < good->result.poses.linear_errors.size(); ++k) {
    const auto& e = good->result.poses.linear_errors[k];
    ASSERT_TRUE(e.identifiable) << e.name;
    EXPECT_NEAR(e.value, expected.at(e.name), 0.05) << e.name;
    worst_wrong = std::max(worst_wrong, std::abs(bad->result.poses.linear_errors[k].value - expected.at(e.name)));
  }
  EXPECT_GT(worst_wrong, 0.5);
  EXPECT_NE(ProbeArtifactsText(*good).find("stylus radius 10 mm"), std::string::npos);
  right.probe_radius_mm = 0.0;
  auto refused = RunProbeArtifactsStage(right);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("stylus radius 0 mm"), std::string::npos) << refused.status().ToString();
}

TEST(ProbeArtifactsStage, UnknownArtifactOrFaceNamesItsLine) {
  const kinematics::MachineModel m = PaStageMachine();
  std::string text = PaStageFile(m, kinematics::ErrorState(m));
  const std::size_t third = text.find('\n', text.find('\n', text.find('\n') + 1) + 1) + 1;  // the first row
  std::string bad_face = text;
  bad_face.replace(bad_face.find(",+X,", third), 4, ",+W,");
  auto r = RunProbeArtifactsStage(PaStageRequest(PaStageWrite("bad_face.csv", bad_face)));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_GT(r.status().line(), 3u);
  EXPECT_NE(r.status().message().find("+W"), std::string::npos);
  std::string bad_box = text;
  bad_box.replace(bad_box.find(",1,", third), 3, ",9,");
  r = RunProbeArtifactsStage(PaStageRequest(PaStageWrite("bad_box.csv", bad_box)));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("'9'"), std::string::npos);
  EXPECT_GT(r.status().line(), 3u);
}

TEST(ProbeArtifactsStage, AMachineOtherThanAnACTableIsRefused) {
  const kinematics::MachineModel m = PaStageMachine();
  const std::string path = PaStageWrite("ok.csv", PaStageFile(m, kinematics::ErrorState(m)));
  auto r = RunProbeArtifactsStage(PaStageRequest(path, std::string(TPCAL_SOURCE_DIR) + "/samples/machines/bc_table.yaml"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("A/C table"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
