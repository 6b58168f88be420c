#include "pipeline/piece_loader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

std::string WriteTemp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("tpcal_piece_loader_" + name);
  std::ofstream(p) << text;
  return p.string();
}

TEST(PieceLoader, NameGivesTheUsualNominalMachine) {
  auto turning = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(turning.ok()) << turning.status().ToString();
  EXPECT_EQ(turning->machine.type, kinematics::MachineType::kAcTable);
  auto m2 = LoadPiece({.testpiece = "iso10791_m2"});
  ASSERT_TRUE(m2.ok()) << m2.status().ToString();
  EXPECT_EQ(m2->machine.type, kinematics::MachineType::kXyz);
}

TEST(PieceLoader, UnknownNameIsWordedAsTheCommandAsks) {
  auto plain = LoadPiece({.testpiece = "gear"});
  ASSERT_FALSE(plain.ok());
  EXPECT_EQ(plain.status().ToString().rfind("unknown test piece 'gear' (expected one of: turning, ", 0), 0u);
  PieceRequest r{.testpiece = "gear"};
  r.wording = {.unknown_name_prefix = "--testpiece: ", .unknown_name_suffix = " (or --config FILE)",
               .unknown_name_file = "tpcal x"};
  auto worded = LoadPiece(r);
  ASSERT_FALSE(worded.ok());
  const std::string s = worded.status().ToString();
  EXPECT_EQ(s.rfind("tpcal x: --testpiece: unknown test piece 'gear'", 0), 0u) << s;
  EXPECT_EQ(s.substr(s.size() - 19), " (or --config FILE)") << s;
  auto run_style = LoadPiece({.testpiece = "gear", .allow_piece_file = true});
  ASSERT_FALSE(run_style.ok());
  EXPECT_NE(run_style.status().message().find(", or a tpcal.testpiece/1 file)"), std::string::npos);
}

TEST(PieceLoader, ConfigMustDescribeTheNamedPieceUnlessAskedOtherwise) {
  const std::string cone = WriteTemp("cone.yaml", "schema: tpcal.testpiece/1\npiece: cone_frustum\n");
  auto mismatch = LoadPiece({.testpiece = "iso10791_m2", .config_path = cone});
  ASSERT_FALSE(mismatch.ok());
  EXPECT_EQ(mismatch.status().file(), cone);
  EXPECT_NE(mismatch.status().message().find("the configuration is for the cone_frustum piece"), std::string::npos);
  auto any = LoadPiece({.testpiece = "iso10791_m2", .config_path = cone, .config_must_match_name = false});
  ASSERT_TRUE(any.ok()) << any.status().ToString();
  EXPECT_EQ(any->piece.kind(), testpieces::PieceKind::kConeFrustum);
  EXPECT_EQ(any->machine.type, kinematics::MachineType::kAcTable);  // the configuration's usual machine
}

TEST(PieceLoader, ConfigFileErrorsCarryFileAndLine) {
  const std::string typo = WriteTemp("typo.yaml", "schema: tpcal.testpiece/1\npiece: iso10791_m2\niso10791_m2:\n  size_mmm: 3\n");
  auto r = LoadPiece({.testpiece = "iso10791_m2", .config_path = typo});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().ToString().rfind(typo + ":4: ", 0), 0u) << r.status().ToString();
}

TEST(PieceLoader, PieceFileOnlyWhereAllowed) {
  const std::string file = WriteTemp("m2.yml", "schema: tpcal.testpiece/1\npiece: iso10791_m2\n");
  auto allowed = LoadPiece({.testpiece = file, .allow_piece_file = true});
  ASSERT_TRUE(allowed.ok()) << allowed.status().ToString();
  EXPECT_EQ(allowed->piece.kind(), testpieces::PieceKind::kFaceMillingM2);
  EXPECT_FALSE(LoadPiece({.testpiece = file}).ok());
}

TEST(PieceLoader, DensityOverridesTheProbing) {
  auto dense = LoadPiece({.testpiece = "turning", .density = "dense", .levels = 2});
  ASSERT_TRUE(dense.ok()) << dense.status().ToString();
  EXPECT_EQ(dense->piece.config.probing.points_per_circle, testpieces::ProbingOptions::Dense().points_per_circle);
  EXPECT_EQ(dense->piece.config.probing.levels_per_face, 2);
  auto n = LoadPiece({.testpiece = "turning", .density = "20"});
  ASSERT_TRUE(n.ok()) << n.status().ToString();
  EXPECT_EQ(n->piece.config.probing.points_per_circle, 20);
  EXPECT_EQ(n->piece.config.probing.points_per_hole, 10);
  auto bad = LoadPiece({.testpiece = "turning", .density = "2"});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message(), "--density: expected paper, dense or a number of points per circle >= 3, got '2'");
  EXPECT_FALSE(LoadPiece({.testpiece = "turning", .levels = -1}).ok());
  auto zero = LoadPiece({.testpiece = "turning", .levels = 0});  // given, so not "as configured"
  ASSERT_FALSE(zero.ok());
  EXPECT_EQ(zero.status().message(), "--levels: expected a number of probing levels per face >= 1, got 0");
}

TEST(PieceLoader, APlanBeyondTheBoundIsRefusedNamingTheOption) {
  auto huge = LoadPiece({.testpiece = "turning", .density = "1000000000"});
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.status().message().rfind("--density 1000000000: the probing plan of the ", 0), 0u)
      << huge.status().message();
  auto levels = LoadPiece({.testpiece = "turning", .density = "dense", .levels = 1'000'000});
  ASSERT_FALSE(levels.ok());
  EXPECT_EQ(levels.status().message().rfind("--density dense --levels 1000000: ", 0), 0u) << levels.status().message();
  const std::string config =
      WriteTemp("huge.yaml", "schema: tpcal.testpiece/1\npiece: turning\nprobing:\n  points_per_circle: 100000000\n");
  auto from_file = LoadPiece({.testpiece = "turning", .config_path = config});
  ASSERT_FALSE(from_file.ok());
  EXPECT_EQ(from_file.status().file(), config);
}

TEST(PieceLoader, PieceErrorsAreNamedAndLocatedAsAsked) {
  // A 3-axis machine whose X stroke is too short for the M2 piece: building the piece fails.
  const std::string machine = WriteTemp(
      "short_x.yaml",
      "schema: tpcal.machine/1\nname: short X\ntype: xyz\nworkpiece_chain: [Y, X]\ntool_chain: [Z]\naxes:\n"
      "  X: {min_mm: -50, max_mm: 50}\n  Y: {min_mm: -200, max_mm: 200}\n  Z: {min_mm: -10, max_mm: 500}\n");
  auto bare = LoadPiece({.testpiece = "iso10791_m2", .machine_path = machine});
  ASSERT_FALSE(bare.ok());
  EXPECT_TRUE(bare.status().file().empty()) << bare.status().ToString();
  PieceRequest r{.testpiece = "iso10791_m2", .machine_path = machine};
  r.wording.name_piece_errors = true;
  r.wording.locate_piece_errors = PieceErrorWording::Locate::kConfigElseMachine;
  auto worded = LoadPiece(r);
  ASSERT_FALSE(worded.ok());
  EXPECT_EQ(worded.status().file(), machine);
  EXPECT_EQ(worded.status().message(), "test piece iso10791_m2: " + bare.status().message());
  r.wording.locate_piece_errors = PieceErrorWording::Locate::kConfig;  // no configuration file given
  EXPECT_TRUE(LoadPiece(r).status().file().empty());
}

}  // namespace
}  // namespace tpcal::pipeline
