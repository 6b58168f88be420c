// End to end on the bundled turning sample: the identified errors match the stated truth within
// their uncertainty, the outputs are complete and deterministic, and the JSON follows its schema.
#include "pipeline/run_stage.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pipeline/report/report_html.h"
#include "pipeline/report/run_json.h"
#include "pipeline/run_output.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;
const std::string kPipeline = std::string(TPCAL_SOURCE_DIR) + "/samples/pipelines/turning.yaml";

PipelineConfig SampleConfig(int mc_trials = 500) {
  auto c = LoadPipelineConfig(kPipeline);
  EXPECT_TRUE(c.ok()) << c.status().ToString();
  PipelineConfig config = c.ok() ? *c : PipelineConfig{};
  config.monte_carlo_trials = mc_trials;
  return config;
}

const RunResult& SampleRun() {
  static const RunResult* run = [] {
    auto r = RunPipeline(SampleConfig());
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    return r.ok() ? new RunResult(std::move(*r)) : nullptr;
  }();
  if (!run) throw std::runtime_error("sample run failed");
  return *run;
}

std::string ReadRunText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The truth is recovered within kSigmas standard uncertainties (k = 1, primary method). With 16
// points per face and 0.5 um noise the u are ~0.2-2 um (urad); 4 u leaves a false-alarm rate
// below 1e-3 over the 11 parameters for an unbiased estimator, and fails on any real bias of the
// order of the errors themselves (10-40 um).
constexpr double kSigmas = 4.0;

TEST(RunStage, TurningSampleRecoversTheStatedTruth) {
  const RunResult& r = SampleRun();
  const auto& id = r.stage.identification;
  ASSERT_FALSE(id.parameters.empty());
  ASSERT_EQ(r.truth.size(), id.parameters.size());
  int identifiable = 0;
  for (const auto& p : id.parameters) {
    if (!p.identifiable) continue;
    ++identifiable;
    const double truth = r.truth.at(p.name);
    ASSERT_TRUE(std::isfinite(p.value) && std::isfinite(p.u)) << p.name;
    EXPECT_GT(p.u, 0.0) << p.name;
    EXPECT_LE(std::abs(p.value - truth), kSigmas * p.u)
        << p.name << ": " << p.value << " +- " << p.u << " " << p.unit << ", truth " << truth;
  }
  EXPECT_GE(identifiable, 1);
  // Every non-identifiable parameter is reported as such, with the combinations named.
  EXPECT_EQ(static_cast<int>(id.identifiability.not_identifiable.size()),
            static_cast<int>(id.parameters.size()) - identifiable);
  if (identifiable < static_cast<int>(id.parameters.size())) {
    EXPECT_FALSE(id.identifiability.estimable.empty() && id.identifiability.null_directions.empty());
  }
  // The residual after identification is the CMM noise (0.5 um) within the sampling spread.
  EXPECT_LT(id.rms_after_um, 0.7);
  EXPECT_GT(id.rms_after_um, 0.3);
}

TEST(RunStage, M1SampleRecoversTheStatedSquareness) {
  auto c = LoadPipelineConfig(std::string(TPCAL_SOURCE_DIR) + "/samples/pipelines/m1.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  c->monte_carlo_trials = 0;
  auto r = RunPipeline(*c);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->stage.identification.parameters.size(), 3u);  // the three ISO 230-1 squareness errors
  for (const auto& p : r->stage.identification.parameters) {
    ASSERT_TRUE(p.identifiable) << p.name;
    EXPECT_LE(std::abs(p.value - r->truth.at(p.name)), kSigmas * p.u)
        << p.name << ": " << p.value << " +- " << p.u << " " << p.unit << ", truth " << r->truth.at(p.name);
  }
  ASSERT_TRUE(r->diagnosis.has_value()) << r->diagnosis_status.ToString();
  EXPECT_EQ(r->diagnosis->verdict.family, "none");
}

// M2 (face milling, two passes) on a 3-axis machine whose X is not straight in Z: the default M2
// set (E_ZX.c2, E_ZX.c3) is identified and matches the stated truth within 4 u; the truth's E_ZX
// offset and slope and its E_ZY are what the strips' datum absorbs.
TEST(RunStage, M2SampleRecoversTheStatedStraightness) {
  auto c = LoadPipelineConfig(std::string(TPCAL_SOURCE_DIR) + "/samples/pipelines/m2.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  c->monte_carlo_trials = 0;
  auto r = RunPipeline(*c);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const auto& id = r->stage.identification;
  ASSERT_EQ(id.parameters.size(), 2u);
  for (const auto& p : id.parameters) {
    ASSERT_TRUE(p.identifiable) << p.name;
    EXPECT_GT(p.u, 0.0) << p.name;
    EXPECT_LE(std::abs(p.value - r->truth.at(p.name)), kSigmas * p.u)
        << p.name << ": " << p.value << " +- " << p.u << " " << p.unit << ", truth " << r->truth.at(p.name);
  }
  EXPECT_EQ(id.parameters[0].unit, "um_per_mm_pow2");
  EXPECT_LT(id.rms_after_um, 0.7);  // the CMM noise (0.5 um)
}

// The cone frustum's default plan separates none of the A/C table's twelve ISO location and
// squareness errors: each is reported without a value, and the six combinations the data do
// determine match the stated truth within 4 of their standard uncertainties (truth evaluated with
// the reported coefficients; errors the truth file leaves out are zero).
TEST(RunStage, ConeSampleReportsEstimableCombinationsThatMatchTheTruth) {
  auto c = LoadPipelineConfig(std::string(TPCAL_SOURCE_DIR) + "/samples/pipelines/cone.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  c->monte_carlo_trials = 0;
  auto r = RunPipeline(*c);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const auto& id = r->stage.identification;
  ASSERT_EQ(id.parameters.size(), 12u);
  for (const auto& p : id.parameters) EXPECT_FALSE(p.identifiable) << p.name << " = " << p.value;
  EXPECT_EQ(id.identifiability.not_identifiable.size(), 12u);
  ASSERT_EQ(id.identifiability.estimable.size(), 6u);
  for (const auto& comb : id.identifiability.estimable) {
    double truth = 0.0;
    for (std::size_t k = 0; k < comb.names.size(); ++k) {
      const auto it = r->truth.find(comb.names[k]);
      truth += comb.coefficients[k] * (it == r->truth.end() ? 0.0 : it->second);
    }
    ASSERT_TRUE(std::isfinite(comb.u) && comb.u > 0.0) << comb.text;
    EXPECT_LE(std::abs(comb.value - truth), kSigmas * comb.u)
        << comb.text << " = " << comb.value << " +- " << comb.u << ", truth " << truth;
  }
  EXPECT_LT(id.rms_after_um, 0.7);  // the CMM noise (0.5 um): the combinations explain the piece
  // The diagnosis's base model: E_Z0A has no signature on the flank-milled cone (Z slides the tool
  // along its own axis; its column is rounding, ~1e-15 of the others). It must come out not
  // identifiable, not fitted as a direction (it was -3.3e13 um +- 5.9e14 um).
  ASSERT_TRUE(r->diagnosis.has_value()) << r->diagnosis_status.ToString();
  bool seen = false;
  for (const auto& p : r->diagnosis->base_parameters) {
    if (p.name != "E_Z0A") continue;
    seen = true;
    EXPECT_FALSE(p.identifiable) << p.value;
  }
  EXPECT_TRUE(seen);
  for (const auto& p : r->diagnosis->base_parameters) {
    if (p.identifiable) {
      EXPECT_LT(std::abs(p.value), 1e5) << p.name;  // um / urad: no rounding direction fitted
    }
  }
}

// The sample's truth holds only errors of the identified set: the diagnosis must find nothing
// beyond noise (a false alarm here would be a wrong verdict on a clean piece).
TEST(RunStage, CleanSampleDiagnosisFindsNothingBeyondNoise) {
  const RunResult& r = SampleRun();
  ASSERT_TRUE(r.diagnosis.has_value()) << r.diagnosis_status.ToString();
  EXPECT_EQ(r.diagnosis->verdict.family, "none") << r.diagnosis->verdict.name;
  EXPECT_NEAR(r.diagnosis->rms_um, r.stage.identification.rms_after_um, 0.05);
}

TEST(RunStage, StagesAreTimedInOrder) {
  const RunResult& r = SampleRun();
  std::vector<std::string> stages;
  for (const auto& t : r.timings) {
    stages.push_back(t.stage);
    EXPECT_GE(t.seconds, 0.0);
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"setup", "read", "gdt", "associate", "identify", "diagnose", "figures"}));
}

TEST(RunStage, JsonFollowsTheSchemaAndIsDeterministic) {
  const RunResult& r = SampleRun();
  const std::string json = RunReportJson(ReportOf(r));
  const auto j = nlohmann::json::parse(json);
  EXPECT_EQ(j.at("schema"), "tpcal.run/1");
  EXPECT_TRUE(j.at("tpcal").at("version").is_string());
  EXPECT_TRUE(j.at("tpcal").at("git_revision").is_string());
  EXPECT_EQ(j.at("seed"), 1);
  EXPECT_EQ(j.at("config").at("seed"), 1);
  EXPECT_EQ(j.at("config").at("uncertainty").at("monte_carlo_trials"), 500);
  EXPECT_EQ(j.at("input").at("num_points"), r.num_points);
  EXPECT_EQ(j.at("input").at("digest_xxh64").get<std::string>().size(), 16u);
  EXPECT_EQ(j.at("inspection").at("schema"), "tpcal.fit/1");
  EXPECT_EQ(j.at("diagnosis").at("schema"), "tpcal.diagnosis/1");
  for (const char* key : {"base_model", "gap", "candidates", "verdict"})
    EXPECT_TRUE(j.at("diagnosis").contains(key)) << key;
  const auto& params = j.at("identification").at("parameters");
  ASSERT_EQ(params.size(), r.stage.identification.parameters.size());
  for (const auto& p : params) {
    for (const char* key : {"name", "iso_symbol", "unit", "identifiable", "value", "u", "ci95", "uncertainty",
                            "primary_method"})
      EXPECT_TRUE(p.contains(key)) << key;
    if (p.at("identifiable").get<bool>()) {
      EXPECT_TRUE(p.at("value").is_number());
      EXPECT_EQ(p.at("ci95").size(), 2u);
      for (const char* m : {"analytic", "jackknife_points", "jackknife_groups", "monte_carlo"})
        EXPECT_TRUE(p.at("uncertainty").contains(m)) << m;
    } else {
      EXPECT_TRUE(p.at("value").is_null());
    }
    EXPECT_TRUE(p.at("truth").is_number());
  }
  for (const char* key : {"num_parameters", "rank", "condition_number", "singular_values", "not_identifiable",
                          "estimable", "null_directions"})
    EXPECT_TRUE(j.at("identification").at("identifiability").contains(key)) << key;
  // The blocks of tpcal.identification/1 under the same keys (identification_blocks.h).
  for (const auto& c : j.at("identification").at("identifiability").at("estimable")) {
    for (const char* key : {"combination", "names", "coefficients", "value", "u", "unit"})
      EXPECT_TRUE(c.contains(key)) << key;
  }
  for (const char* key : {"rms_before_um", "rms_after_um", "sigma_um", "iterations", "termination"})
    EXPECT_TRUE(j.at("identification").at("fit").contains(key)) << key;
  for (const char* key : {"n_points", "n_features", "alignment"})
    EXPECT_TRUE(j.at("identification").contains(key)) << key;

  // Same inputs and seed: the same bytes (a fresh run, not the cached one).
  auto again = RunPipeline(SampleConfig());
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_TRUE(RunReportJson(ReportOf(*again)) == json);
  // A different seed changes only what depends on it (the Monte Carlo figures and the seed fields).
  PipelineConfig other = SampleConfig();
  other.seed = 7;
  auto seeded = RunPipeline(other);
  ASSERT_TRUE(seeded.ok());
  EXPECT_FALSE(RunReportJson(ReportOf(*seeded)) == json);
}

TEST(RunStage, ReportHasEverySectionAndFigure) {
  const RunResult& r = SampleRun();
  const std::string html = RenderReportHtml(ReportOf(r));
  for (const char* id : {"id=\"summary\"", "id=\"identification\"", "id=\"identification-table\"",
                         "id=\"identifiability\"", "id=\"identifiability-table\"", "id=\"gdt\"", "id=\"gdt-table\"",
                         "id=\"features-table\"", "id=\"config\"", "id=\"fig-machine_errors\"",
                         "id=\"fig-hole_positions\"", "id=\"fig-circularity\"", "id=\"fig-vectors\"", "id=\"diagnosis\"",
                         "id=\"verdict\"", "id=\"candidates-table\"", "id=\"fig-gap\""})
    EXPECT_NE(html.find(id), std::string::npos) << id;
  EXPECT_EQ(r.figures.size(), 5u);
  EXPECT_NE(html.find("data-figures=\"5\""), std::string::npos);
  // Self-contained: nothing fetched from elsewhere.
  for (const char* ext : {"src=", "href=", "@import", "url("}) EXPECT_EQ(html.find(ext), std::string::npos) << ext;
  // Every parameter and characteristic is in the tables.
  for (const auto& p : r.stage.identification.parameters) EXPECT_NE(html.find(p.name), std::string::npos) << p.name;
  for (const auto& c : r.stage.inspection.characteristics) EXPECT_NE(html.find(c.name), std::string::npos) << c.name;
}

TEST(RunStage, OutputDirectoryIsCompleteAndReplacedAtomically) {
  const RunResult& r = SampleRun();
  const fs::path dir = fs::path(testing::TempDir()) / "tpcal_run_stage_out";
  fs::remove_all(dir);
  const auto files = RenderRunFiles(r);
  ASSERT_TRUE(WriteDirectoryAtomic(dir.string(), files).ok());
  for (const char* name : {"report.html", "result.json", "config.yaml", "identification.csv", "identifiability.csv",
                           "characteristics.csv", "features.csv", "figures/machine_errors.svg",
                           "figures/hole_positions.svg", "figures/circularity.svg", "figures/vectors.svg",
                           "figures/gap.svg"})
    EXPECT_TRUE(fs::is_regular_file(dir / name)) << name;
  EXPECT_EQ(ReadRunText(dir / "result.json"), RunReportJson(ReportOf(r)));
  // Rewriting replaces the previous run as a whole: a stray file of the old run is gone.
  { std::ofstream(dir / "stale.txt") << "old"; }
  ASSERT_TRUE(WriteDirectoryAtomic(dir.string(), files).ok());
  EXPECT_FALSE(fs::exists(dir / "stale.txt"));
  // A trailing slash names the same directory.
  ASSERT_TRUE(WriteDirectoryAtomic(dir.string() + "/", files).ok());
  EXPECT_TRUE(fs::is_regular_file(dir / "result.json"));
  EXPECT_EQ(WriteDirectoryAtomic(".", files).code(), StatusCode::kInvalidArgument);
  // No temporary directory is left beside it.
  for (const auto& e : fs::directory_iterator(dir.parent_path()))
    EXPECT_EQ(e.path().filename().string().find("tpcal_run_stage_out.tmp."), std::string::npos);
  // A directory that is not a previous run is refused and left alone.
  const fs::path other = fs::path(testing::TempDir()) / "tpcal_run_stage_other";
  fs::remove_all(other);
  fs::create_directories(other);
  { std::ofstream(other / "precious.txt") << "keep"; }
  const Status refused = WriteDirectoryAtomic(other.string(), files);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(fs::exists(other / "precious.txt"));
  EXPECT_FALSE(fs::exists(other / "report.html"));
}

TEST(RunStage, BadPointFileIsAClearError) {
  PipelineConfig config = SampleConfig(0);
  config.points = std::string(TPCAL_SOURCE_DIR) + "/samples/turning/no_such_points.csv";
  auto r = RunPipeline(config);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kIoError);
  EXPECT_NE(r.status().ToString().find("no_such_points.csv"), std::string::npos);
}

TEST(RunStage, ConfigRejectsUnknownKeysWithTheLine) {
  auto c = ParsePipelineConfig("schema: tpcal.pipeline/1\npoints: a.csv\nsede: 3\n", "p.yaml");
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kParseError);
  EXPECT_EQ(c.status().line(), 3u);
  EXPECT_NE(c.status().message().find("sede"), std::string::npos);
  auto ok = ParsePipelineConfig("points: pts/a.csv\nseed: 9\nuncertainty: {monte_carlo_trials: 0}\n", "dir/p.yaml");
  ASSERT_TRUE(ok.ok()) << ok.status().ToString();
  EXPECT_EQ(ok->points, "dir/pts/a.csv");  // relative to the YAML file
  EXPECT_EQ(ok->seed, 9u);
  EXPECT_TRUE(ok->Validate().ok());
  // The effective configuration reads back to the same settings.
  auto back = ParsePipelineConfig(FormatPipelineConfig(*ok), "");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->points, ok->points);
  EXPECT_EQ(back->seed, 9u);
  EXPECT_EQ(back->monte_carlo_trials, 0);
  EXPECT_FALSE(back->anchor_near_mm.has_value());
}

// raw_scan: {anchor_feature, anchor_near_mm}: read, written back, and checked (both or neither;
// three coordinates).
TEST(RunStage, ConfigReadsTheRawScanAnchor) {
  auto c = ParsePipelineConfig("points: a.csv\nraw_scan: {anchor_feature: H1, anchor_near_mm: [120, -80.5, 40]}\n", "p.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->anchor_feature, "H1");
  ASSERT_TRUE(c->anchor_near_mm.has_value());
  EXPECT_EQ(*c->anchor_near_mm, Eigen::Vector3d(120.0, -80.5, 40.0));
  EXPECT_TRUE(c->Validate().ok());
  auto back = ParsePipelineConfig(FormatPipelineConfig(*c), "");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->anchor_feature, "H1");
  ASSERT_TRUE(back->anchor_near_mm.has_value());
  EXPECT_EQ(*back->anchor_near_mm, *c->anchor_near_mm);
  auto two = ParsePipelineConfig("points: a.csv\nraw_scan:\n  anchor_near_mm: [1, 2]\n", "p.yaml");
  ASSERT_FALSE(two.ok());
  EXPECT_EQ(two.status().line(), 3u);
  auto alone = ParsePipelineConfig("points: a.csv\nraw_scan: {anchor_feature: H1}\n", "p.yaml");
  ASSERT_TRUE(alone.ok());
  EXPECT_FALSE(alone->Validate().ok());
}

// scan_cells: read, validated, written back.
TEST(RunStage, ConfigReadsScanCells) {
  auto c = ParsePipelineConfig("points: a.csv\nscan_cells: {above_points: 1000, target_cells: 500, max_cell_mm: 3, "
                               "max_cell_deg: 1.5}\n", "p.yaml");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->scan_cells.above_points, 1000u);
  EXPECT_EQ(c->scan_cells.target_cells, 500u);
  EXPECT_EQ(c->scan_cells.max_cell_mm, 3.0);
  EXPECT_EQ(c->scan_cells.max_cell_deg, 1.5);
  auto back = ParsePipelineConfig(FormatPipelineConfig(*c), "");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->scan_cells.above_points, 1000u);
  EXPECT_EQ(back->scan_cells.max_cell_deg, 1.5);
  auto unknown = ParsePipelineConfig("points: a.csv\nscan_cells:\n  cell_mm: 3\n", "p.yaml");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.status().line(), 3u);
  auto zero = ParsePipelineConfig("points: a.csv\nscan_cells: {max_cell_deg: 0}\n", "p.yaml");
  ASSERT_TRUE(zero.ok());
  EXPECT_FALSE(zero->Validate().ok());
}

// A run whose scan is pooled says so in result.json and in the report. The sample's points are
// 22.5 deg apart, so no two share a cell: the identification is the unpooled one.
TEST(RunStage, PooledRunReportsItsCells) {
  PipelineConfig config = SampleConfig(0);
  config.scan_cells.above_points = 100;
  auto r = RunPipeline(config);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_TRUE(r->scan_cells.has_value());
  EXPECT_EQ(r->scan_cells->num_points, r->num_points);
  EXPECT_EQ(r->scan_cells->num_cells, r->num_points);
  auto plain = RunPipeline(SampleConfig(0));
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE(plain->scan_cells.has_value());
  ASSERT_EQ(plain->stage.identification.parameters.size(), r->stage.identification.parameters.size());
  for (std::size_t k = 0; k < plain->stage.identification.parameters.size(); ++k)
    EXPECT_NEAR(plain->stage.identification.parameters[k].value, r->stage.identification.parameters[k].value,
                1e-9);  // a cell of one is its point rebuilt as p0 + d n0: rounding only
  const auto files = RenderRunFiles(*r);
  bool json = false, html = false;
  for (const auto& f : files) {
    if (f.relative_path == "result.json") json = f.contents.find("\"scan_cells\"") != std::string::npos;
    if (f.relative_path == "report.html") html = f.contents.find("scan-line cells") != std::string::npos;
  }
  EXPECT_TRUE(json);
  EXPECT_TRUE(html);
}

}  // namespace
}  // namespace tpcal::pipeline
