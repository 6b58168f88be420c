#include "pipeline/identify_report.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pipeline/piece_loader.h"

namespace tpcal::pipeline {
namespace {

const std::string kTurningPoints = std::string(TPCAL_SOURCE_DIR) + "/samples/turning/cmm_points.csv";

// The file-level entry gives what the piece-level builder gives on the same points, and says
// what it is identifying.
TEST(IdentifyPointFile, TurningSampleAsBuildIdentificationReport) {
  std::vector<std::string> lines;
  IdentifyRequest request{.points_path = kTurningPoints, .uncertainty = "analytic"};
  request.info = [&](const std::string& line) { lines.push_back(line); };
  auto report = IdentifyPointFile(request);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto loaded = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  auto points = ReadLabelledPoints(kTurningPoints, loaded->piece);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  IdentifyStageOptions options;
  options.identify = IdentifyOptionsFor("analytic", 2000, 0, 1);
  auto direct = BuildIdentificationReport(loaded->piece, loaded->machine, points->points, options);
  ASSERT_TRUE(direct.ok()) << direct.status().ToString();

  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "tpcal identify: 352 points of the " + loaded->piece.name + " from " + kTurningPoints);
  EXPECT_EQ(report->testpiece, loaded->piece.name);
  EXPECT_EQ(report->points_source, kTurningPoints);
  EXPECT_TRUE(report->closed_form.has_value());
  ASSERT_EQ(report->identification.parameters.size(), direct->identification.parameters.size());
  for (std::size_t i = 0; i < direct->identification.parameters.size(); ++i) {
    EXPECT_EQ(report->identification.parameters[i].name, direct->identification.parameters[i].name);
    EXPECT_EQ(report->identification.parameters[i].value, direct->identification.parameters[i].value);
  }
}

TEST(IdentifyPointFile, UnknownPieceBeforeThePointFile) {
  auto report = IdentifyPointFile({.points_path = "/nonexistent.csv", .testpiece = "nope"});
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().ToString().rfind("unknown test piece 'nope' (expected one of: turning,", 0), 0u)
      << report.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
