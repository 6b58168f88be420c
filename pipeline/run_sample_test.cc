// The bundled samples are exactly what their stated truth generates (same seed, same bytes), and
// the pipeline recovers that truth within the uncertainty it reports.
#include "pipeline/run_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pipeline/atomic_file.h"
#include "pipeline/point_io.h"

namespace tpcal::pipeline {
namespace {

const std::string kSampleDir = std::string(TPCAL_SOURCE_DIR) + "/samples/";

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A CMM export as labs hand it over: 5 decimals (10 nm in mm; normals to 1e-5).
std::string SampleCsv(const SimulatedSample& s, const std::string& truth_name) {
  PointWriteOptions w;
  w.fixed_decimals = 5;
  auto csv = FormatPointCsv(s.simulated.points, w);
  EXPECT_TRUE(csv.ok()) << csv.status().ToString();
  return "# Simulated CMM export (virtual machining + virtual CMM); stated truth: " + truth_name +
         " (tpcal.sample_truth/1)\n" + (csv.ok() ? *csv : std::string());
}

void CheckOrRegenerate(const std::string& truth_path, const std::string& csv_path) {
  auto truth = LoadSampleTruth(truth_path);
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  auto sample = SimulateSample(*truth);
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  const std::string csv = SampleCsv(*sample, "truth.yaml");
  if (std::getenv("TPCAL_REGENERATE_SAMPLES")) {
    ASSERT_TRUE(WriteFileAtomic(csv_path, csv).ok());
    GTEST_SKIP() << "regenerated " << csv_path;
  }
  EXPECT_TRUE(csv == ReadText(csv_path))
      << csv_path << " is not what " << truth_path
      << " generates; regenerate with TPCAL_REGENERATE_SAMPLES=1 if the simulator changed on purpose";
}

TEST(RunSample, TurningSampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "turning/truth.yaml", kSampleDir + "turning/cmm_points.csv");
}

TEST(RunSample, M1SampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "m1/truth.yaml", kSampleDir + "m1/cmm_points.csv");
}

TEST(RunSample, TruthFileErrorsAreReported) {
  auto bad = LoadSampleTruth(kSampleDir + "turning/no_such_truth.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kIoError);
}

TEST(RunSample, TruthValuesInDisplayUnits) {
  auto truth = LoadSampleTruth(kSampleDir + "turning/truth.yaml");
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  auto values = LoadTruthValues(kSampleDir + "turning/truth.yaml", {"dx_CR(0)", "alpha_ZY", "dz_AR(-90)"});
  ASSERT_TRUE(values.ok()) << values.status().ToString();
  // Exactly the numbers of truth.yaml (um and urad), round trip through mm / rad.
  EXPECT_NEAR(values->at("dx_CR(0)"), 12.4, 1e-9);
  EXPECT_NEAR(values->at("alpha_ZY"), 19.2, 1e-9);
  EXPECT_NEAR(values->at("dz_AR(-90)"), 28.6, 1e-9);
}

}  // namespace
}  // namespace tpcal::pipeline
