// WriteDirectoryAtomic (run_output.h): a new directory, a replaced previous run, a refused
// unrelated directory, and the siblings a killed run leaves: removed by the next run when their
// process is gone, kept while it lives.
#include "pipeline/run_output.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

std::string ReadRunOutputText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A pid no process has: a child that has exited and been reaped.
pid_t DeadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST(RunOutput, ReplacesAPreviousRunWhole) {
  const fs::path dir = fs::path(testing::TempDir()) / "tpcal_run_output_replace";
  fs::remove_all(dir);
  const std::string out = (dir / "out").string();
  ASSERT_TRUE(WriteDirectoryAtomic(out, {{"result.json", "{1}"}, {"figures/a.svg", "<svg/>"}}).ok());
  ASSERT_TRUE(WriteDirectoryAtomic(out, {{"result.json", "{2}"}}).ok());
  EXPECT_EQ(ReadRunOutputText(dir / "out" / "result.json"), "{2}");
  EXPECT_FALSE(fs::exists(dir / "out" / "figures"));  // nothing of the old run is mixed in
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += e.path().filename() != "out";
  EXPECT_EQ(entries, 0u);  // no temporary sibling left
  fs::create_directories(dir / "notes");
  std::ofstream(dir / "notes" / "keep.txt") << "keep";
  EXPECT_FALSE(WriteDirectoryAtomic((dir / "notes").string(), {{"result.json", "{}"}}).ok());
  EXPECT_EQ(ReadRunOutputText(dir / "notes" / "keep.txt"), "keep");
  fs::remove_all(dir);
}

TEST(RunOutput, StaleSiblingsOfAKilledRunAreRemoved) {
  const fs::path dir = fs::path(testing::TempDir()) / "tpcal_run_output_stale";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const pid_t dead = DeadPid(), alive = ::getppid();
  const fs::path stale_tmp = dir / ("out.tmp." + std::to_string(dead) + ".0badc0de");
  const fs::path stale_old = dir / ("out.old." + std::to_string(dead) + ".12345678");
  const fs::path live_tmp = dir / ("out.tmp." + std::to_string(alive) + ".feedface");
  const fs::path other = dir / ("other.tmp." + std::to_string(dead) + ".0badc0de");
  for (const auto& p : {stale_tmp, stale_old, live_tmp, other}) fs::create_directories(p / "figures");
  ASSERT_TRUE(WriteDirectoryAtomic((dir / "out").string(), {{"result.json", "{}"}}).ok());
  EXPECT_FALSE(fs::exists(stale_tmp));
  EXPECT_FALSE(fs::exists(stale_old));
  EXPECT_TRUE(fs::exists(live_tmp));  // a run in progress elsewhere
  EXPECT_TRUE(fs::exists(other));     // another output's siblings are not ours to touch
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tpcal::pipeline
