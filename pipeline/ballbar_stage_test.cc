// The identification stage of a double-ball-bar test (pipeline/ballbar_stage.h).
// Truth: error motions of seed 003's C turntable and B head (below) on the nominal bhead_ctable,
// seed003_setups.yaml's 13 rotary installations at 0, 20, ..., 340 deg (B: -120 .. 20), bar
// lengths through the exact chain (kinematics/ballbar.h), noise-free, written with 17 digits. The
// identification is linear to first order, so the truth's part the installations can see comes
// back to second order: (10 urad)^2 x 400 mm + 10 urad x 10 um ~ 1e-4 um, within 1e-3.
#include "pipeline/ballbar_stage.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/units.h"
#include "kinematics/ballbar.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/io/ballbar_io.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

const std::string kBbsSetup = std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml";

kinematics::MachineModel BbsMachine() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBheadCtable);
  EXPECT_TRUE(m.ok());
  return *m;
}

kinematics::ErrorState BbsTruth(const kinematics::MachineModel& m) {
  auto e = kinematics::ParseErrorState(
      "effects:\n"
      "  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 2, cos_um: 3.0, sin_um: -1.5}]}\n"
      "  - rotary_error_motion: {symbol: E_AC, harmonics: [{order: 3, cos_urad: 8.0, sin_urad: 2.0}]}\n"
      "  - rotary_error_motion: {symbol: E_ZB, positions_deg: [-120, 20], values_um: [6, -2], periodic: false}\n"
      "  - rotary_error_motion: {symbol: E_CB, positions_deg: [-120, 20], values_urad: [-9, 4], periodic: false}\n",
      "truth.yaml", m);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return *e;
}

// The ball-bar file of every rotary installation of the seed 003 set-up under `truth`.
std::string BbsWriteFile(const kinematics::MachineModel& m, const kinematics::ErrorState& truth, const fs::path& path) {
  auto setup = kinematics::LoadBallbarSetup(kBbsSetup);
  EXPECT_TRUE(setup.ok()) << setup.status().ToString();
  BallbarFile file;
  kinematics::Workspace ws;
  for (const auto& inst : setup->installations) {
    if (inst.kind == kinematics::BallbarKind::kCircle) continue;
    auto g = kinematics::MakeBallbarGeometry(m, inst);
    EXPECT_TRUE(g.ok()) << g.status().ToString();
    const bool b = inst.axis == kinematics::Axis::kB;
    for (double a = b ? -120.0 : 0.0; a <= (b ? 20.0 : 340.0); a += 20.0) {
      auto dl = kinematics::SimulateBallbarDlUm(m, truth, *g, a, 0.0, &ws);
      EXPECT_TRUE(dl.ok()) << dl.status().ToString();
      BallbarRow row;
      row.setup = inst.name;
      row.angle_deg = a;
      row.dl_um = *dl;
      file.rows.push_back(row);
    }
  }
  std::ofstream(path) << FormatBallbar(file);
  return path.string();
}

fs::path BbsDir() {
  const fs::path dir = fs::temp_directory_path() / "tpcal_ballbar_stage";
  fs::create_directories(dir);
  return dir;
}

// The value (um or urad) of the error motion `symbol` ("E_XC") of `errors` at the axis angle:
// the sum of its terms (TermValue, mm or rad) in display units.
double BbsMotionAt(const kinematics::ErrorState& errors, const std::string& symbol, kinematics::Axis axis,
                   double angle_deg) {
  kinematics::AxisState s;
  kinematics::SetPosition(&s, axis, DegToRad(angle_deg));
  double v = 0.0;
  for (const auto& t : errors.terms()) {
    if (t.label.substr(0, t.label.find('@')) != symbol) continue;
    v += kinematics::TermValue(t, s) * (t.quantity == kinematics::Quantity::kLength ? 1e3 : 1e6);
  }
  return v;
}

TEST(BallbarStage, BothAxesOfSeed003AreIdentifiedFromOneFile) {
  const auto m = BbsMachine();
  const auto truth = BbsTruth(m);
  const std::string path = BbsWriteFile(m, truth, BbsDir() / "both.csv");
  auto report = RunBallbarStage({.path = path, .setup_path = kBbsSetup, .machine_path = "", .map_response_to = {}});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(report->machine, "bhead_ctable");
  EXPECT_EQ(report->readings, 7 * 18 + 6 * 8);
  ASSERT_EQ(report->axes.size(), 2u);
  EXPECT_EQ(report->axes[0].axis, "C");
  EXPECT_EQ(report->axes[1].axis, "B");
  EXPECT_EQ(report->axes[0].installations.size(), 7u);
  EXPECT_EQ(report->axes[1].installations.size(), 6u);
  EXPECT_TRUE(report->circles.empty());
  for (const auto& a : report->axes) {
    const auto& r = a.result;
    const kinematics::Axis axis = a.axis == "C" ? kinematics::Axis::kC : kinematics::Axis::kB;
    EXPECT_EQ(a.lines.size(), static_cast<std::size_t>(r.rows));
    // The visible part of the truth: the truth minus its part along the not-separable basis.
    Eigen::VectorXd t(static_cast<Eigen::Index>(r.entries.size()));
    for (Eigen::Index e = 0; e < t.size(); ++e) {
      const auto& x = r.entries[static_cast<std::size_t>(e)];
      t(e) = BbsMotionAt(truth, x.symbol, axis, x.angle_deg);
    }
    const Eigen::MatrixXd& b = r.not_separable_basis;
    const Eigen::VectorXd visible = b.cols() > 0 ? Eigen::VectorXd(t - b * (b.transpose() * t)) : t;
    for (std::size_t e = 0; e < r.entries.size(); ++e) {
      if (!r.entries[e].identifiable) continue;
      EXPECT_NEAR(r.entries[e].value, visible(static_cast<Eigen::Index>(e)), 1e-3)
          << a.axis << " " << r.entries[e].coefficient;
    }
  }
}

TEST(BallbarStage, ErrorsOutReadsBackAsTheIdentifiedTables) {
  const auto m = BbsMachine();
  const std::string path = BbsWriteFile(m, BbsTruth(m), BbsDir() / "errors_out.csv");
  auto report = RunBallbarStage({.path = path, .setup_path = kBbsSetup, .machine_path = "", .map_response_to = {}});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto back = kinematics::ParseErrorState(report->errors_yaml, "errors.yaml", m);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_NE(report->errors_yaml.find("# C: the maps carry no component along the not-separable families"),
            std::string::npos);
  for (const auto& a : report->axes) {
    const kinematics::Axis axis = a.axis == "C" ? kinematics::Axis::kC : kinematics::Axis::kB;
    for (const auto& e : a.result.entries) {
      EXPECT_NEAR(BbsMotionAt(*back, e.symbol, axis, e.angle_deg), e.identifiable ? e.value : 0.0, 1e-9)
          << e.coefficient;
    }
  }
}

TEST(BallbarStage, UnknownInstallationIsNamedWithItsLine) {
  const fs::path path = BbsDir() / "unknown.csv";
  std::ofstream(path) << "# tpcal ballbar v1\n# units: mm\nsetup,angle_deg,dl_um\nC_radial_L1H1,0,0\nnope,20,1\n";
  auto report = RunBallbarStage({.path = path.string(), .setup_path = kBbsSetup, .machine_path = "", .map_response_to = {}});
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(report.status().line(), 5u);
  EXPECT_NE(report.status().ToString().find("unknown.csv:5"), std::string::npos) << report.status().ToString();
  EXPECT_NE(report.status().ToString().find("'nope'"), std::string::npos);
}

TEST(BallbarStage, SetupIsRequiredAndAMachineWithoutTheAxisIsAnError) {
  const auto m = BbsMachine();
  const std::string path = BbsWriteFile(m, BbsTruth(m), BbsDir() / "machine.csv");
  auto no_setup = RunBallbarStage({.path = path, .setup_path = "", .machine_path = "", .map_response_to = {}});
  ASSERT_FALSE(no_setup.ok());
  EXPECT_NE(no_setup.status().ToString().find("--setup"), std::string::npos);
  // The A/C table has no B axis: the B installations cannot be placed on it.
  const std::string ac = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml";
  if (!fs::exists(ac)) GTEST_SKIP() << "no ac_table sample machine";
  auto wrong = RunBallbarStage({.path = path, .setup_path = kBbsSetup, .machine_path = ac, .map_response_to = {}});
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().ToString().find("seed003_setups.yaml"), std::string::npos) << wrong.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
