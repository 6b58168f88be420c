// tests/data/dmis/, tests/data/tables/ and tests/data/qif/turning_sample.qif hold
// samples/turning/cmm_points.csv in the CMM formats and other software's tables (one under its own
// column names, read with a column mapping): read through the dispatch they give the CSV's points
// bit for bit, and the QIF file is what FormatPointQif writes
// today. When the sample changes on purpose, regenerate the QIF file with
// TPCAL_REGENERATE_SAMPLES=1 (this test then writes it) and the DMIS, XYZIJK and table files with
// tests/data/dmis/regenerate.py (their number text is the CSV's, copied).
#include <gtest/gtest.h>

#include <cstdlib>

#include "pipeline/io/atomic_file.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/point_io.h"
#include "pipeline/io/qif_reader.h"

namespace tpcal::pipeline {
namespace {

std::string SourcePath(const std::string& rel) { return std::string(TPCAL_SOURCE_DIR) + "/" + rel; }

TEST(CmmSamples, DmisQifXyzijkAndTablesHoldTheTurningSample) {
  auto csv = ReadPointFile(SourcePath("samples/turning/cmm_points.csv"));
  ASSERT_TRUE(csv.ok()) << csv.status().ToString();
  if (std::getenv("TPCAL_REGENERATE_SAMPLES")) {
    ASSERT_TRUE(WriteFileAtomic(SourcePath("tests/data/qif/turning_sample.qif"), FormatPointQif(csv->points)).ok());
    GTEST_SKIP() << "regenerated tests/data/qif/turning_sample.qif";
  }
  PointReadOptions own_names;  // the table under its own column names, read with a column mapping
  own_names.columns = {{"feature", "Pt ID"}, {"x", "Meas X"}, {"y", "Meas Y"}, {"z", "Meas Z"},
                       {"i", "Vec I"},       {"j", "Vec J"},  {"k", "Vec K"}};
  const struct {
    const char* path;
    PointFormat format;
    PointReadOptions options;
  } files[] = {{"tests/data/dmis/turning_sample.dmo", PointFormat::kDmis, {}},
               {"tests/data/qif/turning_sample.qif", PointFormat::kQif, {}},
               {"tests/data/dmis/turning_sample_xyzijk.txt", PointFormat::kXyzijk, {}},
               {"tests/data/tables/turning_sample_semicolon.csv", PointFormat::kCsv, {}},
               {"tests/data/tables/turning_sample_tab.tsv", PointFormat::kCsv, {}},
               {"tests/data/tables/turning_sample_own_names.csv", PointFormat::kCsv, own_names}};
  for (const auto& f : files) {
    auto r = ReadPointFile(SourcePath(f.path), f.options);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_EQ(r->info.format, f.format) << f.path;
    EXPECT_EQ(r->points.xyz_mm, csv->points.xyz_mm) << f.path;
    EXPECT_EQ(r->points.normal, csv->points.normal) << f.path;
    EXPECT_EQ(r->points.feature, csv->points.feature) << f.path;
    EXPECT_EQ(r->points.feature_names, csv->points.feature_names) << f.path;
  }
  auto qif = ReadFileBytes(SourcePath("tests/data/qif/turning_sample.qif"));
  ASSERT_TRUE(qif.ok());
  EXPECT_EQ(std::string(qif->view()), FormatPointQif(csv->points));
}

}  // namespace
}  // namespace tpcal::pipeline
