// SVG writer and figures: escaping, tick steps, and figures that only exist when there is
// something to draw (never an empty figure).
#include "pipeline/report/svg_figures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pipeline/report/svg_writer.h"

namespace tpcal::pipeline {
namespace {

TEST(SvgWriter, EscapesTextAndPrintsFixedDecimals) {
  SvgWriter svg(100, 50, "a < b & \"c\"");
  svg.Text(1.004, -0.001, "x<y", "lbl");
  svg.Line(0, 0, 1.0 / 3.0, 2, "ax");
  const std::string out = svg.Finish();
  EXPECT_NE(out.find("<title>a &lt; b &amp; &quot;c&quot;</title>"), std::string::npos);
  EXPECT_NE(out.find(">x&lt;y</text>"), std::string::npos);
  EXPECT_NE(out.find("x=\"1.00\" y=\"0.00\""), std::string::npos);  // -0.00 printed as 0.00
  EXPECT_NE(out.find("x2=\"0.33\""), std::string::npos);
  EXPECT_EQ(out.rfind("</svg>\n"), out.size() - 7);
}

TEST(SvgWriter, NiceStepIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(NiceStep(10.0, 5), 2.0);
  EXPECT_DOUBLE_EQ(NiceStep(0.7, 2), 0.5);
  EXPECT_DOUBLE_EQ(NiceStep(37.0, 5), 10.0);
  EXPECT_DOUBLE_EQ(NiceStep(0.0, 5), 1.0);  // degenerate span: a usable default, not NaN
}

TEST(SvgFigures, NothingToDrawGivesNoFigure) {
  gdt::InspectionResult empty;
  gdt::InspectionPlan plan;
  EXPECT_FALSE(HolePositionsFigure(plan, empty).has_value());
  EXPECT_FALSE(CircularityFigure(empty).has_value());
  EXPECT_FALSE(VectorsFigure(empty).has_value());
  EXPECT_FALSE(MachineErrorsFigure({}).has_value());
  EXPECT_TRUE(MakeFigures(plan, empty, nullptr, {}).empty());
}

TEST(SvgFigures, MachineErrorsMarkNonIdentifiableAndTruth) {
  std::vector<kinematics::ParameterEstimate> p(2);
  p[0].name = "dx_CR(0)";
  p[0].iso_symbol = "delta x_CR(0 deg) = E_X0C (seed 002 eq. 1)";
  p[0].unit = "um";
  p[0].identifiable = true;
  p[0].value = 12.0;
  p[0].u = 0.5;
  p[0].ci95_low = 11.0;
  p[0].ci95_high = 13.0;
  p[1].name = "dy_AR(-90)";
  p[1].unit = "um";
  p[1].identifiable = false;
  auto fig = MachineErrorsFigure(p, {{"dx_CR(0)", 12.4}});
  ASSERT_TRUE(fig.has_value());
  EXPECT_EQ(fig->name, "machine_errors");
  EXPECT_NE(fig->svg.find(">dx_CR(0)  [E_X0C]<"), std::string::npos);
  EXPECT_NE(fig->svg.find("not identifiable"), std::string::npos);
  EXPECT_NE(fig->svg.find("class=\"truth\""), std::string::npos);
  EXPECT_NE(fig->svg.find("class=\"bar\""), std::string::npos);
  // Same input, same bytes.
  EXPECT_EQ(MachineErrorsFigure(p, {{"dx_CR(0)", 12.4}})->svg, fig->svg);
}

TEST(SvgFigures, CircularityProfileIsMagnifiedAboutTheLsCircle) {
  gdt::InspectionResult r;
  gdt::CharacteristicResult c;
  c.name = "ta_circularity_S1";
  c.type = gdt::CharacteristicType::kCircularity;
  for (int k = 0; k < 4; ++k) c.profile.push_back({90.0 * k, k == 0 ? 1.0 : 0.0, static_cast<std::size_t>(k)});
  r.characteristics.push_back(c);
  FigureOptions o;
  o.profile_magnification = 10000;
  auto fig = CircularityFigure(r, o);
  ASSERT_TRUE(fig.has_value());
  // No fitted feature: reference radius 100 mm drawn at 80 px, so 1 um x 10000 = 10 mm = 8 px:
  // the theta = 0 sample sits at 88 px right of the panel centre (125 + 88 = 213).
  EXPECT_NE(fig->svg.find("213.00,175.00"), std::string::npos) << fig->svg;
}

// A dense profile (100 000 samples over one turn, a 3-lobe form plus one spike) is drawn with at
// most 2 vertices per 0.25 deg bin, and the drawn polygon keeps its extremes (peak-to-valley).
TEST(SvgFigures, DenseProfileIsDrawnByItsEnvelope) {
  std::vector<gdt::ProfileSample> profile;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    const double theta_deg = 360.0 * k / n - 180.0;
    double dr_um = std::sin(3.0 * theta_deg * std::numbers::pi / 180.0);
    if (k == 4321) dr_um = 5.0;
    profile.push_back({theta_deg, dr_um, static_cast<std::size_t>(k)});
  }
  const auto drawn = DrawnProfile(profile, 1440);
  EXPECT_LE(drawn.size(), 2u * 1440u);
  EXPECT_GE(drawn.size(), 1440u);
  auto by_dr = [](const gdt::ProfileSample& a, const gdt::ProfileSample& b) { return a.dr_um < b.dr_um; };
  EXPECT_EQ(std::max_element(drawn.begin(), drawn.end(), by_dr)->dr_um, 5.0);
  EXPECT_EQ(std::min_element(drawn.begin(), drawn.end(), by_dr)->dr_um,
            std::min_element(profile.begin(), profile.end(), by_dr)->dr_um);
  EXPECT_TRUE(std::is_sorted(drawn.begin(), drawn.end(),
                             [](const auto& a, const auto& b) { return a.theta_deg < b.theta_deg; }));
  // Few samples: drawn as they are.
  const std::vector<gdt::ProfileSample> few(profile.begin(), profile.begin() + 100);
  EXPECT_EQ(DrawnProfile(few, 1440).size(), 100u);
}

}  // namespace
}  // namespace tpcal::pipeline
