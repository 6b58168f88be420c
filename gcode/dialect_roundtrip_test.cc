// The other dialects: golden files (tests/data/gcode/<piece>_<dialect><ext>, regenerated only by
// TPCAL_UPDATE_GOLDEN=1), the per-dialect whitelist checker, and the round trip: the same IR
// posted to LinuxCNC (run by rs274) and to Fanuc / Sinumerik / Heidenhain (read back by the
// small per-dialect readers) gives the same tool path in the part frame within 1 um.
#include <gtest/gtest.h>

#include <iostream>
#include <map>

#include "gcode/dialect_check.h"
#include "gcode/internal/test_support.h"
#include "gcode/nc_reader.h"

namespace tpcal::gcode {
namespace {

using testing::PieceCase;

constexpr double kPathTol_mm = 1e-3;    // requirement: 1 um
constexpr double kPathTol_deg = 1e-4;   // 4 rotary decimals: 5e-5 deg rounding

const std::filesystem::path kGoldenDir = std::filesystem::path(TPCAL_SOURCE_DIR) / "tests" / "data" / "gcode";

struct Case {
  PieceCase piece;
  Dialect dialect;
  FiveAxisMode five_axis;
  std::string Name() const {
    std::string n = piece.id + "_" + DialectName(dialect);
    if (piece.id == "cone" && five_axis != GcodeOptions::ForDialect(dialect).five_axis) {
      n += five_axis == FiveAxisMode::kToolCenterPoint ? "_tcp" : "_joint";
    }
    return n;
  }
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.Name(); }

std::vector<Case> AllCases() {
  std::vector<Case> cases;
  for (const PieceCase& pc : testing::AllPieces()) {
    for (Dialect d : {Dialect::kFanuc, Dialect::kLinuxCnc, Dialect::kSinumerik, Dialect::kHeidenhain}) {
      cases.push_back({pc, d, GcodeOptions::ForDialect(d).five_axis});
      if (pc.id == "cone" && d != Dialect::kLinuxCnc) {
        // The other five-axis mode of each control as well.
        const FiveAxisMode other = GcodeOptions::ForDialect(d).five_axis == FiveAxisMode::kToolCenterPoint
                                       ? FiveAxisMode::kJointInverseTime
                                       : FiveAxisMode::kToolCenterPoint;
        cases.push_back({pc, d, other});
      }
    }
  }
  return cases;
}

struct PostedRoundTrip {
  testpieces::TestPiece piece;
  PostedProgram program;
  GcodeOptions options;
  std::string error;
};

const PostedRoundTrip& PostedOf(const Case& c) {
  static std::map<std::string, PostedRoundTrip> cache;
  const std::string key = c.Name();
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  PostedRoundTrip& p = cache[key];
  auto piece = testing::MakePiece(c.piece);
  if (!piece.ok()) {
    p.error = piece.status().ToString();
    return p;
  }
  p.piece = *piece;
  p.options = testing::GoldenOptions(c.dialect, c.piece.id);
  p.options.five_axis = c.five_axis;
  auto prog = PostProgram(p.piece, p.options);
  if (!prog.ok()) {
    p.error = prog.status().ToString();
    return p;
  }
  p.program = *prog;
  testing::WriteFile(testing::OutputDir() / (key + ProgramExtension(c.dialect)), p.program.program_text);
  return p;
}

// The canonical path of the LinuxCNC program of a piece, by rs274.
const NcPath* LinuxCncPath(const PieceCase& pc, const std::string& rs274, std::string* error) {
  static std::map<std::string, std::pair<NcPath, std::string>> cache;
  auto it = cache.find(pc.id);
  if (it == cache.end()) {
    const PostedRoundTrip& p = PostedOf({pc, Dialect::kLinuxCnc, FiveAxisMode::kJointInverseTime});
    std::pair<NcPath, std::string> entry;
    if (!p.error.empty()) {
      entry.second = p.error;
    } else {
      const auto dir = testing::OutputDir() / "roundtrip";
      std::filesystem::create_directories(dir);
      const auto run = testing::RunRs274(rs274, dir, p.program);
      entry.second = Rs274Errors(run.exit_status, run.out, run.err);
      if (entry.second.empty()) {
        auto listing = ParseRs274Listing(run.out);
        if (listing.ok()) {
          entry.first = listing->path;
        } else {
          entry.second = listing.status().ToString();
        }
      }
    }
    it = cache.emplace(pc.id, entry).first;
  }
  *error = it->second.second;
  return error->empty() ? &it->second.first : nullptr;
}

class DialectProgram : public ::testing::TestWithParam<Case> {};

TEST_P(DialectProgram, MatchesGoldenFile) {
  const Case& c = GetParam();
  const PostedRoundTrip& p = PostedOf(c);
  ASSERT_TRUE(p.error.empty()) << p.error;
  const auto golden = kGoldenDir / (c.Name() + ProgramExtension(c.dialect));
  if (testing::UpdateGolden()) {
    std::filesystem::create_directories(kGoldenDir);
    testing::WriteFile(golden, p.program.program_text);
    if (c.dialect == Dialect::kLinuxCnc) {
      testing::WriteFile(kGoldenDir / (c.Name() + ".tbl"), p.program.tool_table_text);
    }
    std::cout << "[golden] wrote " << golden << "\n";
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(golden))
      << golden << " is missing: regenerate with TPCAL_UPDATE_GOLDEN=1 and review the diff";
  EXPECT_EQ(testing::ReadFile(golden), p.program.program_text)
      << "posted program differs from " << golden << " (if intended: TPCAL_UPDATE_GOLDEN=1, review the diff)";
  if (c.dialect == Dialect::kLinuxCnc) {
    EXPECT_EQ(testing::ReadFile(kGoldenDir / (c.Name() + ".tbl")), p.program.tool_table_text);
  }
}

TEST_P(DialectProgram, UsesOnlyWordsTheControlAccepts) {
  const Case& c = GetParam();
  const PostedRoundTrip& p = PostedOf(c);
  ASSERT_TRUE(p.error.empty()) << p.error;
  auto rep = CheckDialectSyntax(p.program.program_text, p.options);
  ASSERT_TRUE(rep.ok()) << c.Name() << ": " << rep.status().ToString();
  if (c.dialect == Dialect::kHeidenhain) {
    EXPECT_GE(rep->blocks, p.program.posted.block_count) << "Heidenhain numbers comment lines too";
  } else {
    EXPECT_EQ(rep->blocks, p.program.posted.block_count) << "every block the post wrote carries its N number";
  }
}

TEST_P(DialectProgram, ReadsBackToTheLinuxCncCanonicalPath) {
  const Case& c = GetParam();
  TPCAL_REQUIRE_RS274(rs274);
  const PostedRoundTrip& p = PostedOf(c);
  ASSERT_TRUE(p.error.empty()) << p.error;
  std::string error;
  const NcPath* reference = LinuxCncPath(c.piece, rs274, &error);
  ASSERT_NE(reference, nullptr) << error;
  auto read = ReadNcProgram(p.program.program_text, p.options);
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  const auto ref_points = ToPartPoints(*reference, p.piece.machine);
  const auto points = ToPartPoints(*read, p.piece.machine);
  auto cmp = ComparePaths(ref_points, points, kPathTol_mm, kPathTol_deg);
  ASSERT_TRUE(cmp.ok()) << c.Name() << ": " << cmp.status().ToString();
  EXPECT_EQ(read->tool_changes, static_cast<int>(p.program.ir.tools.size()));
  std::cout << "[roundtrip " << c.Name() << "] " << cmp->points << " points, max tool-point deviation "
            << cmp->max_tip_deviation_mm * 1000.0 << " um, rotary " << cmp->max_rotary_deviation_deg
            << " deg, arc centres " << cmp->max_center_deviation_mm * 1000.0 << " um vs rs274\n";
}

INSTANTIATE_TEST_SUITE_P(AllPiecesAllDialects, DialectProgram, ::testing::ValuesIn(AllCases()),
                         [](const auto& info) { return info.param.Name(); });

}  // namespace
}  // namespace tpcal::gcode
