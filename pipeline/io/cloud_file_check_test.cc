#include "pipeline/io/cloud_file_check.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "pipeline/io/file_bytes.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

// Every PLY and PCD file of the bad-input corpus (crash reproducers of the fuzzers among them)
// is refused by tpcal's check with a parse error naming the file, and reading it through the
// public reader (which would hand it to PCL otherwise) fails the same way, without a crash.
TEST(CloudFileCheck, EveryBadCloudIsRefusedBeforePcl) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(std::string(TPCAL_SOURCE_DIR) + "/tests/data/bad")) {
    const std::string path = entry.path().string();
    const std::string ext = entry.path().extension().string();
    if (ext != ".ply" && ext != ".pcd") continue;
    ++n;
    Result<FileBytes> bytes = ReadFileBytes(path);
    ASSERT_TRUE(bytes.ok()) << path;
    const Status check = ext == ".ply" ? internal::CheckPlyBytes(bytes->view(), path)
                                       : internal::CheckPcdBytes(bytes->view(), path);
    EXPECT_FALSE(check.ok()) << path;
    EXPECT_EQ(check.code(), StatusCode::kParseError) << path;
    EXPECT_EQ(check.file(), path);
    Result<PointFile> read = ReadPointFile(path);
    ASSERT_FALSE(read.ok()) << path;
    EXPECT_EQ(read.status().ToString(), check.ToString());
  }
  EXPECT_GE(n, 8);
}

// The good clouds of the reader tests pass the check.
TEST(CloudFileCheck, GoodCloudsPass) {
  for (const char* name : {"scan.pcd", "scan_float.ply", "scan_normals.ply"}) {
    const std::string path = std::string(TPCAL_SOURCE_DIR) + "/tests/data/points/" + name;
    Result<FileBytes> bytes = ReadFileBytes(path);
    ASSERT_TRUE(bytes.ok()) << path;
    const std::string_view v = bytes->view();
    const Status check = path.ends_with(".ply") ? internal::CheckPlyBytes(v, path) : internal::CheckPcdBytes(v, path);
    EXPECT_TRUE(check.ok()) << check.ToString();
  }
}

TEST(CloudFileCheck, DeclaredPointsBeyondTheDataFailAtOnce) {
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n1 2 3\n";
  const Status s = internal::CheckPlyBytes(ply, "a.ply");
  EXPECT_EQ(s.ToString(), "a.ply:8: the data ends after 1 of the 100000000 vertex rows the header declares (line 3)");
  const std::string pcd = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000\nPOINTS 1000000\n"
                          "DATA binary\n0123456789ab";
  EXPECT_EQ(internal::CheckPcdBytes(pcd, "a.pcd").ToString(),
            "a.pcd: the binary data holds 12 bytes; the header declares 1000000 points of 12 bytes (12000000 bytes)");
}

}  // namespace
}  // namespace tpcal::pipeline
