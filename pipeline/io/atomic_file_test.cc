#include "pipeline/io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tpcal_atomic_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t FileCount() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  static std::string Slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, WritesAndReplaces) {
  const std::string path = Path("out.txt");
  ASSERT_TRUE(WriteFileAtomic(path, "first\n").ok());
  EXPECT_EQ(Slurp(path), "first\n");
  ASSERT_TRUE(WriteFileAtomic(path, "second\n").ok());
  EXPECT_EQ(Slurp(path), "second\n");
  EXPECT_EQ(FileCount(), 1u);
}

TEST_F(AtomicFileTest, StreamingWriterLargerThanItsBuffer) {
  const std::string path = Path("big.bin");
  std::string expected;
  Status s = WriteFileAtomic(path, [&](AtomicFileWriter& w) -> Status {
    EXPECT_EQ(fs::path(w.temp_path()).parent_path(), dir_);
    EXPECT_EQ(w.temp_path().rfind(path + ".tmp.", 0), 0u);
    for (int i = 0; i < 3000; ++i) {
      std::string piece(static_cast<std::size_t>(i % 997 + 1), static_cast<char>('a' + i % 26));
      if (i == 1500) piece.assign(3 << 20, 'Z');  // one write bigger than the buffer
      expected += piece;
      TPCAL_RETURN_IF_ERROR(w.Write(piece));
    }
    return Status::Ok();
  });
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(Slurp(path), expected);
  EXPECT_EQ(FileCount(), 1u);
}

TEST_F(AtomicFileTest, FailureInTheProducerLeavesNoPartialTarget) {
  const std::string path = Path("out.csv");
  ASSERT_TRUE(WriteFileAtomic(path, "old\n").ok());
  std::string temp;
  Status s = WriteFileAtomic(path, [&](AtomicFileWriter& w) -> Status {
    temp = w.temp_path();
    TPCAL_RETURN_IF_ERROR(w.Write(std::string(5 << 20, 'x')));  // flushed to the temp file
    EXPECT_TRUE(fs::exists(temp));
    return Status(StatusCode::kParseError, "simulated failure half way");
  });
  EXPECT_EQ(s.message(), "simulated failure half way");
  EXPECT_EQ(Slurp(path), "old\n");
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_EQ(FileCount(), 1u);
}

TEST_F(AtomicFileTest, NewTargetAbsentAfterFailure) {
  const std::string path = Path("never.csv");
  Status s = WriteFileAtomic(path, [](AtomicFileWriter& w) -> Status {
    TPCAL_RETURN_IF_ERROR(w.Write("partial"));
    return Status(StatusCode::kIoError, "disk full (simulated)");
  });
  EXPECT_FALSE(s.ok());
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(FileCount(), 0u);
}

TEST_F(AtomicFileTest, UncommittedWriterCleansUp) {
  const std::string path = Path("x.txt");
  std::string temp;
  {
    Result<AtomicFileWriter> w = AtomicFileWriter::Open(path);
    ASSERT_TRUE(w.ok());
    temp = w->temp_path();
    ASSERT_TRUE(w->Write("abc").ok());
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(AtomicFileTest, RenameFailureRemovesTempAndReports) {
  // The target is a non-empty directory: rename(2) must fail; nothing may be left behind.
  const std::string path = Path("target_dir");
  fs::create_directories(path);
  std::ofstream(path + "/keep") << "x";
  Status s = WriteFileAtomic(path, "data");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_EQ(s.file(), path);
  EXPECT_NE(s.message().find("rename failed"), std::string::npos) << s.message();
  EXPECT_EQ(FileCount(), 1u);
  EXPECT_TRUE(fs::is_directory(path));
}

TEST_F(AtomicFileTest, MissingDirectoryIsAnIoError) {
  Status s = WriteFileAtomic(Path("no/such/dir/out.txt"), "x");
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_NE(s.message().find("creating the temp file"), std::string::npos);
}

TEST_F(AtomicFileTest, ViaThirdPartyWriter) {
  const std::string path = Path("via.ply");
  ASSERT_TRUE(WriteFileAtomicVia(path, [](const std::string& temp) -> Status {
                std::ofstream(temp) << "written by a library";
                return Status::Ok();
              }).ok());
  EXPECT_EQ(Slurp(path), "written by a library");
  Status s = WriteFileAtomicVia(path, [](const std::string& temp) -> Status {
    std::ofstream(temp) << "half";
    return Status(StatusCode::kInternal, "library failed");
  });
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(Slurp(path), "written by a library");
  EXPECT_EQ(FileCount(), 1u);
}

TEST_F(AtomicFileTest, KeepsPermissionsOfAnExistingTarget) {
  const std::string path = Path("perm.txt");
  ASSERT_TRUE(WriteFileAtomic(path, "a").ok());
  ASSERT_EQ(::chmod(path.c_str(), 0640), 0);
  ASSERT_TRUE(WriteFileAtomic(path, "b").ok());
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
}

}  // namespace
}  // namespace tpcal::pipeline
