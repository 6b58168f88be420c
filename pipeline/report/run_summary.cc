#include "pipeline/report/run_summary.h"

#include <fmt/format.h>

#include "pipeline/report/svg_figures.h"

namespace tpcal::pipeline {

std::string RunParameterTable(const kinematics::IdentificationResult& identification) {
  std::string out = fmt::format("{:<16} {:<22} {:>10} {:>9} {:>23}  {}\n", "parameter", "ISO 230-1", "value",
                                "u (k=1)", "95 % interval", "unit");
  for (const auto& p : identification.parameters) {
    const std::string iso = ShortIsoSymbol(p.iso_symbol);
    const bool fixed = p.unit == "um" || p.unit == "urad";
    if (p.identifiable && fixed)
      out += fmt::format("{:<16} {:<22} {:>10.2f} {:>9.3f} [{:>9.2f}, {:>9.2f}]  {}\n", p.name, iso, p.value, p.u,
                         p.ci95_low, p.ci95_high, p.unit);
    else if (p.identifiable)
      out += fmt::format("{:<16} {:<22} {:>10.4g} {:>9.3g} [{:>9.4g}, {:>9.4g}]  {}\n", p.name, iso, p.value, p.u,
                         p.ci95_low, p.ci95_high, p.unit);
    else
      out += fmt::format("{:<16} {:<22} {:>10} {:>9} {:>23}  {}\n", p.name, iso, "n/a", "-", "not identifiable",
                         p.unit);
  }
  const auto& ia = identification.identifiability;
  return out + fmt::format("rank {} of {}, condition number {:.3g}; residual RMS {:.3f} um -> {:.3f} um\n", ia.rank,
                           ia.num_parameters, ia.condition_number, identification.rms_before_um,
                           identification.rms_after_um);
}

std::string InstrumentAgreementLine(const std::optional<ReferenceAgreement>& agreement) {
  if (!agreement) return "";
  std::string names;
  for (const AgreementRow& row : agreement->rows)
    if (!row.agree) names += (names.empty() ? " (" : ", ") + row.name;
  return fmt::format("instrument vs piece: {} of {} compared parameters disagree{}\n", agreement->disagreeing,
                     agreement->compared, names.empty() ? "" : names + ")");
}

std::string IdentificationScreenLine(const std::vector<ScreenedPoint>& flagged, const std::vector<LocalDefect>& patches) {
  if (flagged.empty()) return "";
  int in_patches = 0;
  for (const auto& p : patches) in_patches += p.n_points;
  return fmt::format("identification: {} point(s) {} by the outlier screen ({} in {} local defect(s); result.json: "
                     "identification.outliers)\n",
                     flagged.size(), flagged.front().left_out ? "left out" : "flagged and kept", in_patches,
                     patches.size());
}

std::string GapDiagnosisLine(const std::optional<DiagnosisResult>& diagnosis, bool asked, const Status& why_not) {
  if (diagnosis)
    return fmt::format("gap diagnosis: {} ({}), shrink {:.1f} % (cross-validated {:.1f} %)\n", diagnosis->verdict.family,
                       diagnosis->verdict.name, diagnosis->verdict.shrink_pct, diagnosis->verdict.cv_shrink_pct) +
           InstrumentAgreementLine(diagnosis->reference_agreement);
  if (asked) return "gap diagnosis: not made: " + why_not.ToString() + "\n";
  return "";
}

}  // namespace tpcal::pipeline
