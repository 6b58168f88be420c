#include "pipeline/io/dmis_reader.h"

#include <gtest/gtest.h>

#include "core/units.h"
#include "pipeline/io/xyzijk_reader.h"

namespace tpcal::pipeline {
namespace {

TEST(DmisReader, FeatureOfLabelStripsOnePointSuffix) {
  EXPECT_EQ(DmisFeatureOfLabel("S_R_12"), "S_R");
  EXPECT_EQ(DmisFeatureOfLabel("H1_3"), "H1");
  EXPECT_EQ(DmisFeatureOfLabel("P_2_5"), "P_2");
  EXPECT_EQ(DmisFeatureOfLabel("H1"), "H1");
  EXPECT_EQ(DmisFeatureOfLabel("S_R"), "S_R");
  EXPECT_EQ(DmisFeatureOfLabel("_3"), "_3");
  EXPECT_EQ(DmisFeatureOfLabel("A_"), "A_");
}

TEST(DmisReader, ReadsPointActualsContinuationsCommentsAndUnits) {
  const std::string text =
      "$$ output of a CMM\n"
      "FILNAM/'turning plan',05.3\n"
      "units/mm,angdec\n"
      "FA(S_R_1)=FEAT/POINT,CART,1.5,2,3,0,0,1\n"
      "fa(S_R_2) = feat/point, cart, 4, 5, $\n"
      "   6, 1, 0, 0 $$ continued\n"
      "FA(S_R)=FEAT/CIRCLE,OUTER,CART,0,0,0,0,0,1,50\n"
      "OUTPUT/FA(S_R_1)\n"
      "UNITS/INCH,ANGDEC\n"
      "FA(H1_1)=FEAT/POINT,CART,1,1,1,0,1,0\r\n";
  auto r = ParseDmisOutput(text, "a.dmo");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"S_R", "H1"}));
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.5, 2, 3));
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(ps.line[1], 5u);
  EXPECT_EQ(ps.normal[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_DOUBLE_EQ(ps.xyz_mm[2].x(), kMmPerInch);
  EXPECT_EQ(r->report.filnam, "turning plan");
  EXPECT_EQ(r->report.skipped_actuals.at("CIRCLE"), 1u);
  EXPECT_EQ(r->file.info.source_units, LengthUnit::kInch);
}

TEST(DmisReader, BadFilesSayFileLineAndWhatWasExpected) {
  struct Case {
    const char* what;
    std::string text;
    std::size_t line;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"cut short", "UNITS/MM,ANGDEC\nFA(S_R_1)=FEAT/POINT,CART,1,2,3,0\n", 2, "expected 6 (x,y,z,i,j,k)"},
      {"continuation at end", "FA(S_R_1)=FEAT/POINT,CART,1,2,3,$\n", 1, "the file ends"},
      {"unknown units", "UNITS/FURLONG,ANGDEC\nFA(S_R_1)=FEAT/POINT,CART,1,2,3,0,0,1\n", 1, "expected a length unit"},
      {"not a number", "FA(S_R_1)=FEAT/POINT,CART,1,2,x,0,0,1\n", 1, "'X' is not a number"},
      {"polar", "FA(S_R_1)=FEAT/POINT,POL,1,2,3,0,0,1\n", 1, "polar points are not supported"},
      {"bad vector", "FA(S_R_1)=FEAT/POINT,CART,1,2,3,0,0,2\n", 1, "expected a unit vector"},
      {"no points", "$$ nothing\nUNITS/MM,ANGDEC\n", 1, "no FA(label)"},
  };
  for (const Case& c : cases) {
    auto r = ParseDmisOutput(c.text, "bad.dmo");
    ASSERT_FALSE(r.ok()) << c.what;
    EXPECT_EQ(r.status().code(), StatusCode::kParseError) << c.what;
    EXPECT_EQ(r.status().line(), c.line) << c.what << ": " << r.status().ToString();
    EXPECT_NE(r.status().message().find(c.expect), std::string::npos) << c.what << ": " << r.status().ToString();
  }
}

TEST(DmisReader, LabelThePlanDoesNotKnowIsAnError) {
  DmisReadOptions o;
  o.known_features = {"S_R", "B_R"};
  auto r = ParseDmisOutput("FA(S_R_1)=FEAT/POINT,CART,1,2,3,0,0,1\nFA(XX_2)=FEAT/POINT,CART,1,2,3,0,0,1\n", "p.dmo", o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().ToString(),
            "p.dmo:2: FA(XX_2): feature 'XX' is not in the plan: expected a label <feature>_<k> of one of its 2 features");
}

TEST(XyzijkReader, MetricAndInchAndLabels) {
  EXPECT_TRUE(IsXyzijkText("XYZIJK\r\nMETRIC\n"));
  EXPECT_TRUE(IsXyzijkText("\xEF\xBB\xBFxyzijk\n"));
  EXPECT_FALSE(IsXyzijkText("1 2 3\n"));
  auto r = ParsePointXyzijk("XYZIJK\nMETRIC\n1,2,3,0,0,1\n\n4,5,6,0,1,0\n", "a.txt");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->points.size(), 2u);
  EXPECT_FALSE(r->points.has_labels());
  EXPECT_EQ(r->points.line[1], 5u);
  EXPECT_EQ(r->info.format, PointFormat::kXyzijk);
  auto in = ParsePointXyzijk("XYZIJK\nINCH\nP1,1,0,0\nP1,2,0,0\n", "b.txt");
  ASSERT_TRUE(in.ok()) << in.status().ToString();
  EXPECT_DOUBLE_EQ(in->points.xyz_mm[1].x(), 2 * kMmPerInch);
  EXPECT_EQ(in->points.feature_names, std::vector<std::string>{"P1"});
  auto bad = ParsePointXyzijk("XYZIJK\nMETRIC\n1,2,3,0,0,1\n4,5\n", "c.txt");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().ToString(), "c.txt:4: 2 numbers: expected 6 as on the first data line");
  auto unit = ParsePointXyzijk("XYZIJK\nFURLONG\n1,2,3\n", "d.txt");
  ASSERT_FALSE(unit.ok());
  EXPECT_EQ(unit.status().line(), 2u);
}

}  // namespace
}  // namespace tpcal::pipeline
