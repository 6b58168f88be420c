#include "pipeline/report/identify_summary.h"

#include <gtest/gtest.h>

#include "pipeline/identify_report.h"
#include "pipeline/piece_loader.h"
#include "pipeline/raw_scan_labeling.h"

namespace tpcal::pipeline {
namespace {

TEST(IdentifyOptionsFor, EachUncertaintyChoice) {
  using kinematics::UncertaintyMethod;
  const auto analytic = IdentifyOptionsFor("analytic", 500, 0, 4);
  EXPECT_EQ(analytic.primary, UncertaintyMethod::kAnalytic);
  EXPECT_FALSE(analytic.jackknife_groups);
  EXPECT_EQ(analytic.monte_carlo_trials, 0);
  EXPECT_EQ(analytic.seed, 4u);
  const auto mc = IdentifyOptionsFor("mc", 500, 0, 1);
  EXPECT_EQ(mc.primary, UncertaintyMethod::kMonteCarlo);
  EXPECT_EQ(mc.monte_carlo_trials, 500);
  EXPECT_FALSE(mc.jackknife_groups);
  const auto jackknife = IdentifyOptionsFor("jackknife", 500, 7, 1);
  EXPECT_EQ(jackknife.primary, UncertaintyMethod::kJackknifePoints);
  EXPECT_TRUE(jackknife.jackknife_groups);
  EXPECT_EQ(jackknife.monte_carlo_trials, 0);
  EXPECT_EQ(jackknife.random_subset_trials, 7);
  const auto all = IdentifyOptionsFor("all", 500, 0, 1);
  EXPECT_EQ(all.primary, UncertaintyMethod::kJackknifePoints);
  EXPECT_TRUE(all.jackknife_groups);
  EXPECT_EQ(all.monte_carlo_trials, 500);
}

TEST(IdentificationSummary, TurningSampleTable) {
  auto loaded = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  auto points = ReadLabelledPoints(std::string(TPCAL_SOURCE_DIR) + "/samples/turning/cmm_points.csv", loaded->piece);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_FALSE(points->raw_scan.has_value());
  IdentifyStageOptions options;
  options.identify = IdentifyOptionsFor("analytic", 0, 0, 1);
  auto report = BuildIdentificationReport(loaded->piece, loaded->machine, points->points, options);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const std::string text = IdentificationSummary(*report);
  EXPECT_NE(text.find(" points in "), std::string::npos) << text;
  EXPECT_NE(text.find("\nparameter           value unit    u_anal  u_jk_pt  u_jk_ft       95 % interval  ISO 230-1\n"),
            std::string::npos) << text;
  EXPECT_NE(text.find("\ndx_CR(0) "), std::string::npos) << text;
  EXPECT_NE(text.find("\nidentifiability: rank "), std::string::npos) << text;
  EXPECT_NE(text.find("C error motion "), std::string::npos) << text;  // turning piece: the C error motions
}

}  // namespace
}  // namespace tpcal::pipeline
