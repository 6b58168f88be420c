// The diagnosis's HTML blocks on hand-made results: what shows, what is escaped, what stays out.
#include "pipeline/report/diagnosis_html_blocks.h"

#include <gtest/gtest.h>

#include "pipeline/report/diagnosis_json.h"

namespace tpcal::pipeline {
namespace {

DiagnosisResult Straightness() {
  DiagnosisResult d;
  d.verdict.family = "straightness";
  d.verdict.name = "straightness of X in Y (quadratic)";
  d.verdict.families = {"straightness", "local_defect"};
  CandidateResult c;
  c.family = "straightness";
  c.name = d.verdict.name;
  c.base_shift = {{.name = "E_C(0X)Y", .unit = "urad", .without_um = -44.0, .with_um = -13.2, .u_without = 2.6,
                   .u_with = 2.8}};
  d.candidates = {c};
  return d;
}

TEST(DiagnosisHtmlBlocks, BaseShiftShowsBothValuesAndBothUncertainties) {
  const std::string h = BaseShiftHtml(Straightness());
  EXPECT_NE(h.find("id=\"base-shift-table\""), std::string::npos);
  EXPECT_NE(h.find("<td>-44.000</td><td>2.600</td><td>-13.200</td><td>2.800</td><td>11.0</td>"), std::string::npos) << h;
  DiagnosisResult none;
  EXPECT_EQ(BaseShiftHtml(none), "");
  DiagnosisResult unexplained = Straightness();
  unexplained.verdict.family = "unexplained";
  EXPECT_EQ(BaseShiftHtml(unexplained), "");  // no effect named: nothing was re-identified
}

TEST(DiagnosisHtmlBlocks, FamiliesAndPartialCandidatesAreNamedAndEscaped) {
  Verdict v = Straightness().verdict;
  EXPECT_NE(VerdictFamiliesHtml(v).find("straightness + local_defect"), std::string::npos);
  Verdict one;
  one.families = {"thermal_drift"};
  EXPECT_EQ(VerdictFamiliesHtml(one), "");
  Verdict u;
  u.family = "unexplained";
  u.partial = {"harmonic <7>"};
  EXPECT_NE(VerdictFamiliesHtml(u).find("harmonic &lt;7&gt;"), std::string::npos);
  Verdict pair;
  pair.families = {"thermal_drift", "probe_radius"};
  pair.also = "probe_radius";
  EXPECT_EQ(VerdictFamiliesHtml(pair).find("verdict-also-alike"), std::string::npos);  // nothing alike: not said
  pair.also_indistinguishable_from = {"linear_positioning"};
  EXPECT_NE(VerdictFamiliesHtml(pair).find("The second effect, probe_radius, cannot be told apart on this piece and plan "
                                           "from: linear_positioning."),
            std::string::npos);
}

TEST(DiagnosisHtmlBlocks, ScreenListsPatchesAndPointsWithTheirLines) {
  DiagnosisResult d;
  EXPECT_EQ(ScreenHtml(d), "");
  d.neighbour_sigma_um = 0.5;
  d.local_defects = {{.feature = "S2", .n_points = 2, .peak_um = 4.1, .mean_um = 3.9, .extent_mm = 1.5,
                      .point_index = {10, 11}, .lines = {12, 13}}};
  d.outliers = {{.point_index = 40, .line = 42, .feature = "H1", .kind = "outlier", .deviation_um = -21.0,
                 .reason = "18 sigma from the model and its neighbours"}};
  const std::string h = ScreenHtml(d);
  EXPECT_NE(h.find("left out of identification and diagnosis"), std::string::npos);
  EXPECT_NE(h.find("<td class=\"t\">12 13</td>"), std::string::npos) << h;
  EXPECT_NE(h.find("<td>-21.00</td>"), std::string::npos);
  EXPECT_NE(h.find("<td class=\"t\">42</td>"), std::string::npos);
  d.outliers[0].left_out = false;
  EXPECT_NE(ScreenHtml(d).find("kept in (--keep-outliers)"), std::string::npos);
}

// Patches the verdict's effect explains are kept in the fit and still listed where they lie.
TEST(DiagnosisHtmlBlocks, PatchesTheVerdictExplainsAreListed) {
  DiagnosisResult d;
  d.explained_patches = {{.feature = "S_R", .n_points = 5, .peak_um = -2.4, .mean_um = -1.9, .extent_mm = 6.0,
                          .point_index = {30, 31, 32, 33, 34}, .lines = {31, 32, 33, 34, 35}}};
  const std::string h = ScreenHtml(d);
  EXPECT_NE(h.find("patch explained by the verdict (kept)</td><td class=\"t\">S_R</td><td>5</td>"), std::string::npos) << h;
  EXPECT_NE(h.find("31 32 33 34 35"), std::string::npos) << h;
}

// indistinguishable_candidates by name: the text and the HTML say which of the verdict's own
// family (another axis) explain the gap about as well; another family's stays in the JSON only
// (indistinguishable_from names that family); none listed, no line.
TEST(DiagnosisHtmlBlocks, AnotherAxisOfTheVerdictsFamilyIsNamed) {
  DiagnosisResult d = Straightness();
  CandidateResult other = d.candidates.front(), drift = d.candidates.front();
  other.name = "straightness of Y in X (quadratic) <b>";
  drift.family = "thermal_drift";
  drift.name = "linear drift of the table";
  d.candidates.push_back(other);
  d.candidates.push_back(drift);
  d.verdict.indistinguishable_candidates = {drift.name, other.name};
  EXPECT_EQ(SameFamilyAlternatives(d), std::vector<std::string>{other.name});
  const std::string text = DiagnosisText(d);
  EXPECT_NE(text.find("within its family, explained about as well by: straightness of Y in X (quadratic) <b>\n"),
            std::string::npos) << text;
  EXPECT_EQ(text.find("by: linear drift"), std::string::npos) << text;
  const std::string html = DiagnosisHtml(d, "t");
  EXPECT_NE(html.find("explained about as well by: straightness of Y in X (quadratic) &lt;b&gt;</p>"), std::string::npos)
      << html;
  EXPECT_NE(DiagnosisJson(d).find("\"indistinguishable_candidates\""), std::string::npos);
  d.verdict.indistinguishable_candidates.clear();
  EXPECT_EQ(DiagnosisText(d).find("within its family"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
