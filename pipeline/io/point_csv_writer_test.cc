#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {
namespace {

// Same size and the same bytes (bit-identical doubles; -0.0 differs from 0.0, NaN equals itself).
template <typename T>
bool WriterBitsEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}


namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("tpcal_writer_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Random points with hard doubles (full 53-bit mantissas, tiny and huge magnitudes).
PointSet RandomPointSet(std::size_t n, std::uint64_t seed, bool normals) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-1000.0, 1000.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  PointSet ps;
  ps.source = "random";
  ps.feature_names = {"S_R", "H1", "odd, name", "#hash", " padded "};
  PointAttribute t{"t_s", {}, {}};
  PointAttribute note{"note", {}, {}};
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = i % 7 == 0 ? 1e-9 : (i % 11 == 0 ? 1e6 : 1.0);
    ps.xyz_mm.push_back(Eigen::Vector3d{coord(rng) * scale, coord(rng), coord(rng) / 3.0});
    if (normals) {
      Eigen::Vector3d nv{gauss(rng), gauss(rng), gauss(rng)};
      ps.normal.push_back(nv.normalized());
    }
    ps.feature.push_back(i % 13 == 0 ? PointSet::kUnlabelled : static_cast<int>(i % 5));
    t.values.push_back(coord(rng) * 1e-3);
    note.text.push_back(i % 3 == 0 ? "x" : "a, b");
  }
  ps.attributes = {t, note};
  return ps;
}

void WriterExpectSameBits(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(WriterBitsEqual(a, b));
}

TEST(PointCsvWriter, WritesTheContractLayout) {
  PointSet ps;
  ps.feature_names = {"S_R"};
  ps.xyz_mm = {{118.99871, 0.00312, -4.9996}};
  ps.normal = {{-1, 0, 0}};
  ps.feature = {0};
  Result<std::string> text = FormatPointCsv(ps);
  ASSERT_TRUE(text.ok()) << text.status().ToString();
  EXPECT_EQ(*text, "# tpcal points v1\n# units: mm\nfeature,x,y,z,i,j,k\nS_R,118.99871,0.00312,-4.9996,-1,0,0\n");
  PointWriteOptions fixed;
  fixed.fixed_decimals = 6;
  EXPECT_EQ(*FormatPointCsv(ps, fixed),
            "# tpcal points v1\n# units: mm\nfeature,x,y,z,i,j,k\n"
            "S_R,118.998710,0.003120,-4.999600,-1.000000,0.000000,0.000000\n");
}

TEST(PointCsvWriter, RoundTripIsBitExact) {
  const fs::path dir = TempDir("roundtrip");
  const PointSet ps = RandomPointSet(5000, 42, true);
  const std::string path = (dir / "points.csv").string();
  ASSERT_TRUE(WritePointCsv(path, ps).ok());
  Result<PointFile> back = ReadPointCsv(path);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  const PointSet& r = back->points;
  EXPECT_EQ(back->info.kind, PointFileKind::kPoints);
  WriterExpectSameBits(r.xyz_mm, ps.xyz_mm);
  WriterExpectSameBits(r.normal, ps.normal);  // normalized() output re-read without change
  // Labels: names in order of first appearance in the file, indices remapped accordingly.
  ASSERT_EQ(r.size(), ps.size());
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (ps.feature[i] == PointSet::kUnlabelled) {
      EXPECT_EQ(r.feature[i], PointSet::kUnlabelled);
    } else {
      EXPECT_EQ(r.feature_names[r.feature[i]], ps.feature_names[ps.feature[i]]);
    }
  }
  ASSERT_EQ(r.attributes.size(), 2u);
  EXPECT_EQ(r.attributes[0].name, "t_s");
  EXPECT_TRUE(WriterBitsEqual(r.attributes[0].values, ps.attributes[0].values));
  EXPECT_EQ(r.attributes[1].text, ps.attributes[1].text);
  EXPECT_EQ(r.line.front(), 4u);  // tag, units, header, first row
  fs::remove_all(dir);
}

TEST(PointCsvWriter, FixedDecimalsRoundTripWithinHalfAUnitOfTheLastDigit) {
  const PointSet ps = RandomPointSet(500, 7, false);
  PointWriteOptions o;
  o.fixed_decimals = 6;  // 1 nm
  Result<std::string> text = FormatPointCsv(ps, o);
  ASSERT_TRUE(text.ok());
  Result<PointFile> back = ParsePointCsv(*text, "mem.csv");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  for (std::size_t i = 0; i < ps.size(); ++i)
    for (int c = 0; c < 3; ++c)  // 0.5e-6 mm rounding plus the ulp of 1e9 (huge test values)
      EXPECT_NEAR(back->points.xyz_mm[i][c], ps.xyz_mm[i][c], 0.5e-6 + 2e-7) << i;
}

TEST(PointCsvWriter, PlanTagAndRawScan) {
  PointSet ps;
  ps.xyz_mm = {{1, 2, 3}, {4, 5, 6}};
  ps.feature = {PointSet::kUnlabelled, PointSet::kUnlabelled};
  PointWriteOptions plan;
  plan.kind = PointFileKind::kPlan;
  Result<std::string> no_normals = FormatPointCsv(ps, plan);
  ASSERT_FALSE(no_normals.ok());
  EXPECT_EQ(no_normals.status().code(), StatusCode::kInvalidArgument);
  ps.normal = {{0, 0, 1}, {0, 0, 1}};
  ps.attributes = {{"op", {1, 2}, {}}, {"t_s", {0.5, 1.5}, {}}};
  Result<std::string> text = FormatPointCsv(ps, plan);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(*text, "# tpcal plan v1\n# units: mm\nfeature,x,y,z,i,j,k,op,t_s\n,1,2,3,0,0,1,1,0.5\n,4,5,6,0,0,1,2,1.5\n");
  Result<PointFile> back = ParsePointCsv(*text, "plan.csv");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->info.kind, PointFileKind::kPlan);
  EXPECT_FALSE(back->points.has_labels());
}

TEST(PointCsvWriter, RefusesWhatCannotBeReadBack) {
  PointSet ps;
  ps.xyz_mm = {{1, 2, 3}};
  ps.feature_names = {"has \"quote\""};
  ps.feature = {0};
  EXPECT_EQ(FormatPointCsv(ps).status().code(), StatusCode::kInvalidArgument);
  ps.feature_names = {"ok"};
  ps.xyz_mm[0].x() = std::nan("");
  EXPECT_EQ(FormatPointCsv(ps).status().message(), "point 0 has a non-finite coordinate");
  ps.xyz_mm[0].x() = 1;
  ps.normal = {{0, 0, 0}};
  EXPECT_EQ(FormatPointCsv(ps).status().message(), "point 0 has a normal of length 0, expected a unit vector");
  ps.normal.clear();
  ps.attributes = {{"X", {1}, {}}};
  EXPECT_EQ(FormatPointCsv(ps).status().message(), "attribute name 'X' clashes with another column");
  ps.attributes = {{"t_s", {1, 2}, {}}};
  EXPECT_EQ(FormatPointCsv(ps).status().message(), "attribute 't_s' has 2 values for 1 points");
  EXPECT_EQ(FormatPointCsv(PointSet{}).status().message(), "no points to write");
}

TEST(PointCsvWriter, FailedWriteLeavesExistingFileUntouched) {
  const fs::path dir = TempDir("keep");
  const std::string path = (dir / "points.csv").string();
  {
    std::ofstream(path) << "old contents\n";
  }
  PointSet ps;
  ps.xyz_mm = {{1, 2, 3}, {std::nan(""), 0, 0}};  // fails at the second row, mid-stream
  Status s = WritePointCsv(path, ps);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.file(), path);
  EXPECT_EQ(Slurp(path), "old contents\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temp left
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
