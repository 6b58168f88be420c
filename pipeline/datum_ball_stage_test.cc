// The datum-ball stage (pipeline/datum_ball_stage.h) and the ball-position reader
// (pipeline/io/ballpos_reader.h). Truth of the sample: seed 001 Table 1(a)'s assumed errors on the
// nominal B/C table (kinematics/datum_ball_test.cc maps its symbols), ball at (R, delta_YW, H) =
// (200, 0.1, 300) mm (Table 1(a) prints R 200, delta_YW 300, H 0.1: the last two read swapped)
// in the part frame, B = 0, +-30 deg and C every 30 deg, readings rounded to 0.1 um (the file's 4
// decimals): identified within 4 u of the truth (u from the rounding, about 0.03 um).
#include "pipeline/datum_ball_stage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/units.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/datum_ball_simulate_stage.h"
#include "pipeline/io/ballpos_reader.h"

namespace tpcal::pipeline {
namespace {

const std::map<std::string, double> kTruth = {
    {"E_A(0Y)Z", -34.0}, {"E_B(0X)Z", 29.0}, {"E_C(0X)Y", 17.0}, {"E_A0B", -17.0}, {"E_C0B", 75.0}, {"E_X0B", -12.0},
    {"E_Z0B", 19.0},     {"E_A0C", -87.0},   {"E_B0C", 42.0},    {"E_X0C", 10.0},  {"E_Y0C", -15.0}};

const std::string kSample = std::string(TPCAL_SOURCE_DIR) + "/samples/datum_ball/table1a_ballpos.csv";

// The sample's text: the virtual instrument (pipeline/datum_ball_simulate_stage.h) on the truth,
// noise-free, seed 001's default plan (B = 0, 30, -30 deg, C every 30 deg, ball (200, 0.1, 300)).
std::string SampleText() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  EXPECT_TRUE(m.ok());
  kinematics::ErrorState e(*m);
  for (const auto& [name, v] : kTruth) {
    auto info = kinematics::LookupParameter(*m, name);
    EXPECT_TRUE(info.ok());
    EXPECT_TRUE(e.SetParameter(*m, name, info->quantity == kinematics::Quantity::kAngle ? v * 1e-6 : UmToMm(v)).ok());
  }
  auto sim = SimulateDatumBall(*m, e, DatumBallSimRequest{});
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  return sim.ok() ? sim->csv : std::string();
}

// TPCAL_REGENERATE_SAMPLES=1 rewrites the sample from the model (then the test compares it again).
TEST(DatumBallStage, SampleIsWhatTheModelGivesForItsTruth) {
  if (const char* regenerate = std::getenv("TPCAL_REGENERATE_SAMPLES"); regenerate && std::string(regenerate) == "1")
    std::ofstream(kSample) << SampleText();
  std::ifstream in(kSample);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), SampleText());
}

TEST(DatumBallStage, SampleIdentifiesTable1aWithinItsUncertainty) {
  auto r = RunDatumBallStage({.path = kSample, .machine_path = "", .parameters = {}, .ball_part_mm = std::nullopt});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->machine, "bc_table");
  ASSERT_EQ(r->result.parameters.size(), kTruth.size());
  for (const auto& p : r->result.parameters) {
    EXPECT_TRUE(p.identifiable) << p.name;
    EXPECT_LT(std::abs(p.value - kTruth.at(p.name)), 4.0 * p.u + 1e-3) << p.name << " " << p.value << " +- " << p.u;
  }
  EXPECT_LT(r->result.sigma_um, 0.1);  // 0.1 um rounding: sigma 0.029 um
  EXPECT_EQ(r->lines.front(), 4u);
}

// The identified errors as tpcal.errors/1 read back (as simulate --errors and diagnose
// --reference read them) give the identified values and centre the ball where the readings say,
// within the readings' rounding (sigma 0.03 um: every residual below 0.2 um).
TEST(DatumBallStage, ErrorsYamlReadsBackToTheIdentifiedMachine) {
  auto r = RunDatumBallStage({.path = kSample, .machine_path = "", .parameters = {}, .ball_part_mm = std::nullopt});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  ASSERT_TRUE(m.ok());
  auto e = kinematics::ParseErrorState(r->errors_yaml, "identified.yaml", *m);
  ASSERT_TRUE(e.ok()) << e.status().ToString() << "\n" << r->errors_yaml;
  for (const auto& p : r->result.parameters) {
    auto v = e->Parameter(*m, p.name);
    ASSERT_TRUE(v.ok()) << p.name;
    auto info = kinematics::LookupParameter(*m, p.name);
    const double display = info->quantity == kinematics::Quantity::kAngle ? *v * 1e6 : MmToUm(*v);
    EXPECT_NEAR(display, p.value, 1e-9 * std::max(1.0, std::abs(p.value))) << p.name;
  }
  auto file = ReadBallPositions(kSample);
  ASSERT_TRUE(file.ok());
  for (const auto& row : file->rows) {
    kinematics::AxisState rotary;
    rotary.b_rad = DegToRad(row.rotary_deg.at('B')), rotary.c_rad = DegToRad(row.rotary_deg.at('C'));
    auto cmd = kinematics::BallCentreCommand(*m, *e, rotary, r->result.ball_part_mm);
    ASSERT_TRUE(cmd.ok());
    EXPECT_LT(MmToUm((*cmd - row.centre_mm).cwiseAbs().maxCoeff()), 0.2) << "line " << row.line;
  }
}

TEST(BallPositions, BadInputNamesFileLineAndWhatWasExpected) {
  struct Case { const char* text; const char* message; std::size_t line; };
  const Case cases[] = {
      {"x,y,z\n", "expected '# tpcal ballpos v1'", 1},
      {"# tpcal ballpos v1\n# units: inch\nB_deg,C_deg,x,y,z\n", "only mm", 2},
      {"# tpcal ballpos v1\nB_deg,C_deg,x,y\n", "header needs x, y, z", 2},
      {"# tpcal ballpos v1\nB_deg,C_deg,x,y,z,w\n", "unknown column 'w'", 2},
      {"# tpcal ballpos v1\nB_deg,C_deg,x,y,z\n0,0,1,2\n", "expected 5 fields, got 4", 3},
      {"# tpcal ballpos v1\nB_deg,C_deg,x,y,z\n0,0,1,nan,3\n", "field 4: expected a finite number", 3},
      {"# tpcal ballpos v1\nB_deg,C_deg,x,y,z\n", "no ball positions", 2},
      {"", "empty file", 1},  // found by the fuzzer (tests/fuzz/corpus/ballpos/empty.csv)
  };
  for (const auto& c : cases) {
    auto r = ParseBallPositions(c.text, "f.csv");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.status().message().find(c.message), std::string::npos) << r.status().ToString();
    EXPECT_EQ(r.status().line(), c.line) << r.status().ToString();
    EXPECT_EQ(r.status().file(), "f.csv");
  }
}

TEST(DatumBallStage, RotaryColumnsMustBeTheMachines) {
  const auto dir = std::filesystem::temp_directory_path() / "tpcal_ballpos_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / "a.csv").string();
  std::ofstream(path) << "# tpcal ballpos v1\nA_deg,C_deg,x,y,z\n0,0,1,2,3\n0,90,1,2,3\n30,0,1,2,3\n";
  auto r = RunDatumBallStage({.path = path,
                              .machine_path = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/bc_table.yaml",
                              .parameters = {},
                              .ball_part_mm = std::nullopt});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("A_deg: the machine (bc_table) has no such axis"), std::string::npos)
      << r.status().ToString();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
