#include "pipeline/diagnose_stage.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/io/point_io.h"
#include "pipeline/testing/turning_fixture.h"
#include "testpieces/simulate_piece.h"

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

// A scan of the turning piece with random Table 2 errors (RandomTable2 drawn from `truth_seed`),
// 1 um noise (`noise_seed`), random placement: `per_circle` hits per circle and half as many per
// hole, at 4 levels each.
Result<testpieces::SimulatedPiece> ScanOfTurning(const LoadedPiece& setup, int truth_seed, int noise_seed, int per_circle) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(truth_seed));
  testpieces::PieceSimOptions sim;
  sim.noise_um = 1.0;
  sim.seed = static_cast<std::uint64_t>(noise_seed);
  sim.random_placement = true;
  testpieces::ProbingOptions density;
  density.points_per_circle = per_circle;
  density.levels_per_face = 4;
  density.points_per_hole = per_circle / 2;
  density.levels_per_hole = 4;
  sim.density = density;
  return testpieces::SimulatePiece(setup.piece, setup.machine,
                                   test_support::ToErrorState(test_support::RandomTable2(rng)), sim);
}

// A dense scan of the turning piece (2880 hits per circle x 4 levels, 1440 per hole x 4: 253 440
// hits, above the 250 000 of ScanCellOptions), random Table 2 errors of 10-50 um / urad (seed 7),
// 1 um noise, random placement. Truth: nothing beyond noise. The stage re-aligns and pools it as
// `tpcal run` does: none, one hit's sigma 1 um within 3 %, the cells named in the inputs and a
// progress line. The same points diagnosed in the GD&T frame, point by point (Diagnose), read
// probe_radius: the linear re-alignment misses t^2 / 2R on the shifted holes (README).
TEST(DiagnoseStage, DenseScanIsReAlignedAndPooled) {
  auto setup = LoadDiagnosisPiece({});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  auto points = ScanOfTurning(*setup, 7, 9, 2880);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  ASSERT_GT(points->points.size(), 250000u);
  const std::string path = (std::filesystem::path(testing::TempDir()) / "tpcal_dense_diagnose.csv").string();
  ASSERT_TRUE(WritePointCsv(path, points->points).ok());
  std::vector<std::string> lines;
  DiagnoseRequest request{.points_path = path};
  request.info = [&](const std::string& line) { lines.push_back(line); };
  auto stage = RunDiagnoseStage(*setup, request);
  std::filesystem::remove(path);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  EXPECT_EQ(stage->diagnosis.verdict.family, "none") << stage->diagnosis.verdict.name;
  EXPECT_NEAR(stage->diagnosis.noise_sigma_um, 1.0, 0.03);
  ASSERT_TRUE(stage->inputs.contains("scan_cells"));
  EXPECT_EQ(stage->inputs.at("scan_cells").rfind("253440 points in ", 0), 0u) << stage->inputs.at("scan_cells");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1].rfind("dense scan: 253440 points in ", 0), 0u) << lines[1];
  auto in_gdt_frame = Diagnose(setup->piece, setup->machine, points->points);
  ASSERT_TRUE(in_gdt_frame.ok()) << in_gdt_frame.status().ToString();
  EXPECT_EQ(in_gdt_frame->verdict.family, "probe_radius") << in_gdt_frame->verdict.name;
}

// A scan of 7 920 hits (90 per circle x 4 levels, 45 per hole x 4) of clean turning pieces, random
// Table 2 errors of 10-50 um / urad, 1 um noise, random placement: the three of eight seeds that
// Diagnose (the GD&T frame's linear re-alignment) reads as probe_radius or harmonic 2 on the holes
// (seeds 1, 5, 6). Truth: nothing beyond noise. Above 3 000 points the stage identifies, re-aligns
// and re-associates first, as `tpcal run` does: none for each, not pooled (measured: 0 of 8).
TEST(DiagnoseStage, AFileAboveThreeThousandPointsIsReAligned) {
  auto setup = LoadDiagnosisPiece({});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  int false_in_gdt_frame = 0;
  for (int seed : {1, 5, 6}) {
    auto points = ScanOfTurning(*setup, 100 + seed, 200 + seed, 90);
    ASSERT_TRUE(points.ok()) << points.status().ToString();
    ASSERT_EQ(points->points.size(), 7920u);
    const std::string path = (std::filesystem::path(testing::TempDir()) / "tpcal_7920_diagnose.csv").string();
    ASSERT_TRUE(WritePointCsv(path, points->points).ok());
    auto stage = RunDiagnoseStage(*setup, {.points_path = path});
    std::filesystem::remove(path);
    ASSERT_TRUE(stage.ok()) << stage.status().ToString();
    EXPECT_EQ(stage->diagnosis.verdict.family, "none") << seed << ": " << stage->diagnosis.verdict.name;
    EXPECT_FALSE(stage->inputs.contains("scan_cells"));
    auto in_gdt_frame = Diagnose(setup->piece, setup->machine, points->points);
    ASSERT_TRUE(in_gdt_frame.ok()) << in_gdt_frame.status().ToString();
    false_in_gdt_frame += in_gdt_frame->verdict.family != "none";
  }
  EXPECT_GE(false_in_gdt_frame, 2);  // what the re-association corrects
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
