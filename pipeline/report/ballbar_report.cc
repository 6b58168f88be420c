#include "pipeline/report/ballbar_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "pipeline/report/json_util.h"

namespace tpcal::pipeline {
namespace {

using BbJson = nlohmann::ordered_json;
using kinematics::BallbarErrorEntry;

constexpr const char* kBbSymbols[6] = {"E_X", "E_Y", "E_Z", "E_A", "E_B", "E_C"};

// "1.234 +- 0.012", "1.234" (u unknown) or "-" (not identifiable).
std::string BbValueU(bool identifiable, bool u_known, double value, double u) {
  if (!identifiable) return "-";
  return u_known ? fmt::format("{:.3f} +- {:.3f}", value, u) : fmt::format("{:.3f}", value);
}

BbJson BbResidualsJson(const std::vector<double>& residuals_um, const std::vector<std::size_t>& lines) {
  BbJson out = BbJson::array();
  for (std::size_t i = 0; i < residuals_um.size(); ++i)
    out.push_back({{"line", i < lines.size() ? lines[i] : 0}, {"residual_um", residuals_um[i]}});
  return out;
}

// The entries; with a map response (BallbarAxisReport::response_to), each entry's "response": its
// change per display unit of each named error, in the entry's unit.
// Whether the axis's map response is written ("response_to" and every entry's "response").
bool BbHasResponse(const BallbarAxisReport& a) {
  return !a.response_to.empty() && a.map_response.rows() == static_cast<Eigen::Index>(a.result.entries.size()) &&
         a.map_response.cols() == static_cast<Eigen::Index>(a.response_to.size());
}

BbJson BbEntriesJson(const BallbarAxisReport& a) {
  const auto& r = a.result;
  const bool response = BbHasResponse(a);
  BbJson out = BbJson::array();
  for (std::size_t k = 0; k < r.entries.size(); ++k) {
    const BallbarErrorEntry& e = r.entries[k];
    const bool u_known = e.identifiable && r.sigma_known;
    out.push_back({{"symbol", e.symbol},
                   {"coefficient", e.coefficient},
                   {"unit", e.unit},
                   {"angle_deg", e.angle_deg},
                   {"identifiable", e.identifiable},
                   {"convention_dependent", e.convention_dependent},
                   {"value", OrNull(e.identifiable, e.value)},
                   {"u", OrNull(u_known, e.u)},
                   {"ci95", u_known ? BbJson{e.ci95_low, e.ci95_high} : BbJson(nullptr)}});
    if (!response) continue;
    BbJson per_unit = BbJson::array();
    for (Eigen::Index c = 0; c < a.map_response.cols(); ++c) per_unit.push_back(a.map_response(static_cast<Eigen::Index>(k), c));
    out.back()["response"] = std::move(per_unit);
  }
  return out;
}

BbJson BbAxisJson(const BallbarAxisReport& a) {
  const auto& r = a.result;
  BbJson setup = BbJson::array();
  for (const auto& t : r.setup_terms) {
    const std::string& name = t.installation >= 0 && static_cast<std::size_t>(t.installation) < a.installations.size()
                                  ? a.installations[static_cast<std::size_t>(t.installation)]
                                  : std::to_string(t.installation);
    setup.push_back({{"installation", name},
                     {"term", t.name},
                     {"identifiable", t.identifiable},
                     {"value_um", OrNull(t.identifiable, t.value_um)},
                     {"u_um", OrNull(t.identifiable && r.sigma_known, t.u_um)}});
  }
  BbJson j;
  j["axis"] = a.axis;
  j["installations"] = a.installations;
  j["fit"] = {{"readings", r.rows},
              {"unknowns", r.unknowns},
              {"rank", r.rank},
              {"dof", r.dof},
              {"sigma_um", OrNull(r.sigma_known, r.sigma_um)}};
  j["angles_deg"] = r.angle_deg;
  j["periodic"] = r.periodic;
  if (BbHasResponse(a)) j["response_to"] = a.response_to;
  j["errors"] = BbEntriesJson(a);
  j["setup_terms"] = std::move(setup);
  j["not_separable"] = r.not_separable;
  j["not_identifiable"] = r.not_identifiable;
  j["convention_dependent"] = r.convention_dependent;
  j["conventions"] = r.conventions;
  j["residuals"] = BbResidualsJson(r.residuals_um, a.lines);
  return j;
}

BbJson BbCircleJson(const BallbarCircleReport& c) {
  const auto& r = c.result;
  BbJson figures = BbJson::array();
  for (const auto& f : r.figures) {
    figures.push_back({{"name", f.name},
                       {"symbol", f.symbol},
                       {"unit", f.unit},
                       {"identifiable", f.identifiable},
                       {"value", OrNull(f.identifiable, f.value)},
                       {"u", OrNull(f.identifiable && f.u > 0.0, f.u)},
                       {"note", f.note}});
  }
  BbJson j;
  j["installation"] = c.installation;
  j["plane"] = r.plane;
  j["radius_mm"] = r.radius_mm;
  j["fit"] = {{"readings", r.rows}, {"dof", r.dof}, {"sigma_um", OrNull(r.sigma_known, r.sigma_um)}};
  j["figures"] = std::move(figures);
  j["conventions"] = r.conventions;
  j["residuals"] = BbResidualsJson(r.residuals_um, c.lines);
  return j;
}

// The six error motions of one axis, one row per angle: value +- u, '-' without a number,
// '*' after a value the not-separable families touch (relative to the convention).
std::string BbAxisTableText(const BallbarAxisReport& a) {
  const auto& r = a.result;
  std::string o = fmt::format("  {:>9}", a.axis + " deg");
  for (int d = 0; d < 6; ++d) o += fmt::format(" {:>20}", fmt::format("{}{} {}", kBbSymbols[d], a.axis, d < 3 ? "um" : "urad"));
  o += "\n";
  const std::size_t nodes = r.angle_deg.size();
  for (std::size_t i = 0; i < nodes; ++i) {
    o += fmt::format("  {:>9g}", r.angle_deg[i]);
    for (std::size_t d = 0; d < 6; ++d) {
      const std::size_t k = d * nodes + i;  // term d, node i
      if (k >= r.entries.size()) {
        o += fmt::format(" {:>20}", "-");
        continue;
      }
      const BallbarErrorEntry& e = r.entries[k];
      const std::string v = BbValueU(e.identifiable, r.sigma_known, e.value, e.u);
      o += fmt::format(" {:>20}", e.identifiable && e.convention_dependent ? v + "*" : v);
    }
    o += "\n";
  }
  return o;
}

std::string BbAxisText(const BallbarAxisReport& a) {
  const auto& r = a.result;
  std::string o = fmt::format("\naxis {}: {} installations, {} readings, {} unknowns, rank {}, dof {}", a.axis,
                              a.installations.size(), r.rows, r.unknowns, r.rank, r.dof);
  o += r.sigma_known ? fmt::format(", sigma {:.3f} um\n", r.sigma_um) : std::string(", sigma unknown\n");
  o += "conventions:\n";
  for (const std::string& c : r.conventions) o += "  - " + c + "\n";
  if (!r.not_separable.empty()) {
    o += fmt::format("not separable by these installations ({} families; the maps are given without them):\n",
                     r.not_separable.size());
    for (const std::string& f : r.not_separable) o += "  - " + f + "\n";
  }
  o += fmt::format("error motions of {}, value +- u (k=1); '-' not identifiable; '*' relative to the convention "
                   "({} entries):\n",
                   a.axis, r.convention_dependent);
  o += BbAxisTableText(a);
  o += "set-up terms (fitted and removed), um:\n";
  for (const auto& t : r.setup_terms)
    o += fmt::format("  {:<44} {}\n", t.name, BbValueU(t.identifiable, r.sigma_known, t.value_um, t.u_um));
  if (r.not_identifiable.empty()) return o + "not identifiable: none\n";
  o += fmt::format("not identifiable ({}; no number is given for them):", r.not_identifiable.size());
  for (const std::string& n : r.not_identifiable) o += " " + n;
  return o + "\n";
}

std::string BbCircleText(const BallbarCircleReport& c) {
  const auto& r = c.result;
  std::string o = fmt::format("\ncircle {} (plane {}, radius {:g} mm): {} readings, dof {}", c.installation, r.plane,
                              r.radius_mm, r.rows, r.dof);
  o += r.sigma_known ? fmt::format(", sigma {:.3f} um\n", r.sigma_um) : std::string(", sigma unknown\n");
  for (const auto& f : r.figures) {
    const std::string label = f.symbol.empty() ? f.name : f.name + " (" + f.symbol + ")";
    o += fmt::format("  {:<36} {:>20} {:<5} {}\n", label, BbValueU(f.identifiable, f.u > 0.0, f.value, f.u), f.unit,
                     f.note);
  }
  for (const std::string& s : r.conventions) o += "  - " + s + "\n";
  return o;
}

}  // namespace

std::string BallbarJson(const BallbarReport& report) {
  BbJson j;
  j["schema"] = "tpcal.identification/1";
  j["instrument"] = "ballbar";
  j["source"] = report.source;
  j["setup_source"] = report.setup_source;
  j["machine"] = report.machine;
  j["readings"] = report.readings;
  BbJson axes = BbJson::array();
  for (const auto& a : report.axes) axes.push_back(BbAxisJson(a));
  j["axes"] = std::move(axes);
  BbJson circles = BbJson::array();
  for (const auto& c : report.circles) circles.push_back(BbCircleJson(c));
  j["circles"] = std::move(circles);
  j["errors_yaml"] = report.errors_yaml.empty() ? BbJson(nullptr) : BbJson(report.errors_yaml);
  return j.dump(2) + "\n";
}

std::string BallbarText(const BallbarReport& report) {
  std::string o = fmt::format("ball bar: {} readings from {} (set-up {}, machine {})\n", report.readings, report.source,
                              report.setup_source, report.machine);
  o += fmt::format("{} rotary axis(es), {} circular test(s); u k = 1, 95 % intervals in the JSON\n",
                   report.axes.size(), report.circles.size());
  for (const auto& a : report.axes) o += BbAxisText(a);
  for (const auto& c : report.circles) o += BbCircleText(c);
  return o;
}

}  // namespace tpcal::pipeline
