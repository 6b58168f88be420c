#include "pipeline/simulate_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace tpcal::pipeline {
namespace {

std::string WriteErrors(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("tpcal_simulate_stage_" + name);
  std::ofstream(p) << text;
  return p.string();
}

TEST(SimulateStage, ErrorsMoveTheMeasuredPointsAndTheTruthStatesThem) {
  auto loaded = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  SimulateRequest request;
  request.testpiece = "turning";
  request.points_path = "pts.csv";
  request.truth = true;
  std::vector<std::string> lines;
  request.info = [&](const std::string& line) { lines.push_back(line); };

  request.errors_path = WriteErrors("zero.yaml", "schema: tpcal.errors/1\nmachine: ac_table\n");
  auto zero = RunSimulateStage(*loaded, request);
  ASSERT_TRUE(zero.ok()) << zero.status().ToString();
  request.errors_path = WriteErrors("x.yaml", "schema: tpcal.errors/1\nmachine: ac_table\ndx_CR(0)_um: 20\n");
  auto moved = RunSimulateStage(*loaded, request);
  ASSERT_TRUE(moved.ok()) << moved.status().ToString();

  ASSERT_EQ(zero->simulated.points.size(), moved->simulated.points.size());
  double max_shift_mm = 0;
  for (std::size_t i = 0; i < zero->simulated.points.size(); ++i)
    max_shift_mm = std::max(max_shift_mm, (zero->simulated.points.xyz_mm[i] - moved->simulated.points.xyz_mm[i]).norm());
  EXPECT_GT(max_shift_mm, 0.005);  // a 20 um location error of C moves points by micrometres
  EXPECT_LT(max_shift_mm, 0.1);
  EXPECT_EQ(zero->csv.rfind("# tpcal points v1\n", 0), 0u) << zero->csv.substr(0, 80);
  EXPECT_NE(moved->truth_yaml.find("schema: tpcal.simulation_truth/1\n"), std::string::npos);
  EXPECT_NE(moved->truth_yaml.find("points_file: \"pts.csv\"\n"), std::string::npos);
  EXPECT_NE(moved->truth_yaml.find("dx_CR(0)_um: 20"), std::string::npos) << moved->truth_yaml;
  ASSERT_EQ(lines.size(), 4u);  // two progress lines per run
  EXPECT_EQ(lines[0].rfind("tpcal simulate: ", 0), 0u);
}

TEST(SimulateStage, BadInputIsNamed) {
  SimulateRequest request;
  request.noise_um = -1;
  EXPECT_EQ(request.Validate().message(), "--noise-um must be a finite number >= 0 (um)");
  request.noise_um = 0;
  request.max_translation_mm = NAN;
  EXPECT_FALSE(request.Validate().ok());
  request.max_translation_mm = 300;
  EXPECT_TRUE(request.Validate().ok());

  auto loaded = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(loaded.ok());
  request.errors_path = WriteErrors("bad.yaml", "schema: tpcal.errors/1\nmachine: ac_table\nE_X0Q_um: 1\n");
  auto bad = RunSimulateStage(*loaded, request);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().ToString().rfind(request.errors_path + ":3:", 0), 0u) << bad.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
