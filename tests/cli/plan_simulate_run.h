// Test helpers of the plan / simulate CLI tests: run the built `tpcal` (TPCAL_EXE) in a fresh
// temporary directory and collect its exit code, stdout and stderr.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace tpcal::cli_test {

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string ReadText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void WriteText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

inline std::string Source(const std::string& relative) { return std::string(TPCAL_SOURCE_DIR) + "/" + relative; }

// A fresh directory per test, removed at the end unless the test failed.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (std::filesystem::temp_directory_path() / "tpcal_cli_XXXXXX").string();
    ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir_);
    else std::cerr << "outputs kept in " << dir_ << "\n";
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs `tpcal ARGS` in the test directory (arguments are passed through the shell: no blanks
  // or quotes inside one argument).
  RunResult Run(const std::string& args) const {
    const std::string cmd = "cd '" + dir_.string() + "' && '" + std::string(TPCAL_EXE) + "' " + args + " > stdout.txt 2> stderr.txt";
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = ReadText(dir_ / "stdout.txt");
    r.err = ReadText(dir_ / "stderr.txt");
    return r;
  }

  std::filesystem::path dir_;
};

}  // namespace tpcal::cli_test
