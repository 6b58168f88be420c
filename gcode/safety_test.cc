// The safety checks catch what they are for, and name the block: a rapid through the stock,
// a target outside a stroke, a reamer that does not match its hole, an end mill too wide for
// the groove. Each violation is built into an otherwise valid test piece.
#include "gcode/safety.h"

#include <gtest/gtest.h>

#include <regex>

#include "core/units.h"
#include "gcode/internal/test_support.h"
#include "testpieces/piece_config.h"

namespace tpcal::gcode {
namespace {

testpieces::TestPiece Piece(const std::string& id) {
  for (const auto& pc : testing::AllPieces()) {
    if (pc.id == id) {
      auto p = testing::MakePiece(pc);
      EXPECT_TRUE(p.ok()) << p.status().ToString();
      return *p;
    }
  }
  ADD_FAILURE() << id;
  return {};
}

// Turning piece options without the rapid check (the known defect below would be reported first).
GcodeOptions TurningOptions(Dialect d) {
  GcodeOptions o = GcodeOptions::ForDialect(d);
  o.safety.check_rapids = false;
  return o;
}

// The block label at the start of the message ("N1230: ...").
std::string BlockOf(const Status& s) {
  std::smatch m;
  const std::string msg = s.message();
  if (std::regex_search(msg, m, std::regex(R"((N\d+): )"))) return m[1];
  return "";
}

TEST(Safety, EveryPieceIsSafeInEveryDialect) {
  for (const auto& pc : testing::AllPieces()) {
    auto piece = testing::MakePiece(pc);
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    for (Dialect d : {Dialect::kFanuc, Dialect::kLinuxCnc, Dialect::kSinumerik, Dialect::kHeidenhain}) {
      auto p = PostProgram(*piece, GcodeOptions::ForDialect(d));
      ASSERT_TRUE(p.ok()) << pc.id << " " << DialectName(d) << ": " << p.status().ToString();
      EXPECT_GT(p->safety.rapids_checked, 0);
      EXPECT_GE(p->safety.min_rapid_clearance_mm, -GcodeOptions().safety.rapid_tolerance_mm);
      if (d == Dialect::kLinuxCnc) std::cout << "[safety] " << pc.id << ": " << p->Summary() << "\n";
    }
  }
}

TEST(Safety, RapidThroughTheStockNamesTheBlock) {
  testpieces::TestPiece piece = Piece("m2");
  // Make the approach of pass 1 a rapid straight down into the block (instead of beside it).
  bool changed = false;
  for (auto& pass : piece.operations[0].passes) {
    for (auto& m : pass.moves) {
      if (!changed && m.kind == testpieces::MoveKind::kRapid && m.end.z_mm < m.start.z_mm - 1.0) {
        m.end.x_mm = 0.0;  // the middle of the block
        m.end.z_mm -= 10.0;
        changed = true;
      }
    }
  }
  ASSERT_TRUE(changed);
  auto p = PostProgram(piece, GcodeOptions::ForDialect(Dialect::kFanuc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("rapid move enters the stock envelope"), std::string::npos) << p.status().message();
  const std::string block = BlockOf(p.status());
  ASSERT_FALSE(block.empty()) << p.status().message();
  // The named block is the offending G00 of the posted program.
  GcodeOptions off = GcodeOptions::ForDialect(Dialect::kFanuc);
  off.safety.check_rapids = false;
  auto unchecked = PostProgram(piece, off);
  ASSERT_TRUE(unchecked.ok());
  const std::size_t at = unchecked->program_text.find("\n" + block + " ");
  ASSERT_NE(at, std::string::npos);
  const std::string line = unchecked->program_text.substr(at + 1, unchecked->program_text.find('\n', at + 1) - at - 1);
  EXPECT_NE(line.find("G00"), std::string::npos) << line;
  EXPECT_NE(line.find("X0."), std::string::npos) << line;
}

// The retract height is a YAML key of every piece (safe_clearance_mm): the program's rapids
// climb to top + clearance and pass the rapid check; a clearance that is not positive is refused
// with its key.
TEST(Safety, SafeClearanceComesFromTheConfig) {
  auto machine = kinematics::LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/xyz.yaml");
  ASSERT_TRUE(machine.ok()) << machine.status().ToString();
  auto highest_rapid_z = [](const testpieces::TestPiece& piece) {
    double z = -1e9;
    for (const auto& op : piece.operations) {
      for (const auto& pass : op.passes) {
        for (const auto& m : pass.moves) {
          if (m.kind == testpieces::MoveKind::kRapid) z = std::max(z, m.end.z_mm);
        }
      }
    }
    return z;
  };
  for (double clearance_mm : {25.0, 40.0}) {
    auto config = testpieces::ParsePieceConfig(
        "piece: iso10791_m2\niso10791_m2:\n  safe_clearance_mm: " + std::to_string(clearance_mm) + "\n", "<m2.yaml>");
    ASSERT_TRUE(config.ok()) << config.status().ToString();
    auto piece = testpieces::MakeTestPiece(*config, *machine);
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    const double top_mm = std::get<testpieces::FaceMillingPieceParams>(config->params).height_mm;
    EXPECT_NEAR(highest_rapid_z(*piece), top_mm + clearance_mm, 1e-9) << clearance_mm;
    auto p = PostProgram(*piece, GcodeOptions::ForDialect(Dialect::kFanuc));
    ASSERT_TRUE(p.ok()) << p.status().ToString();
  }
  auto low = testpieces::ParsePieceConfig("piece: iso10791_m2\niso10791_m2:\n  safe_clearance_mm: -1\n", "<m2.yaml>");
  ASSERT_FALSE(low.ok());
  EXPECT_NE(low.status().message().find("safe_clearance_mm"), std::string::npos) << low.status().message();
}

TEST(Safety, StrokeViolationNamesAxisAndBlock) {
  testpieces::TestPiece piece = Piece("turning");
  // A machine whose A axis cannot reach -90 deg (A = -90 turning of S3/B3, S6/B6).
  for (auto& l : piece.machine.links) {
    if (l.axis == kinematics::Axis::kA) l.min_position = DegToRad(-60.0);
  }
  auto p = PostProgram(piece, TurningOptions(Dialect::kSinumerik));
  ASSERT_FALSE(p.ok());
  EXPECT_FALSE(BlockOf(p.status()).empty()) << p.status().message();
  EXPECT_NE(p.status().message().find("travel"), std::string::npos) << p.status().message();
  EXPECT_NE(p.status().message().find("A"), std::string::npos);
}

TEST(Safety, ReamerMustMatchTheHole) {
  testpieces::TestPiece piece = Piece("turning");
  for (auto& op : piece.operations) {
    if (op.tool.kind == testpieces::ToolKind::kReamer) op.tool.diameter_mm = 10.5;  // hole is 10.7
  }
  auto p = PostProgram(piece, TurningOptions(Dialect::kLinuxCnc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("does not match hole H1"), std::string::npos) << p.status().message();
  EXPECT_FALSE(BlockOf(p.status()).empty());
}

TEST(Safety, EndMillMustFitTheGroove) {
  testpieces::TestPiece piece = Piece("turning");
  const auto& params = std::get<testpieces::TurningPieceParams>(piece.config.params);
  auto* sr = const_cast<testpieces::FeatureCut*>(piece.Cut("S_R"));
  ASSERT_NE(sr, nullptr);
  std::get<testpieces::PathMillCut>(sr->model).tool_radius_mm =
      0.5 * (params.groove_outer_radius_mm - params.groove_inner_radius_mm) + 0.5;
  auto p = PostProgram(piece, TurningOptions(Dialect::kHeidenhain));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("groove width"), std::string::npos) << p.status().message();
  // Heidenhain blocks are named by their line number.
  EXPECT_TRUE(std::regex_search(p.status().message(), std::regex(R"(\.h: \d+: )"))) << p.status().message();
}

TEST(Safety, ConcaveRadiusLimitsTheEndMill) {
  testpieces::TestPiece piece = Piece("m1_160");
  auto* bore = const_cast<testpieces::FeatureCut*>(piece.Cut("BORE"));
  ASSERT_NE(bore, nullptr);
  std::get<testpieces::PathMillCut>(bore->model).tool_radius_mm = piece.Feature("BORE")->radius_mm + 1.0;
  auto p = PostProgram(piece, GcodeOptions::ForDialect(Dialect::kLinuxCnc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("concave face BORE"), std::string::npos) << p.status().message();
}

TEST(Stock, EnvelopeSignsAndNames) {
  testpieces::TestPiece piece = Piece("turning");
  auto stock = StockOf(piece);
  ASSERT_TRUE(stock.ok());
  const auto& p = std::get<testpieces::TurningPieceParams>(piece.config.params);
  std::string name;
  // Inside S1's raw stock, in the groove, in a hole, above the top.
  EXPECT_LT(stock->SignedDistance({p.steps[0].radius_mm + 0.5 * p.turning_depth_of_cut_mm, 0, 400}, &name), 0);
  EXPECT_NEAR(stock->SignedDistance({0.5 * (p.groove_inner_radius_mm + p.groove_outer_radius_mm), 0,
                                     p.groove_bottom_z_mm + 1.0}),
              1.0, 1e-9);  // in the groove, 1 mm above its floor
  EXPECT_GT(stock->SignedDistance({p.hole_pitch_radius_mm, 0, p.top_z_mm() - 1}), 0);
  EXPECT_NEAR(stock->SignedDistance({0, 150, p.top_z_mm() + 5}), 5.0, 1e-9);
}

}  // namespace
}  // namespace tpcal::gcode
