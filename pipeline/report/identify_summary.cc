#include "pipeline/report/identify_summary.h"

#include "pipeline/report/screen_json.h"

#include <fmt/format.h>

namespace tpcal::pipeline {
namespace {

std::string FixedDigits(double v, int digits = 2) { return fmt::format("{:.{}f}", v, digits); }

}  // namespace

std::string IdentificationSummary(const IdentificationReport& r) {
  const auto& id = r.identification;
  std::string out = fmt::format("{} on {}: {} points in {} features; residual RMS {} um before, {} um after (sigma {} um)\n\n",
                                r.testpiece, r.machine, id.num_observations, id.num_groups, FixedDigits(id.rms_before_um, 3),
                                FixedDigits(id.rms_after_um, 3), FixedDigits(id.sigma_um, 3));
  out += fmt::format("{:<15} {:>9} {:<5} {:>8} {:>8} {:>8} {:>19}  {}\n", "parameter", "value", "unit", "u_anal",
                     "u_jk_pt", "u_jk_ft", "95 % interval", "ISO 230-1");
  for (const auto& p : id.parameters) {
    if (!p.identifiable) {
      out += fmt::format("{:<15} {:>9} {:<5}   not identifiable from this piece (see combinations)  {}\n", p.name, "-",
                         p.unit, p.iso_symbol);
      continue;
    }
    auto u_of = [&](kinematics::UncertaintyMethod m) {
      for (const auto& u : p.uncertainties)
        if (u.method == m && u.available) return FixedDigits(u.u);
      return std::string("-");
    };
    const std::string subset = u_of(kinematics::UncertaintyMethod::kRandomSubsets);
    out += fmt::format("{:<15} {:>9} {:<5} {:>8} {:>8} {:>8} {:>19}  {}{}\n", p.name, FixedDigits(p.value), p.unit,
                       u_of(kinematics::UncertaintyMethod::kAnalytic),
                       u_of(kinematics::UncertaintyMethod::kJackknifePoints),
                       u_of(kinematics::UncertaintyMethod::kJackknifeGroups),
                       "[" + FixedDigits(p.ci95_low) + ", " + FixedDigits(p.ci95_high) + "]", p.iso_symbol,
                       subset == "-" ? std::string() : "  (random subsets: u " + subset + ")");
  }
  const auto& ident = id.identifiability;
  out += fmt::format("\nidentifiability: rank {} of {}, condition number {:.3g}\n", ident.rank, ident.num_parameters,
                     ident.condition_number);
  for (const auto& c : ident.estimable)
    out += fmt::format("  only the combination {} = {} +- {} is determined\n", c.text, FixedDigits(c.value),
                       FixedDigits(c.u));
  for (const auto& m : r.error_motion)
    out += fmt::format("C error motion {} ({}): radial P-V {} um, tilt P-V {} urad\n", m.name, m.faces,
                       FixedDigits(m.profile.radial_pv_um), FixedDigits(m.profile.tilt_pv_urad));
  for (const auto& s : r.straightness)
    out += fmt::format("straightness {} from {}: {} um (LS P-V), {} um (minimum zone)\n", s.name, s.feature,
                       FixedDigits(s.pv_ls_um), FixedDigits(s.mz_um));
  out += ScreenText(r.outliers, r.local_defects, r.neighbour_sigma_um);
  if (r.gap_check)
    out += r.gap_check->warning.empty() ? "gap check: nothing beyond measurement noise\n"
                                        : "WARNING: " + r.gap_check->warning + "\n";
  return out;
}

}  // namespace tpcal::pipeline
