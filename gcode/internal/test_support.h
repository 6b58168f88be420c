// Test support for gcode/*_test.cc (header only, not part of the library): the test pieces of
// the proofs, the rs274 runner, golden-file handling, output directory.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "gcode/post_program.h"
#include "gcode/rs274_canon.h"
#include "kinematics/machine_yaml.h"
#include "testpieces/test_piece.h"

namespace tpcal::gcode::testing {

struct PieceCase {
  std::string id;        // file stem of goldens and outputs: "turning", "m1_160", ...
  std::string machine;   // samples/machines/<machine>.yaml
};

// gtest prints the parameter in test names (and CTest names): the id, not the bytes.
inline void PrintTo(const PieceCase& pc, std::ostream* os) { *os << pc.id; }

inline std::vector<PieceCase> AllPieces() {
  return {{"turning", "ac_table"}, {"m1_160", "xyz"}, {"m1_320", "xyz"}, {"m2", "xyz"}, {"cone", "ac_table"}};
}

inline testpieces::PieceConfig ConfigOf(const std::string& id) {
  testpieces::PieceConfig c;
  if (id == "turning") c.params = testpieces::TurningPieceParams{};
  if (id == "m1_160") c.params = testpieces::ContourPieceParams::ForSize(160.0);
  if (id == "m1_320") c.params = testpieces::ContourPieceParams::ForSize(320.0);
  if (id == "m2") c.params = testpieces::FaceMillingPieceParams{};
  if (id == "cone") c.params = testpieces::ConeFrustumParams{};
  return c;
}

inline Result<testpieces::TestPiece> MakePiece(const PieceCase& pc) {
  auto machine = kinematics::LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/" + pc.machine + ".yaml");
  if (!machine.ok()) return machine.status();
  return testpieces::MakeTestPiece(ConfigOf(pc.id), *machine);
}

// Options of the golden files: fixed date, program name from the piece.
inline GcodeOptions GoldenOptions(Dialect d, const std::string& id) {
  GcodeOptions o = GcodeOptions::ForDialect(d);
  std::string name = "TP_";
  for (char ch : id) name += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  o.program_name = name;
  o.date = "2025-01-01";
  return o;
}

// Where tests write their outputs (the test's working directory: the build tree under ctest).
inline std::filesystem::path OutputDir() {
  const std::filesystem::path p = std::filesystem::current_path() / "gcode_test_output";
  std::filesystem::create_directories(p);
  return p;
}

// Writes through a temp file and a rename: ctest runs the cases of one suite as parallel
// processes, some of which write the same output file.
inline void WriteFile(const std::filesystem::path& p, const std::string& text) {
  const std::filesystem::path tmp = p.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
  }
  std::filesystem::rename(tmp, p);
}

// A directory of its own for the running test (ctest runs every case as its own process, in
// parallel: rs274 runs of two cases must not share program and listing files).
inline std::filesystem::path TestDir(const std::filesystem::path& parent) {
  std::string name = "run";
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
    name = std::string(info->test_suite_name()) + "." + info->name();
  }
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '_' && ch != '-') ch = '_';
  }
  const std::filesystem::path dir = parent / name;
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline bool UpdateGolden() {
  const char* v = std::getenv("TPCAL_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

// rs274 on PATH (or /usr/bin/rs274); "" if absent.
inline std::string Rs274Path() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  dirs += ":/usr/bin";
  std::stringstream ss(dirs);
  for (std::string d; std::getline(ss, d, ':');) {
    const std::filesystem::path p = std::filesystem::path(d) / "rs274";
    if (!d.empty() && std::filesystem::exists(p)) return p.string();
  }
  return "";
}

inline bool AllowNoRs274() {
  const char* v = std::getenv("TPCAL_ALLOW_NO_RS274");
  return v && std::string(v) == "1";
}

struct Rs274Run {
  int exit_status = -1;
  std::string out, err;
};

// Writes PROGRAM.ngc and PROGRAM.tbl into a directory of the running test under `parent`
// (TestDir) and runs `rs274 -g PROGRAM.ngc -t PROGRAM.tbl` there (default -n: stop at the first
// error), with HOME set to that directory (see below).
template <class Posted>  // PostedProgram or PostedInstrumentProgram: program_file / _text, tool_table_file / _text
Rs274Run RunRs274(const std::string& rs274, const std::filesystem::path& parent, const Posted& p) {
  const std::filesystem::path dir = TestDir(parent);
  WriteFile(dir / p.program_file, p.program_text);
  WriteFile(dir / p.tool_table_file, p.tool_table_text);
  const std::string out = (dir / (p.program_file + ".canon")).string();
  const std::string err = (dir / (p.program_file + ".stderr")).string();
  // HOME: rs274 (LinuxCNC 2.9) keeps its tool data in a shared mmap file $HOME/.tool.mmap;
  // parallel runs sharing it read each other's tool tables ("tool not found", SIGBUS).
  const std::string cmd = "cd '" + dir.string() + "' && HOME='" + dir.string() + "' '" + rs274 + "' -g '" + p.program_file + "' -t '" +
                          p.tool_table_file + "' > '" + out + "' 2> '" + err + "' < /dev/null";
  Rs274Run run;
  const int rc = std::system(cmd.c_str());
  run.exit_status = rc == -1 ? -1 : WEXITSTATUS(rc);
  run.out = ReadFile(out);
  run.err = ReadFile(err);
  return run;
}

// Fails the test when rs274 is missing, unless TPCAL_ALLOW_NO_RS274=1 (then skips).
#define TPCAL_REQUIRE_RS274(var)                                                              \
  const std::string var = ::tpcal::gcode::testing::Rs274Path();                              \
  if (var.empty()) {                                                                         \
    if (::tpcal::gcode::testing::AllowNoRs274()) GTEST_SKIP() << "rs274 not installed";       \
    FAIL() << "LinuxCNC's rs274 is not installed (apt-get install --no-install-recommends "    \
              "linuxcnc-uspace); set TPCAL_ALLOW_NO_RS274=1 to skip locally";                 \
  }

}  // namespace tpcal::gcode::testing
