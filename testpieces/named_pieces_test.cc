#include "testpieces/named_pieces.h"

#include <gtest/gtest.h>

#include "testpieces/piece_config.h"

namespace tpcal::testpieces {
namespace {

// The enriched names stand for exactly the sample configurations a user can copy and edit.
TEST(NamedPieces, EnrichedNamesAreTheSampleConfigurations) {
  const std::string dir = std::string(TPCAL_SOURCE_DIR) + "/samples/testpieces/";
  for (const char* name : {"turning_enriched", "cone_frustum_enriched", "iso10791_m1_160", "iso10791_m1_320",
                           "iso10791_m2", "cone_frustum"}) {
    auto named = NamedPieceConfig(name);
    ASSERT_TRUE(named.ok()) << named.status().ToString();
    auto sample = LoadPieceConfig(dir + name + ".yaml");
    ASSERT_TRUE(sample.ok()) << sample.status().ToString();
    EXPECT_EQ(FormatPieceConfig(named->config), FormatPieceConfig(*sample)) << name;
  }
  auto turning = NamedPieceConfig("turning");
  ASSERT_TRUE(turning.ok());
  auto seed002 = LoadPieceConfig(dir + "turning_seed002.yaml");
  ASSERT_TRUE(seed002.ok());
  EXPECT_EQ(FormatPieceConfig(turning->config), FormatPieceConfig(*seed002));
}

TEST(NamedPieces, EveryNameBuildsAndUnknownNamesListTheChoices) {
  for (const auto& name : PieceNames()) {
    auto named = NamedPieceConfig(name);
    ASSERT_TRUE(named.ok()) << name << ": " << named.status().ToString();
    EXPECT_TRUE(named->config.Validate().ok()) << name;
    const bool five_axis = KindOf(named->config.params) == PieceKind::kTurning ||
                           KindOf(named->config.params) == PieceKind::kConeFrustum;
    EXPECT_EQ(named->usual_machine, five_axis ? kinematics::MachineType::kAcTable : kinematics::MachineType::kXyz) << name;
  }
  auto bad = NamedPieceConfig("cone");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find("cone_frustum_enriched"), std::string::npos) << bad.status().message();
}

TEST(NamedPieces, AConfigFileMustDescribeTheNamedPiece) {
  auto cone = NamedPieceConfig("cone_frustum_enriched");
  auto m1_160 = NamedPieceConfig("iso10791_m1_160");
  auto m1_any = NamedPieceConfig("iso10791_m1");
  ASSERT_TRUE(cone.ok() && m1_160.ok() && m1_any.ok());
  EXPECT_TRUE(CheckConfigMatchesName(NamedPieceConfig("cone_frustum")->config, *cone, "cone_frustum_enriched", "c.yaml").ok());
  const Status wrong_kind = CheckConfigMatchesName(m1_160->config, *cone, "cone_frustum_enriched", "c.yaml");
  ASSERT_FALSE(wrong_kind.ok());
  EXPECT_EQ(wrong_kind.file(), "c.yaml");
  EXPECT_NE(wrong_kind.message().find("but --testpiece is cone_frustum_enriched"), std::string::npos);
  PieceConfig big;
  big.params = ContourPieceParams::ForSize(320.0);
  const Status wrong_size = CheckConfigMatchesName(big, *m1_160, "iso10791_m1_160", "m1.yaml");
  ASSERT_FALSE(wrong_size.ok());
  EXPECT_NE(wrong_size.message().find("size 320 mm"), std::string::npos) << wrong_size.message();
  EXPECT_TRUE(CheckConfigMatchesName(big, *m1_any, "iso10791_m1", "m1.yaml").ok());  // the plain name fixes no size
}

}  // namespace
}  // namespace tpcal::testpieces
