// The instrument-versus-piece table's reports, from a table built by hand.
#include "pipeline/report/reference_agreement_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace tpcal::pipeline {
namespace {

ReferenceAgreement OneRowTable() {
  ReferenceAgreement a;
  a.instrument = "datum_ball";
  a.source = "ballpos.csv";
  a.compared = 1;
  a.p_threshold = 0.01;
  a.reference_note = "the instrument's errors as measured";
  AgreementRow row;
  row.name = "E_X0C";
  row.unit = "um";
  row.instrument_known = row.piece_known = row.compared = true;
  row.instrument_value = 10.0, row.instrument_u = 0.4, row.piece_value = 10.5, row.piece_u = 0.3, row.z = 1.0;
  a.rows = {row};
  return a;
}

// Nothing flagged by the piece's identification: no sentence, no key. Three points, two of them in
// one patch on H1, left out: named in the text, the HTML and the JSON.
TEST(ReferenceAgreementReport, ThePieceIdentificationsLeftOutPointsAreNamed) {
  ReferenceAgreement a = OneRowTable();
  EXPECT_EQ(ReferenceAgreementText(a).find("outlier screen"), std::string::npos);
  EXPECT_EQ(ReferenceAgreementHtml(a).find("outlier screen"), std::string::npos);
  EXPECT_FALSE(ReferenceAgreementJson(a).contains("piece_outliers"));

  a.piece_outliers.assign(3, ScreenedPoint{.point_index = 0, .line = 39, .feature = "H1", .kind = "local_defect",
                                           .deviation_um = 2.5, .reason = "r", .left_out = true});
  LocalDefect patch;
  patch.feature = "H1";
  patch.n_points = 2;
  a.piece_local_defects = {patch};
  const std::string sentence =
      "the piece's values are fitted without the 3 point(s) its identification's outlier screen flagged (2 in 1 local "
      "defect(s): H1; JSON: reference_agreement.piece_outliers); the diagnosis screens every point itself";
  EXPECT_NE(ReferenceAgreementText(a).find("  " + sentence + "\n"), std::string::npos) << ReferenceAgreementText(a);
  EXPECT_NE(ReferenceAgreementHtml(a).find(" the piece&#39;s values"), std::string::npos) << ReferenceAgreementHtml(a);
  const auto js = ReferenceAgreementJson(a);
  EXPECT_EQ(js["piece_outliers"].size(), 3u);
  EXPECT_EQ(js["piece_outliers"][0]["line"], 39);
  EXPECT_EQ(js["piece_local_defects"][0]["feature"], "H1");

  a.piece_outliers[0].left_out = false;
  EXPECT_NE(ReferenceAgreementText(a).find("fitted with (kept) the 3 point(s)"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
