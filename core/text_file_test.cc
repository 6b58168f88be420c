#include "core/text_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace tpcal {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))).string();
}

TEST(TextFile, ReadsAFile) {
  const std::string path = TempPath("tpcal_text_file");
  std::ofstream(path, std::ios::binary) << "schema: x\n";
  Result<std::string> text = ReadTextFile(path, "cannot open it");
  ASSERT_TRUE(text.ok()) << text.status().ToString();
  EXPECT_EQ(*text, "schema: x\n");
  std::remove(path.c_str());
}

TEST(TextFile, MissingFileGivesTheCallersMessage) {
  Result<std::string> text = ReadTextFile("/nonexistent/tpcal.yaml", "cannot open pipeline file");
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.status().ToString(), "/nonexistent/tpcal.yaml: cannot open pipeline file");
}

TEST(TextFile, FifoAndDirectoryAreRefusedWithoutBlocking) {
  const std::string fifo = TempPath("tpcal_fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  Result<std::string> text = ReadTextFile(fifo, "cannot open");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.status().ToString(), fifo + ": not a regular file");
  std::remove(fifo.c_str());
  Result<std::string> dir = ReadTextFile(std::filesystem::temp_directory_path().string(), "cannot open");
  ASSERT_FALSE(dir.ok());
  EXPECT_EQ(dir.status().message(), "not a regular file");
}

TEST(TextFile, AboveTheLimitFailsBeforeReading) {
  const std::string path = TempPath("tpcal_text_big");
  std::ofstream(path, std::ios::binary) << std::string(1000, 'x');
  Result<std::string> text = ReadTextFile(path, "cannot open", 999);
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.status().code(), StatusCode::kParseError);
  EXPECT_EQ(text.status().message(), "file of 1000 bytes; expected at most 999 bytes for this kind of file");
  EXPECT_TRUE(ReadTextFile(path, "cannot open", 1000).ok());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace tpcal
