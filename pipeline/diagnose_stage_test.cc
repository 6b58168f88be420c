#include "pipeline/diagnose_stage.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace tpcal::pipeline {
namespace {

const std::string kCli = std::string(TPCAL_SOURCE_DIR) + "/tests/cli/";

TEST(DiagnoseStage, UnknownPieceNamesTheFlagAndTheConfigAlternative) {
  auto setup = LoadDiagnosisPiece({.testpiece = "nope"});
  ASSERT_FALSE(setup.ok());
  const std::string message = setup.status().ToString();
  EXPECT_EQ(message.rfind("--testpiece: unknown test piece 'nope'", 0), 0u) << message;
  EXPECT_NE(message.find(") (or --config FILE)"), std::string::npos) << message;
}

// The drift sample against the clean one (same plan and location errors): the gap is the
// withheld drift, and the inputs name the point reference.
TEST(DiagnoseStage, PointReferenceFindsTheWithheldDrift) {
  auto setup = LoadDiagnosisPiece({});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  std::vector<std::string> lines;
  DiagnoseRequest request{.points_path = kCli + "diagnose_drift_points.csv",
                          .reference_path = kCli + "diagnose_clean_points.csv"};
  request.info = [&](const std::string& line) { lines.push_back(line); };
  auto stage = RunDiagnoseStage(*setup, request);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  EXPECT_EQ(stage->diagnosis.verdict.family, "thermal_drift");
  EXPECT_EQ(stage->inputs.at("reference_kind"), "points");
  EXPECT_EQ(stage->inputs.at("testpiece"), "turning");
  EXPECT_EQ(stage->inputs.at("machine"), "nominal");
  EXPECT_EQ(stage->inputs.at("alpha"), "0.01");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("tpcal diagnose: ", 0), 0u) << lines[0];
}

TEST(DiagnoseStage, ReferenceOfNeitherKindIsRefusedBeforeDiagnosing) {
  auto setup = LoadDiagnosisPiece({});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  auto stage = RunDiagnoseStage(*setup, {.points_path = kCli + "diagnose_clean_points.csv", .reference_path = "ref.abc"});
  ASSERT_FALSE(stage.ok());
  EXPECT_EQ(stage.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(stage.status().ToString(),
            "--reference ref.abc: expected machine errors (.yaml, .yml) or a point file (.csv, .ply, .pcd, .xyz, .txt)");
}

TEST(DiagnoseStage, ValidationMarkdownStartsWithItsSettings) {
  auto setup = LoadDiagnosisPiece({});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  ValidationOptions options;
  options.trials = 1;
  options.magnitudes = {10};
  options.noise_um = {1.0};
  options.families = {"none"};
  auto md = RunValidationStage(*setup, options);
  ASSERT_TRUE(md.ok()) << md.status().ToString();
  EXPECT_EQ(md->rfind("Diagnosis validation: " + setup->piece.name +
                          " piece, seed 1, trials 1, magnitudes 10 (visible signature peak), noise 1 um\n\n",
                      0),
            0u)
      << md->substr(0, 200);
}

}  // namespace
}  // namespace tpcal::pipeline
