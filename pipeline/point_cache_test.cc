#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pipeline/point_io.h"

namespace tpcal::pipeline {
namespace {

// Same size and the same bytes (bit-identical doubles; -0.0 differs from 0.0, NaN equals itself).
template <typename T>
bool BitsEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}


namespace fs = std::filesystem;

class PointCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tpcal_cache_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    source_ = (dir_ / "points.csv").string();
    WriteText(source_, kText);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void WriteText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
  }
  static std::string Slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void SetMtime(const std::string& path, const struct timespec& t) {
    struct timespec times[2] = {t, t};
    ASSERT_EQ(::utimensat(AT_FDCWD, path.c_str(), times, 0), 0);
  }
  static struct timespec Mtime(const std::string& path) {
    struct stat st {};
    ::stat(path.c_str(), &st);
    return st.st_mtim;
  }

  Result<PointFile> Read(const PointCacheOptions& cache = {}, const PointReadOptions& o = {}) {
    return ReadPointFileCached(source_, o, cache);
  }

  static constexpr const char* kText =
      "# tpcal points v1\nfeature,x,y,z,i,j,k,note\nA,1.25,2,3,0,0,1,x\n# c\nB,4,5,6,1,0,0,7\n";
  fs::path dir_;
  std::string source_;
};

void ExpectSame(const PointSet& a, const PointSet& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(BitsEqual(a.xyz_mm, b.xyz_mm));
  EXPECT_TRUE(BitsEqual(a.normal, b.normal));
  EXPECT_EQ(a.feature, b.feature);
  EXPECT_EQ(a.feature_names, b.feature_names);
  EXPECT_EQ(a.line, b.line);
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  for (std::size_t k = 0; k < a.attributes.size(); ++k) {
    EXPECT_EQ(a.attributes[k].name, b.attributes[k].name);
    EXPECT_EQ(a.attributes[k].values, b.attributes[k].values);
    EXPECT_EQ(a.attributes[k].text, b.attributes[k].text);
  }
}

TEST_F(PointCacheTest, MissThenHit) {
  Result<PointFile> direct = ReadPointFile(source_);
  ASSERT_TRUE(direct.ok());
  Result<PointFile> first = Read();
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_EQ(first->info.cache, CacheOutcome::kMissing);
  EXPECT_TRUE(first->info.cache_write.ok()) << first->info.cache_write.ToString();
  EXPECT_TRUE(fs::exists(source_ + ".tpcache"));
  ExpectSame(first->points, direct->points);

  Result<PointFile> second = Read();
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->info.cache, CacheOutcome::kHit);
  EXPECT_EQ(second->info.chunks, 0);
  EXPECT_EQ(second->info.kind, PointFileKind::kPoints);
  EXPECT_EQ(second->info.bytes, direct->info.bytes);
  ExpectSame(second->points, direct->points);
  EXPECT_EQ(second->points.line, (std::vector<std::size_t>{3, 5}));
  EXPECT_FALSE(second->points.attributes[0].is_numeric());
}

TEST_F(PointCacheTest, EditedSourceIsStaleAndTheCacheIsRewritten) {
  ASSERT_TRUE(Read().ok());
  WriteText(source_, std::string(kText) + "C,7,8,9,0,1,0,y\n");
  Result<PointFile> r = Read();
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->info.cache, CacheOutcome::kStale);
  EXPECT_EQ(r->points.size(), 3u);
  Result<PointFile> again = Read();
  EXPECT_EQ(again->info.cache, CacheOutcome::kHit);
  EXPECT_EQ(again->points.size(), 3u);
}

TEST_F(PointCacheTest, SameSizeSameMtimeEditCaughtByFullHashOnly) {
  ASSERT_TRUE(Read().ok());
  const struct timespec t = Mtime(source_);
  std::string edited = kText;
  edited[edited.find("1.25")] = '9';  // 1.25 -> 9.25, same size
  WriteText(source_, edited);
  SetMtime(source_, t);  // as `cp -p` or an unlucky clock would leave it

  PointCacheOptions ends;
  ends.verify = CacheVerify::kEnds;
  ends.write = false;
  Result<PointFile> quick = Read(ends);
  ASSERT_TRUE(quick.ok());
  // kEnds sees this edit because it lies in the first 64 KiB (see the next test for its blind spot).
  EXPECT_EQ(quick->info.cache, CacheOutcome::kStale);

  Result<PointFile> full = Read();
  ASSERT_TRUE(full.ok());
  EXPECT_EQ(full->info.cache, CacheOutcome::kStale);
  EXPECT_EQ(full->points.xyz_mm[0].x(), 9.25);
}

TEST_F(PointCacheTest, EndsModeMissesAMiddleEditOfABigFileFullModeCatchesIt) {
  std::string big = "feature,x,y,z\n";
  for (int i = 0; i < 20000; ++i) big += "A,1.000,2.000,3.000\n";
  WriteText(source_, big);
  ASSERT_TRUE(Read().ok());
  const struct timespec t = Mtime(source_);
  const std::size_t pos = big.find("1.000", big.size() / 2);
  big.replace(pos, 5, "4.000");
  WriteText(source_, big);
  SetMtime(source_, t);
  PointCacheOptions ends;
  ends.verify = CacheVerify::kEnds;
  ends.write = false;
  Result<PointFile> quick = Read(ends);
  EXPECT_EQ(quick->info.cache, CacheOutcome::kHit);  // the documented blind spot
  Result<PointFile> full = Read();
  EXPECT_EQ(full->info.cache, CacheOutcome::kStale);
}

TEST_F(PointCacheTest, CorruptOrTruncatedCacheIsIgnoredAndRewritten) {
  ASSERT_TRUE(Read().ok());
  const std::string cache = source_ + ".tpcache";
  std::string bytes = Slurp(cache);
  bytes[bytes.size() / 2] ^= 0x5a;
  WriteText(cache, bytes);
  Result<PointFile> r = Read();
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->info.cache, CacheOutcome::kCorrupt);
  EXPECT_EQ(r->points.size(), 2u);
  EXPECT_EQ(Read()->info.cache, CacheOutcome::kHit);

  WriteText(cache, Slurp(cache).substr(0, 40));
  EXPECT_EQ(Read()->info.cache, CacheOutcome::kCorrupt);
  WriteText(cache, "garbage");
  EXPECT_EQ(Read()->info.cache, CacheOutcome::kCorrupt);
  EXPECT_EQ(Read()->info.cache, CacheOutcome::kHit);
}

TEST_F(PointCacheTest, ChangedOptionsMakeTheCacheStale) {
  ASSERT_TRUE(Read().ok());
  PointReadOptions o;
  o.normal_tolerance = 0.01;
  EXPECT_EQ(Read({}, o)->info.cache, CacheOutcome::kStale);
  o.threads = 1;  // does not change the result: still a hit
  EXPECT_EQ(Read({}, o)->info.cache, CacheOutcome::kHit);
}

TEST_F(PointCacheTest, CacheDirectory) {
  PointCacheOptions in_dir;
  in_dir.cache_dir = (dir_ / "cache" / "sub").string();
  const std::string cache_path = PointCachePath(source_, in_dir);
  EXPECT_EQ(fs::path(cache_path).parent_path(), fs::path(in_dir.cache_dir));
  EXPECT_EQ(fs::path(cache_path).filename().string().rfind("points.csv.", 0), 0u);
  EXPECT_EQ(Read(in_dir)->info.cache, CacheOutcome::kMissing);
  EXPECT_TRUE(fs::exists(cache_path));
  EXPECT_FALSE(fs::exists(source_ + ".tpcache"));
  EXPECT_EQ(Read(in_dir)->info.cache, CacheOutcome::kHit);
}

TEST_F(PointCacheTest, UnwritableCacheDoesNotFailTheRead) {
  PointCacheOptions bad;
  bad.cache_dir = source_ + "/not_a_dir";  // below a regular file
  Result<PointFile> r = Read(bad);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->points.size(), 2u);
  EXPECT_FALSE(r->info.cache_write.ok());
}

TEST_F(PointCacheTest, ParseErrorsAreReturnedAndNothingIsCached) {
  WriteText(source_, "feature,x,y,z\nA,1,2\n");
  Result<PointFile> r = Read();
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().ToString(), source_ + ":2: row has 3 cells, header has 4 (feature,x,y,z)");
  EXPECT_FALSE(fs::exists(source_ + ".tpcache"));
}

TEST_F(PointCacheTest, PlySourcesAreCachedToo) {
  const std::string ply = (dir_ / "scan.ply").string();
  fs::copy_file(std::string(TPCAL_SOURCE_DIR) + "/tests/data/points/scan_normals.ply", ply);
  Result<PointFile> first = ReadPointFileCached(ply, {}, {});
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_EQ(first->info.cache, CacheOutcome::kMissing);
  Result<PointFile> second = ReadPointFileCached(ply, {}, {});
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->info.cache, CacheOutcome::kHit);
  EXPECT_EQ(second->info.format, PointFormat::kPly);
  ExpectSame(first->points, second->points);
}

}  // namespace
}  // namespace tpcal::pipeline
