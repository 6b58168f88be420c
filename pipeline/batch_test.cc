// Batch of 100 point files, 3 of them corrupt: 97 results, 3 clear errors, a summary with one
// row per file (and the same checks on 8 files, short enough for the sanitizer stage). The files are generated here from one simulated piece (the turning sample's
// truth) with fresh CMM noise per file, so the test needs no bulky data.
#include "pipeline/batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/parallel.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/io/point_io.h"
#include "pipeline/run_sample.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

std::string ReadBatchText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int CountLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

// n_files files; the three in `corrupt` (ascending) are broken in three ways: a non-number in a
// coordinate, a row cut off (a crashed export), a feature left with too few points.
void CheckBatch(int n_files, const std::vector<int>& corrupt_files) {
  ASSERT_EQ(corrupt_files.size(), 3u);
  auto truth = LoadSampleTruth(std::string(TPCAL_SOURCE_DIR) + "/samples/turning/truth.yaml");
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  truth->sim.noise_um = 0.0;  // noise is added per file below
  auto sample = SimulateSample(*truth);
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  const PointSet& clean = sample->simulated.points;

  const fs::path dir = fs::path(testing::TempDir()) / fmt::format("tpcal_batch_test_{}", n_files);
  fs::remove_all(dir);
  fs::create_directories(dir / "in");
  const int kFiles = n_files;
  const std::set<int> corrupt(corrupt_files.begin(), corrupt_files.end());
  const int bad_number = corrupt_files[0], cut_off = corrupt_files[1], too_few = corrupt_files[2];
  PointWriteOptions w;
  w.fixed_decimals = 5;
  for (int f = 0; f < kFiles; ++f) {
    PointSet pts = clean;
    std::mt19937_64 rng(1000 + static_cast<std::uint64_t>(f));
    std::normal_distribution<double> noise_mm(0.0, 0.5e-3);  // 0.5 um along the normal
    for (std::size_t i = 0; i < pts.size(); ++i) pts.xyz_mm[i] += noise_mm(rng) * pts.normal[i];
    auto csv = FormatPointCsv(pts, w);
    ASSERT_TRUE(csv.ok());
    std::string text = *csv;
    if (f == bad_number) {  // a non-number in a coordinate
      const auto pos = text.find('\n', text.find("feature,")) + 1;
      const auto comma = text.find(',', pos);
      text.replace(comma + 1, 3, "abc");
    } else if (f == cut_off) {  // cut off in the middle of a row (a crashed export)
      text.resize(text.size() / 2);
      text.resize(text.rfind(',') + 1);
    } else if (f == too_few) {  // one feature (S4) left with 2 points: a circle needs 3
      std::string kept;
      int s4 = 0;
      std::istringstream in(text);
      for (std::string line; std::getline(in, line);)
        if (!line.starts_with("S4,") || ++s4 <= 2) kept += line + "\n";
      text = kept;
    }
    ASSERT_TRUE(WriteFileAtomic((dir / "in" / fmt::format("run{:03d}.csv", f)).string(), text).ok());
  }

  auto files = ExpandBatchInputs((dir / "in").string());
  ASSERT_TRUE(files.ok()) << files.status().ToString();
  ASSERT_EQ(files->size(), static_cast<std::size_t>(kFiles));

  BatchOptions options;
  options.base.testpiece = "turning";
  options.base.machine = std::string(TPCAL_SOURCE_DIR) + "/samples/machines/ac_table.yaml";
  options.base.monte_carlo_trials = 0;  // jackknife only, no diagnosis: keeps 100 runs fast
  options.base.diagnose = false;
  options.base.points = "(batch)";
  options.out_dir = (dir / "out").string();
  options.write_runs = false;  // run directories: tests/cli/run_batch_test.sh
  std::size_t callbacks = 0;
  auto result = RunBatch(*files, options, [&](const BatchItem&, std::size_t done, std::size_t total) {
    ++callbacks;
    EXPECT_LE(done, total);
  });
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(callbacks, static_cast<std::size_t>(kFiles));
  EXPECT_EQ(result->failed, 3);
  int ok = 0;
  for (int f = 0; f < kFiles; ++f) {
    const BatchItem& item = result->items[static_cast<std::size_t>(f)];
    EXPECT_EQ(item.points, (*files)[static_cast<std::size_t>(f)]);  // input order kept
    if (corrupt.count(f)) {
      EXPECT_FALSE(item.status.ok()) << f;
      // A clear error: names the file (and for the parse errors, the line).
      EXPECT_NE(item.status.ToString().find(fmt::format("run{:03d}.csv", f)), std::string::npos)
          << item.status.ToString();
      EXPECT_TRUE(item.run_dir.empty());
    } else {
      EXPECT_TRUE(item.status.ok()) << item.status.ToString();
      EXPECT_FALSE(item.parameters.empty());
      ++ok;
    }
  }
  EXPECT_EQ(ok, kFiles - 3);
  const BatchItem& number_item = result->items[static_cast<std::size_t>(bad_number)];
  EXPECT_NE(number_item.status.ToString().find("abc"), std::string::npos) << number_item.status.ToString();
  EXPECT_GT(number_item.status.line(), 0u);
  const BatchItem& few_item = result->items[static_cast<std::size_t>(too_few)];
  EXPECT_NE(few_item.status.ToString().find("S4"), std::string::npos) << few_item.status.ToString();

  const std::string summary = ReadBatchText(dir / "out" / "summary.csv");
  EXPECT_EQ(CountLines(summary), kFiles + 1);
  EXPECT_NE(summary.find("dx_CR(0)_um"), std::string::npos);
  EXPECT_EQ(CountLines(summary) - 1, (kFiles - 3) + 3);
  int error_rows = 0;
  std::istringstream in(summary);
  for (std::string line; std::getline(in, line);)
    error_rows += !line.starts_with("run,") && line.find(",error,") != std::string::npos;
  EXPECT_EQ(error_rows, 3);
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "summary_trend.svg"));
  // The same files on one thread give the same rows (order and numbers do not depend on
  // scheduling): the first (up to) 10 files, one of them corrupt.
  options.threads = 1;
  options.out_dir = (dir / "out1").string();
  const int n_serial = std::min(kFiles, 10);
  const std::vector<std::string> first(files->begin(), files->begin() + n_serial);
  // -j 1 bounds the items' own loops too: they see one thread (core/parallel.h's limit).
  std::size_t seen_threads = 0;
  auto serial = RunBatch(first, options, [&](const BatchItem&, std::size_t, std::size_t) {
    seen_threads = std::max(seen_threads, HardwareThreads());
  });
  ASSERT_TRUE(serial.ok());
  EXPECT_EQ(seen_threads, 1u);
  const std::string serial_summary = ReadBatchText(dir / "out1" / "summary.csv");
  std::istringstream a(summary), b(serial_summary);
  std::string la, lb;
  for (int row = 0; row < n_serial + 1 && std::getline(a, la) && std::getline(b, lb); ++row) EXPECT_EQ(la, lb) << row;
  fs::remove_all(dir);
}

// The case. Long under the sanitizers (tests/sanitizers/long_tests.txt): there the
// eight-file case below covers the same code.
TEST(Batch, HundredFilesThreeCorrupt) { CheckBatch(100, {7, 42, 93}); }

TEST(Batch, EightFilesThreeCorrupt) { CheckBatch(8, {1, 4, 6}); }

TEST(Batch, NothingToRunIsAnError) {
  auto files = ExpandBatchInputs(std::string(TPCAL_SOURCE_DIR) + "/samples/turning/*.nothing");
  ASSERT_FALSE(files.ok());
  EXPECT_EQ(files.status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tpcal::pipeline
