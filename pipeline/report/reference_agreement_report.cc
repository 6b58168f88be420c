#include "pipeline/report/reference_agreement_report.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "core/xml_escape.h"
#include "pipeline/report/json_util.h"
#include "pipeline/report/screen_json.h"

namespace tpcal::pipeline {
namespace {

using json = nlohmann::ordered_json;

std::string AgreementWord(const AgreementRow& r) {
  if (!r.compared) return r.note;
  return r.agree ? "agree" : "DISAGREE";
}

std::string AgreementValueText(bool known, double value, double u) {
  return known ? fmt::format("{:.3f} +- {:.3f}", value, u) : std::string("-");
}

// What the outlier screen of the piece's identification behind the rows left out; "" when nothing.
std::string PieceScreenSentence(const ReferenceAgreement& a) {
  if (a.piece_outliers.empty()) return "";
  std::string features;
  int in_patches = 0;
  for (const LocalDefect& d : a.piece_local_defects) {
    features += (features.empty() ? ": " : ", ") + d.feature;
    in_patches += d.n_points;
  }
  const bool left_out = a.piece_outliers.front().left_out;
  return fmt::format("the piece's values are fitted {} the {} point(s) its identification's outlier screen flagged "
                     "({} in {} local defect(s){}; JSON: reference_agreement.piece_outliers); the diagnosis screens "
                     "every point itself",
                     left_out ? "without" : "with (kept)", a.piece_outliers.size(), in_patches,
                     a.piece_local_defects.size(), features);
}

}  // namespace

json ReferenceAgreementJson(const ReferenceAgreement& a) {
  json rows = json::array();
  for (const AgreementRow& r : a.rows) {
    json row = {{"name", r.name},
                {"unit", r.unit},
                {"instrument", {{"value", OrNull(r.instrument_known, r.instrument_value)},
                                {"u", OrNull(r.instrument_known, r.instrument_u)}}},
                {"piece", {{"value", OrNull(r.piece_known, r.piece_value)}, {"u", OrNull(r.piece_known, r.piece_u)}}},
                {"compared", r.compared},
                {"z", OrNull(r.compared, r.z)},
                {"p_value", OrNull(r.compared, r.p_value)},
                {"agree", r.agree}};
    if (!r.note.empty()) row["note"] = r.note;
    rows.push_back(row);
  }
  json out = {{"instrument", a.instrument}, {"source", a.source},   {"alpha", a.alpha},
              {"p_threshold", a.p_threshold}, {"compared", a.compared}, {"disagreeing", a.disagreeing},
              {"reference", a.reference_note}, {"rows", rows}};
  if (!a.piece_outliers.empty()) {
    out["piece_outliers"] = OutliersJson(a.piece_outliers);
    out["piece_local_defects"] = LocalDefectsJson(a.piece_local_defects);
  }
  return out;
}

std::string ReferenceAgreementText(const ReferenceAgreement& a) {
  std::string o = fmt::format(
      "\ninstrument ({}, {}) against the piece: {} of {} compared parameters disagree (two-sided p < {:.3g}, "
      "alpha {} over {})\n",
      a.instrument, a.source, a.disagreeing, a.compared, a.p_threshold, a.alpha, a.compared);
  o += fmt::format("  {:<40} {:>22} {:>22} {:>7}  {}\n", "parameter", "instrument", "piece", "z", "");
  for (const AgreementRow& r : a.rows)
    o += fmt::format("  {:<40.40} {:>22} {:>22} {:>7} {} {}\n", r.name, AgreementValueText(r.instrument_known, r.instrument_value, r.instrument_u),
                     AgreementValueText(r.piece_known, r.piece_value, r.piece_u), r.compared ? fmt::format("{:+.2f}", r.z) : "-",
                     r.unit, AgreementWord(r));
  o += "  gap measured against " + a.reference_note + "\n";
  if (const std::string screen = PieceScreenSentence(a); !screen.empty()) o += "  " + screen + "\n";
  return o;
}

std::string ReferenceAgreementHtml(const ReferenceAgreement& a) {
  const std::string screen = PieceScreenSentence(a);
  std::string o = "<h2>Instrument against piece</h2><p>" + XmlEscape(a.instrument) + " " + XmlEscape(a.source) +
                  fmt::format(": {} of {} compared parameters disagree (two-sided p &lt; {:.3g}). ", a.disagreeing,
                              a.compared, a.p_threshold) +
                  "The gap is measured against " + XmlEscape(a.reference_note) + "." +
                  (screen.empty() ? "" : " " + XmlEscape(screen) + ".") +
                  "</p>\n<table><tr><th>parameter</th><th>unit</th><th>instrument</th><th>piece</th><th>z</th>"
                  "<th></th></tr>\n";
  for (const AgreementRow& r : a.rows)
    o += fmt::format("<tr{}><td class=l>{}</td><td class=l>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=l>{}</td></tr>\n",
                     r.agree ? "" : " class=hi", XmlEscape(r.name), XmlEscape(r.unit),
                     AgreementValueText(r.instrument_known, r.instrument_value, r.instrument_u),
                     AgreementValueText(r.piece_known, r.piece_value, r.piece_u), r.compared ? fmt::format("{:+.2f}", r.z) : "-",
                     XmlEscape(AgreementWord(r)));
  return o + "</table>\n";
}

}  // namespace tpcal::pipeline
