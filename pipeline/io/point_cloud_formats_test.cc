#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/units.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {
namespace {

// Same size and the same bytes (bit-identical doubles; -0.0 differs from 0.0, NaN equals itself).
template <typename T>
bool CloudBitsEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}


namespace fs = std::filesystem;

std::string CloudDataPath(const std::string& name) {
  return std::string(TPCAL_SOURCE_DIR) + "/tests/data/points/" + name;
}

class PointCloudFormatsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tpcal_formats_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  static PointSet Sample(std::size_t n) {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> coord(-300.0, 300.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    PointSet ps;
    ps.feature_names = {"S1"};
    PointAttribute t{"t_s", {}, {}};
    PointAttribute note{"note", {}, {}};
    for (std::size_t i = 0; i < n; ++i) {
      ps.xyz_mm.push_back(Eigen::Vector3d{coord(rng), coord(rng), coord(rng) * 1e-7});
      ps.normal.push_back(Eigen::Vector3d{gauss(rng), gauss(rng), gauss(rng)}.normalized());
      ps.feature.push_back(0);
      t.values.push_back(coord(rng));
      note.text.push_back("text");
    }
    ps.attributes = {t, note};
    return ps;
  }

  fs::path dir_;
};

void CloudExpectSameBits(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(CloudBitsEqual(a, b));
}

TEST_F(PointCloudFormatsTest, PlyAndPcdRoundTripThroughPclWritersAtDoublePrecision) {
  const PointSet ps = Sample(1000);
  struct Case {
    const char* name;
    bool binary;
    bool ply;
  };
  for (const Case& c : {Case{"b.ply", true, true}, Case{"a.ply", false, true}, Case{"b.pcd", true, false},
                        Case{"a.pcd", false, false}}) {
    SCOPED_TRACE(c.name);
    PointWriteOptions o;
    o.binary = c.binary;
    const std::string path = Path(c.name);
    Status s = c.ply ? WritePointPly(path, ps, o) : WritePointPcd(path, ps, o);
    ASSERT_TRUE(s.ok()) << s.ToString();
    Result<PointFile> back = ReadPointFile(path);  // format from the extension
    ASSERT_TRUE(back.ok()) << back.status().ToString();
    EXPECT_EQ(back->info.format, c.ply ? PointFormat::kPly : PointFormat::kPcd);
    const PointSet& r = back->points;
    CloudExpectSameBits(r.xyz_mm, ps.xyz_mm);
    CloudExpectSameBits(r.normal, ps.normal);
    // Labels and text attributes are not representable in PLY/PCD (documented).
    EXPECT_FALSE(r.has_labels());
    ASSERT_EQ(r.attributes.size(), 1u);
    EXPECT_EQ(r.attributes[0].name, "t_s");
    EXPECT_EQ(r.attributes[0].values, ps.attributes[0].values);
    EXPECT_TRUE(r.line.empty());
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 4);  // no temps
}

TEST_F(PointCloudFormatsTest, PlyWithoutNormals) {
  Result<PointFile> r = ReadPointPly(CloudDataPath("scan_float.ply"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_FALSE(ps.has_normals());
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.5, 2.25, -3));  // exact in float
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(0.5, 0, 10.125));
  EXPECT_EQ(ps.feature, (std::vector<int>(3, PointSet::kUnlabelled)));
}

TEST_F(PointCloudFormatsTest, PlyDoublesAndNxNyNz) {
  Result<PointFile> r = ReadPointPly(CloudDataPath("scan_normals.ply"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.xyz_mm[0].x(), 118.99871234567);  // double property kept at double precision
  ASSERT_TRUE(ps.has_normals());
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(-1, 0, 0));
  ASSERT_NE(ps.Attribute("quality"), nullptr);
  EXPECT_EQ(ps.Attribute("quality")->values, (std::vector<double>{200, 17}));
}

TEST_F(PointCloudFormatsTest, PcdNonFinitePoints) {
  Result<PointFile> r = ReadPointPcd(CloudDataPath("scan.pcd"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().file(), CloudDataPath("scan.pcd"));
  EXPECT_EQ(r.status().line(), 14u);  // its own row
  EXPECT_EQ(r.status().message(),
            "point 2 (0-based) has a NaN or infinite coordinate; expected finite x,y,z (set "
            "skip_nonfinite_points to drop such points)");
  PointReadOptions skip;
  skip.skip_nonfinite_points = true;
  r = ReadPointPcd(CloudDataPath("scan.pcd"), skip);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->points.size(), 2u);
  EXPECT_EQ(r->points.normal[1], Eigen::Vector3d(0, 1, 0));
  ASSERT_NE(r->points.Attribute("curvature"), nullptr);
  EXPECT_EQ(r->points.Attribute("curvature")->values, (std::vector<double>{0.5, 0.25}));
}

TEST_F(PointCloudFormatsTest, ANonFinitePointOfAsciiDataCitesItsOwnRow) {
  const std::string ply = Path("nan.ply");
  std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n1 2 3\n4 5 6\n7 nan 9\n1 1 1\n";
  Result<PointFile> r = ReadPointPly(ply);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().ToString(), ply + ":10: point 2 (0-based) has a NaN or infinite coordinate; expected finite "
                                         "x,y,z (set skip_nonfinite_points to drop such points)");
  // A float field beyond the float range is infinite once read; blank lines are no rows.
  const std::string pcd = Path("overflow.pcd");
  std::ofstream(pcd) << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                        "POINTS 3\nDATA ascii\n1 2 3\n\n4 5 1e39\n7 8 9\n";
  r = ReadPointPcd(pcd);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().file(), pcd);
  EXPECT_EQ(r.status().line(), 12u) << r.status().ToString();
}

TEST_F(PointCloudFormatsTest, DamagedPlyIsAParseError) {
  const std::string path = Path("bad.ply");
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nend_header\n1\n";
  Result<PointFile> r = ReadPointPly(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().file(), path);
  EXPECT_EQ(r.status().code(), StatusCode::kParseError);
  EXPECT_EQ(ReadPointPly(Path("missing.ply")).status().code(), StatusCode::kIoError);
}

TEST_F(PointCloudFormatsTest, AssumedUnitsForFormatsWithoutUnits) {
  PointReadOptions inch;
  inch.assumed_units = LengthUnit::kInch;
  Result<PointFile> r = ReadPointPly(CloudDataPath("scan_float.ply"), inch);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->info.source_units, LengthUnit::kInch);
  EXPECT_EQ(r->points.xyz_mm[0], Eigen::Vector3d(1.5 * kMmPerInch, 2.25 * kMmPerInch, -3 * kMmPerInch));
}

TEST_F(PointCloudFormatsTest, XyzText) {
  Result<PointFile> r = ReadPointFile(CloudDataPath("points.xyz"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->info.format, PointFormat::kXyz);
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{3, 4, 6}));
  EXPECT_EQ(ps.xyz_mm[2], Eigen::Vector3d(2, 2, 3));
  EXPECT_EQ(ps.normal[1], Eigen::Vector3d(0, 0, 1));
  EXPECT_FALSE(ps.has_labels());

  Result<PointFile> three = ParsePointXyz("# units: in\n1 2 3\n4 5 6\n", "mem.xyz");
  ASSERT_TRUE(three.ok());
  EXPECT_FALSE(three->points.has_normals());
  EXPECT_EQ(three->points.xyz_mm[1], Eigen::Vector3d(4 * kMmPerInch, 5 * kMmPerInch, 6 * kMmPerInch));

  Result<PointFile> bad = ParsePointXyz("1 2 3\n\n4 5 6 7\n", "mem.xyz");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().ToString(),
            "mem.xyz:3: line has 4 values, expected 3 (x y z) as on the first data line (line 1)");
  bad = ParsePointXyz("1 2\n", "mem.xyz");
  EXPECT_EQ(bad.status().ToString(), "mem.xyz:1: expected 3 values (x y z) or 6 (x y z i j k) per line, got 2");
  bad = ParsePointXyz("1 2 3\n1 two 3\n", "mem.xyz");
  EXPECT_EQ(bad.status().ToString(), "mem.xyz:2: column 'y': expected a number, got 'two'");
  bad = ParsePointXyz("# nothing\n", "mem.xyz");
  EXPECT_EQ(bad.status().ToString(),
            "mem.xyz: no points: the file has only comments and blank lines; expected lines of x y z [i j k]");
}

TEST_F(PointCloudFormatsTest, XyzParallelEqualsSerial) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coord(-100.0, 100.0);
  std::string text = "# scan\n";
  for (int i = 0; i < 30000; ++i) {
    const double x = coord(rng), y = coord(rng), z = coord(rng);  // drawn in this order under every compiler
    text += std::to_string(x) + (i % 3 ? " " : "\t") + std::to_string(y) + ", " +
            std::to_string(z) + (i % 5 ? "\n" : "  \r\n");
    if (i % 1000 == 0) text += "# comment\n\n";
  }
  PointReadOptions serial;
  serial.threads = 1;
  PointReadOptions parallel;
  parallel.threads = 4;
  parallel.min_chunk_bytes = 1000;
  Result<PointFile> a = ParsePointXyz(text, "scan.xyz", serial);
  Result<PointFile> b = ParsePointXyz(text, "scan.xyz", parallel);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(b->info.chunks, 4);
  ASSERT_EQ(a->points.size(), 30000u);
  EXPECT_TRUE(CloudBitsEqual(a->points.xyz_mm, b->points.xyz_mm));
  EXPECT_EQ(a->points.line, b->points.line);
  EXPECT_EQ(a->points.line.back(), 30000u + 1u + 2u * 30u);
}

TEST_F(PointCloudFormatsTest, FormatChoice) {
  EXPECT_EQ(PointFormatFromExtension("a/b.CSV"), PointFormat::kCsv);
  EXPECT_EQ(PointFormatFromExtension("a/b.tsv"), PointFormat::kCsv);
  EXPECT_EQ(PointFormatFromExtension("b.txt"), PointFormat::kXyz);
  EXPECT_EQ(PointFormatFromExtension("b.Ply"), PointFormat::kPly);
  EXPECT_EQ(PointFormatFromExtension("b.pcd"), PointFormat::kPcd);
  EXPECT_EQ(PointFormatFromExtension("b.dat"), PointFormat::kAuto);
  const std::string odd = Path("points.dat");
  fs::copy_file(CloudDataPath("canonical.csv"), odd);
  Result<PointFile> r = ReadPointFile(odd);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message(),
            "unknown point file extension '.dat': expected .csv, .tsv, .ply, .pcd, .xyz, .txt, .qif or "
            ".dmo (or give the format explicitly)");
  PointReadOptions csv;
  csv.format = PointFormat::kCsv;
  r = ReadPointFile(odd, csv);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->points.size(), 5u);
}

}  // namespace
}  // namespace tpcal::pipeline
