#include "pipeline/fit_stage.h"

#include <gtest/gtest.h>

#include <vector>

namespace tpcal::pipeline {
namespace {

const std::string kSamples = std::string(TPCAL_SOURCE_DIR) + "/samples/";

TEST(FitStage, EvaluatesThePlanAndSummarisesIt) {
  FitRequest request;
  request.points_path = kSamples + "turning/cmm_points.csv";
  request.plan_path = kSamples + "plans/turning.yaml";
  std::vector<std::string> lines;
  request.info = [&](const std::string& line) { lines.push_back(line); };
  auto result = RunFitStage(request);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  bool concentricity = false;
  for (const auto& c : result->characteristics) concentricity |= c.name == "t1_concentricity_Ch_SR";
  EXPECT_TRUE(concentricity);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("tpcal fit: ", 0), 0u);
  const std::string text = FitSummary(*result);
  EXPECT_EQ(text.rfind("feature      kind           points     rms_um    form_um\n", 0), 0u) << text.substr(0, 120);
  EXPECT_NE(text.find("\nt1_concentricity_Ch_SR"), std::string::npos);
}

TEST(FitStage, BadRequestsAreNamed) {
  FitRequest request;
  request.points_path = kSamples + "turning/cmm_points.csv";
  request.types = {"S_R"};
  EXPECT_EQ(RunFitStage(request).status().message(), "--type expects FEATURE=KIND, got 'S_R'");
  request.types = {"S_R=blob"};
  EXPECT_NE(RunFitStage(request).status().message().find("unknown kind 'blob'"), std::string::npos);
  request.types.clear();
  request.machine_path = kSamples + "machines/ac_table.yaml";
  EXPECT_EQ(RunFitStage(request).status().message(), "--config and --machine need --testpiece");
  request.machine_path.clear();
  request.points_path = kSamples + "turning_raw/cmm_scan.csv";
  auto raw = RunFitStage(request);
  ASSERT_FALSE(raw.ok());
  EXPECT_EQ(raw.status().file(), request.points_path);
  EXPECT_NE(raw.status().message().find("--testpiece"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
