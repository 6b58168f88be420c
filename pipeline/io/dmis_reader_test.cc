#include "pipeline/io/dmis_reader.h"

#include <gtest/gtest.h>

#include <cmath>

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
      {"neither CART nor POL", "FA(S_R_1)=FEAT/POINT,SPH,1,2,3,0,0,1\n", 1, "or FEAT/POINT,POL,r,a,h,i,j,k"},
      {"polar in DMS", "UNITS/MM,ANGDMS\nFA(S_R_1)=FEAT/POINT,POL,1,2,3,0,0,1\n", 2, "expected ANGDEC or ANGRAD"},
      {"polar in another work plane", "WKPLAN/FA(PL1)\nFA(S_R_1)=FEAT/POINT,POL,1,2,3,0,0,1\n", 2,
       "a polar point in 'WKPLAN/FA(PL1)': expected WKPLAN/XYPLAN"},
      {"polar cut short", "FA(S_R_1)=FEAT/POINT,POL,1,2,3,0,0\n", 1, "expected 6 (r,a,h,i,j,k)"},
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

// Truth: a point at radius 100 mm, 30 degrees, height 5 mm is (100 cos 30, 100 sin 30, 5) on
// XYPLAN; on YZPLAN the angle runs Y -> Z and the height is X; on ZXPLAN Z -> X, height Y.
// Tolerance 1e-12 mm: one rounding of cos/sin times 100 mm.
TEST(DmisReader, PolarPointsLieInTheWorkPlaneInTheAngleUnit) {
  const std::string text =
      "UNITS/MM,ANGDEC\n"
      "FA(S_R_1)=FEAT/POINT,POL,100,30,5,0.8660254037844386,0.5,0\n"
      "WKPLAN/YZPLAN\n"
      "FA(S_R_2)=FEAT/POINT,POL,100,30,5,1,0,0\n"
      "wkplan/zxplan\n"
      "UNITS/INCH,ANGRAD\n"
      "FA(S_R_3)=FEAT/POINT,POL,2,0.5235987755982988,1,0,1,0\n";
  auto r = ParseDmisOutput(text, "polar.dmo");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  ASSERT_EQ(ps.size(), 3u);
  const double c = 100 * std::cos(M_PI / 6), s = 100 * std::sin(M_PI / 6);
  EXPECT_LT((ps.xyz_mm[0] - Eigen::Vector3d(c, s, 5)).norm(), 1e-12);
  EXPECT_LT((ps.xyz_mm[1] - Eigen::Vector3d(5, c, s)).norm(), 1e-12);
  EXPECT_LT((ps.xyz_mm[2] - kMmPerInch * Eigen::Vector3d(2 * std::sin(M_PI / 6), 1, 2 * std::cos(M_PI / 6))).norm(),
            1e-12);
  EXPECT_EQ(ps.normal[1], Eigen::Vector3d(1, 0, 0));
  // A work plane of another kind does not matter to Cartesian points.
  auto cart = ParseDmisOutput("WKPLAN/FA(PL1)\nFA(S_R_1)=FEAT/POINT,CART,1,2,3,0,0,1\n", "cart.dmo");
  ASSERT_TRUE(cart.ok()) << cart.status().ToString();
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
