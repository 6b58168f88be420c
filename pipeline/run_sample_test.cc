// The bundled samples are exactly what their stated truth generates (same seed, same bytes), and
// the pipeline recovers that truth within the uncertainty it reports.
#include "pipeline/run_sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "pipeline/io/atomic_file.h"
#include "pipeline/io/point_io.h"
#include "pipeline/raw_scan_labeling.h"
#include "pipeline/report/run_json.h"
#include "pipeline/run_output.h"
#include "pipeline/run_stage.h"

namespace tpcal::pipeline {
namespace {

const std::string kSampleDir = std::string(TPCAL_SOURCE_DIR) + "/samples/";

std::string ReadSampleText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A CMM export as labs hand it over: 5 decimals (10 nm in mm; normals to 1e-5).
std::string SampleCsv(const SampleTruth& truth, const SimulatedSample& s, const std::string& truth_name) {
  PointWriteOptions w;
  w.fixed_decimals = 5;
  auto csv = FormatPointCsv(SampleExportPoints(truth, s), w);
  EXPECT_TRUE(csv.ok()) << csv.status().ToString();
  const std::string what = truth.raw_scan ? "Simulated raw CMM scan, no feature labels" : "Simulated CMM export";
  return "# " + what + " (virtual machining + virtual CMM); stated truth: " + truth_name +
         " (tpcal.sample_truth/1)\n" + (csv.ok() ? *csv : std::string());
}

void CheckOrRegenerate(const std::string& truth_path, const std::string& csv_path) {
  auto truth = LoadSampleTruth(truth_path);
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  auto sample = SimulateSample(*truth);
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  const std::string csv = SampleCsv(*truth, *sample, "truth.yaml");
  if (std::getenv("TPCAL_REGENERATE_SAMPLES")) {
    ASSERT_TRUE(WriteFileAtomic(csv_path, csv).ok());
    GTEST_SKIP() << "regenerated " << csv_path;
  }
  EXPECT_TRUE(csv == ReadSampleText(csv_path))
      << csv_path << " is not what " << truth_path
      << " generates; regenerate with TPCAL_REGENERATE_SAMPLES=1 if the simulator changed on purpose";
}

TEST(RunSample, TurningSampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "turning/truth.yaml", kSampleDir + "turning/cmm_points.csv");
}

TEST(RunSample, M1SampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "m1/truth.yaml", kSampleDir + "m1/cmm_points.csv");
}

TEST(RunSample, M2SampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "m2/truth.yaml", kSampleDir + "m2/cmm_points.csv");
}

TEST(RunSample, ConeSampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "cone/truth.yaml", kSampleDir + "cone/cmm_points.csv");
}

TEST(RunSample, TurningRawSampleIsWhatItsTruthGenerates) {
  CheckOrRegenerate(kSampleDir + "turning_raw/truth.yaml", kSampleDir + "turning_raw/cmm_scan.csv");
}

// The bundled raw scan carries no labels; labelling it gives (nearly) every point the feature the
// simulator measured it on.
TEST(RunSample, TurningRawSampleIsLabelledAsSimulated) {
  auto truth = LoadSampleTruth(kSampleDir + "turning_raw/truth.yaml");
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  ASSERT_TRUE(truth->raw_scan);
  auto sample = SimulateSample(*truth);
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  auto file = ReadPoints(kSampleDir + "turning_raw/cmm_scan.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  ASSERT_FALSE(file->has_labels());
  const PointSet& sim = sample->simulated.points;
  ASSERT_EQ(file->size(), sim.size());
  auto r = LabelRawScan(sample->setup.piece, *file);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::size_t correct = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const int f = r->piece_feature[i];
    if (f != PointSet::kUnlabelled &&
        sample->setup.piece.features[static_cast<std::size_t>(f)].name ==
            sim.feature_names[static_cast<std::size_t>(sim.feature[i])])
      ++correct;
  }
  const double fraction = static_cast<double>(correct) / static_cast<double>(sim.size());
  RecordProperty("correct_fraction", std::to_string(fraction));
  RecordProperty("labelling", r->BriefReport());
  EXPECT_GE(fraction, 0.99) << r->BriefReport();
}

// End to end: `tpcal run samples/pipelines/turning_raw.yaml` labels the scan (stage "label") and
// recovers the stated truth within 4 standard uncertainties (as the labelled turning sample).
TEST(RunSample, TurningRawSampleRecoversTheStatedTruth) {
  constexpr double kSigmas = 4.0;
  auto c = LoadPipelineConfig(kSampleDir + "pipelines/turning_raw.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  c->monte_carlo_trials = 0;
  c->diagnose = false;  // not what this test is about (and the slowest stage on 16k points)
  auto r = RunPipeline(*c);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::vector<std::string> stages;
  for (const auto& t : r->timings) {
    stages.push_back(t.stage);
    RecordProperty(t.stage + "_s", std::to_string(t.seconds));
  }
  ASSERT_GE(stages.size(), 3u);
  EXPECT_EQ(stages[1], "read");
  EXPECT_EQ(stages[2], "label");
  const auto& id = r->stage.identification;
  int identifiable = 0;
  for (const auto& p : id.parameters) {
    if (!p.identifiable) continue;
    ++identifiable;
    ASSERT_TRUE(std::isfinite(p.value) && std::isfinite(p.u)) << p.name;
    EXPECT_LE(std::abs(p.value - r->truth.at(p.name)), kSigmas * p.u)
        << p.name << ": " << p.value << " +- " << p.u << " " << p.unit << ", truth " << r->truth.at(p.name);
    RecordProperty(p.name + "_error_in_u", std::to_string((p.value - r->truth.at(p.name)) / p.u));
  }
  EXPECT_GE(identifiable, 5);
  EXPECT_LT(id.rms_after_um, 0.7);  // the CMM noise (0.5 um): no mislabelled point left
  // result.json states the labelling: every point of the file counted, labelled + rejected.
  ASSERT_TRUE(r->raw_scan.has_value());
  const auto j = nlohmann::json::parse(RunReportJson(ReportOf(*r)));
  const auto& raw = j.at("input").at("raw_scan");
  EXPECT_EQ(j.at("input").at("num_points").get<std::size_t>(), r->raw_scan->num_points);
  EXPECT_EQ(raw.at("num_labelled").get<std::size_t>() + raw.at("num_rejected").get<std::size_t>(),
            raw.at("num_points").get<std::size_t>());
  std::size_t per_feature = 0;
  for (const auto& [name, count] : raw.at("points_per_feature").items()) per_feature += count.get<std::size_t>();
  EXPECT_EQ(per_feature, raw.at("num_labelled").get<std::size_t>());
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
