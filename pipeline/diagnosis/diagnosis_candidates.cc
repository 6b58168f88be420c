#include "pipeline/diagnosis/diagnosis_candidates.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <span>
#include <utility>

#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/diagnosis/diagnosis_process_candidates.h"
#include "pipeline/diagnosis/straightness_lines.h"

namespace tpcal::pipeline {
namespace {

using kinematics::Axis;

struct MachineSpec {
  std::string family, name;
  std::vector<std::string> items;  // errors_yaml effect items (YAML flow maps), values zero
};

std::string Harmonics(int first, int last, const char* unit) {
  std::string h = "[";
  for (int k = first; k <= last; ++k) {
    if (k > first) h += ", ";
    h += "{order: " + std::to_string(k) + ", cos_" + unit + ": 0, sin_" + unit + ": 0}";
  }
  return h + "]";
}

std::string AxisString(Axis a) {
  const std::string letters = "XYZABC";
  return std::string(1, letters[static_cast<std::size_t>(kinematics::AxisIndex(a))]);
}

// thermal_drift: with rotary axes, linear and exponential drift of the workpiece-branch
// translations (and the last rotary axis' line) and, with two, linear drift of the last one's
// tilt and of Z's squareness; without, linear drift of the squareness.
void ThermalDriftSpecs(const std::vector<Axis>& rotary, double duration_s, std::vector<MachineSpec>* specs) {
  if (!rotary.empty()) {
    std::vector<std::string> params;
    const std::string first = AxisString(rotary.front());
    for (const char* d : {"X", "Y", "Z"}) params.push_back(std::string("E_") + d + "0" + first);
    if (rotary.size() > 1) {
      const std::string last = AxisString(rotary.back());
      params.push_back("E_Y0" + last);
      params.push_back("E_Z0" + last);
    }
    MachineSpec lin{"thermal_drift", "linear drift of the table position (X, Y, Z and C line) with machining time", {}};
    MachineSpec ex{"thermal_drift", "", {}};
    const double tau_s = std::max(60.0, duration_s / 3.0);
    ex.name = "exponential drift of the table position, tau = " + std::to_string(static_cast<int>(std::lround(tau_s))) + " s";
    for (const auto& p : params) {
      lin.items.push_back("{thermal_drift: {parameter: " + p + ", rate_um_per_h: 0}}");
      ex.items.push_back("{thermal_drift: {parameter: " + p + ", K_um: 0, tau_s: " + std::to_string(tau_s) + "}}");
    }
    specs->push_back(lin);
    specs->push_back(ex);
    if (rotary.size() > 1) {  // spindle and column heat tilt the table's line against the Z column
      const std::string last = AxisString(rotary.back());
      MachineSpec tilt{"thermal_drift", "linear drift of the " + last + " line's tilt and of Z's squareness with machining time", {}};
      for (const std::string& p : {"E_A0" + last, "E_B0" + last, std::string("E_B(0X)Z"), std::string("E_A(0Y)Z")})
        tilt.items.push_back("{thermal_drift: {parameter: " + p + ", rate_urad_per_h: 0}}");
      specs->push_back(tilt);
    }
  } else {
    MachineSpec sq{"thermal_drift", "linear drift of the squareness of X, Y, Z with machining time", {}};
    for (const std::string& p : kinematics::LinearSquarenessSet())
      sq.items.push_back("{thermal_drift: {parameter: " + p + ", rate_urad_per_h: 0}}");
    specs->push_back(sq);
  }
}

// linear_straightness (quadratic; quadratic to quartic; to sextic of X, Y, Z; quadratic to quartic
// of each axis in each direction) and linear_positioning (scale; scale and quadratic) of X, Y, Z.
void LinearAxisSpecs(std::vector<MachineSpec>* specs) {
  MachineSpec q{"linear_straightness", "quadratic straightness of X, Y, Z", {}};
  MachineSpec c{"linear_straightness", "quadratic to quartic straightness of X, Y, Z", {}};
  MachineSpec x{"linear_straightness", "quadratic to sextic straightness of X, Y, Z", {}};
  for (const std::string& s : diagnosis_internal::StraightnessSymbols()) {
    const std::string i2 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [2]}}";
    const std::string i3 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [3]}}";
    const std::string i4 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [4]}}";
    q.items.push_back(i2);
    c.items.push_back(i2);
    c.items.push_back(i3);
    c.items.push_back(i4);
    for (int k = 2; k <= 6; ++k)
      x.items.push_back(std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [" + std::to_string(k) + "]}}");
  }
  specs->push_back(q);
  specs->push_back(c);
  specs->push_back(x);
  for (const std::string& s : diagnosis_internal::StraightnessSymbols()) {
    // One axis in one direction (E_ZY: Y's motion in Z), rank 3 against the six symbols' 18
    // together: a bow of one axis then competes with smaller models (changed location errors, a
    // drift, positioning) without carrying the other five symbols' directions.
    MachineSpec one{"linear_straightness",
                    "quadratic to quartic straightness of " + s.substr(3, 1) + " in " + s.substr(2, 1) + " (" + s + ")", {}};
    for (int k = 2; k <= 4; ++k)
      one.items.push_back("{linear_error_motion: {symbol: " + s + ", coefficients_um_per_mm_pow: [0], powers: [" + std::to_string(k) + "]}}");
    specs->push_back(one);
  }
  MachineSpec s1{"linear_positioning", "scale error of X, Y, Z", {}};
  MachineSpec s2{"linear_positioning", "scale and quadratic positioning error of X, Y, Z", {}};
  for (const char* s : {"E_XX", "E_YY", "E_ZZ"}) {
    const std::string i1 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [1]}}";
    const std::string i2 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [2]}}";
    s1.items.push_back(i1);
    s2.items.push_back(i1);
    s2.items.push_back(i2);
  }
  specs->push_back(s1);
  specs->push_back(s2);
}

// rotary_error_motion (radial, axial, tilt: 2 to 5 lobes; with `motions`) and rotary_positioning
// (orders 1 to 4) of the rotary axis `k_axis`.
void RotaryAxisSpecs(Axis k_axis, bool motions, std::vector<MachineSpec>* specs) {
  const std::string k = AxisString(k_axis);
  const std::string h_um = Harmonics(2, 5, "um"), h_urad = Harmonics(2, 5, "urad");
  auto item = [&](const std::string& sym, const std::string& h) {
    return "{rotary_error_motion: {symbol: " + sym + ", harmonics: " + h + "}}";
  };
  std::string radial_a = "X", radial_b = "Y", tilt_a = "A", tilt_b = "B";
  if (k == "A") { radial_a = "Y"; radial_b = "Z"; tilt_a = "B"; tilt_b = "C"; }
  if (k == "B") { radial_a = "X"; radial_b = "Z"; tilt_a = "A"; tilt_b = "C"; }
  const std::string axial = k == "A" ? "X" : k == "B" ? "Y" : "Z";
  if (motions) {
    specs->push_back({"rotary_error_motion", "radial error motion of " + k + ", 2 to 5 lobes",
                      {item("E_" + radial_a + k, h_um), item("E_" + radial_b + k, h_um)}});
    specs->push_back({"rotary_error_motion", "axial error motion of " + k + ", 2 to 5 lobes", {item("E_" + axial + k, h_um)}});
    specs->push_back({"rotary_error_motion", "tilt error motion of " + k + ", 2 to 5 lobes",
                      {item("E_" + tilt_a + k, h_urad), item("E_" + tilt_b + k, h_urad)}});
  }
  specs->push_back({"rotary_positioning", "angular positioning error of " + k + ", orders 1 to 4",
                    {"{rotary_error_motion: {symbol: E_" + k + k + ", harmonics: " + Harmonics(1, 4, "urad") + "}}"}});
}

std::vector<MachineSpec> MachineSpecs(const kinematics::MachineModel& m, double duration_s,
                                      std::vector<std::pair<std::string, std::string>>* not_applicable) {
  std::vector<MachineSpec> specs;
  // Rotary axes in A, B, C order: C, the last, is the spindle-like table on every machine here.
  std::vector<Axis> rotary;
  for (Axis a : {Axis::kA, Axis::kB, Axis::kC})
    if (m.HasAxis(a)) rotary.push_back(a);
  ThermalDriftSpecs(rotary, duration_s, &specs);
  LinearAxisSpecs(&specs);
  if (!rotary.empty()) {
    RotaryAxisSpecs(rotary.back(), true, &specs);
    // The other rotary axis (A of an A/C table, B of a B/C one): its angular positioning only. Its
    // error motions at the few angles a piece uses act as offsets per angle, which the location
    // errors also hold: against a reference, A's axial motion takes a location error of the
    // reference (Diagnosis.ReferenceUncertaintyIsFittedNotBlamed).
    for (std::size_t i = 0; i + 1 < rotary.size(); ++i) RotaryAxisSpecs(rotary[i], false, &specs);
  } else {
    not_applicable->push_back({"rotary_error_motion", "the machine has no rotary axis"});
    not_applicable->push_back({"rotary_positioning", "the machine has no rotary axis"});
  }
  return specs;
}

// The machine-error candidates as zero-valued terms added to `errors` (`combined`), the
// coefficient names of each effect item, and the coefficients to linearise (`active`, named
// `lin_names`: every candidate coefficient, plus the base set in reference mode).
struct MachineCandidates {
  std::vector<MachineSpec> specs;
  kinematics::ErrorState combined;
  std::map<std::string, std::vector<std::string>> item_names;  // item -> coefficient names
  std::vector<std::string> lin_names;
  kinematics::ActiveSet active;
  // Straightness term label -> its reference line's coefficient names (power 0, power 1).
  std::map<std::string, std::pair<std::string, std::string>> line_names;
};

// Adds the zero-valued terms of one effect item to mc.combined and records their coefficient
// names (none when the item does not apply to this machine).
void AddItem(const kinematics::MachineModel& machine, const std::string& item, MachineCandidates* mc) {
  if (mc->item_names.count(item)) return;
  auto parsed = kinematics::ParseErrorState("effects: [" + item + "]", "<diagnosis candidate>", machine);
  if (!parsed.ok()) { mc->item_names[item] = {}; return; }  // not on this machine
  std::vector<std::string> names;
  for (int c = 0; c < parsed->num_coefficients(); ++c) names.push_back(parsed->coefficient_info(c).name);
  bool ok = true;
  for (const auto& t : parsed->terms())
    if (!mc->combined.AddTerm(machine, t).ok()) ok = false;
  if (!ok) names.clear();
  mc->item_names[item] = names;
  mc->lin_names.insert(mc->lin_names.end(), names.begin(), names.end());
}

Result<MachineCandidates> CombineMachineCandidates(const testpieces::TestPiece& piece,
                                                   const kinematics::MachineModel& machine,
                                                   const kinematics::ErrorState& errors,
                                                   const std::vector<std::string>& base_names, bool reference_mode,
                                                   std::vector<std::pair<std::string, std::string>>* not_applicable) {
  MachineCandidates mc{MachineSpecs(machine, piece.duration_s(), not_applicable), errors, {}, {}, {}, {}};
  for (const auto& spec : mc.specs)
    for (const auto& item : spec.items) AddItem(machine, item, &mc);
  for (const std::string& symbol : diagnosis_internal::StraightnessSymbols()) {
    const std::string item = diagnosis_internal::ReferenceLineItem(symbol);
    AddItem(machine, item, &mc);
    if (mc.item_names[item].size() == 2) mc.line_names[symbol] = {mc.item_names[item][0], mc.item_names[item][1]};
  }
  if (reference_mode) mc.lin_names.insert(mc.lin_names.end(), base_names.begin(), base_names.end());
  if (!mc.lin_names.empty()) {
    auto active = kinematics::SelectCoefficients(mc.combined, mc.lin_names);
    if (!active.ok()) return active.status();
    mc.active = *active;
  }
  return mc;
}

// The columns of every machine-error candidate coefficient (and the base set in reference mode):
// from the caller's slot design at `errors` when given, else linearised here.
Result<Eigen::MatrixXd> MachineCandidateColumns(const kinematics::MachineModel& machine,
                                                std::span<const kinematics::Observation> obs,
                                                const MachineCandidates& mc, const kinematics::SlotDesign* design) {
  if (design) return kinematics::CoefficientColumns(*design, mc.combined, mc.active.coefficients, obs);
  auto lin = kinematics::LineariseBySlots(machine, mc.combined, mc.active.coefficients, obs);
  if (!lin.ok()) return lin.status();
  return std::move(lin->J_dev_params);
}

// Candidates sharing one matrix of columns (CandidateColumns::shared); columns that never act on
// this piece are left out (as DropZeroColumns does for the process candidates).
class SharedCandidates {
 public:
  SharedCandidates(Eigen::MatrixXd J_lin, const MachineCandidates& mc) : mc_(mc) {
    for (std::size_t k = 0; k < mc.lin_names.size(); ++k) col_[mc.lin_names[k]] = static_cast<int>(k);
    zero_.resize(static_cast<std::size_t>(J_lin.cols()));
    for (Eigen::Index j = 0; j < J_lin.cols(); ++j) zero_[static_cast<std::size_t>(j)] = J_lin.col(j).squaredNorm() <= 1e-20;
    shared_ = std::make_shared<const Eigen::MatrixXd>(std::move(J_lin));
  }

  CandidateColumns Make(const std::string& family, const std::string& name, const std::vector<std::string>& names) const {
    CandidateColumns c{family, name, {}, {}, {}, shared_, {}};
    for (const auto& nm : names) {
      const int j = col_.at(nm);
      if (zero_[static_cast<std::size_t>(j)]) continue;
      c.shared_columns.push_back(j);
      c.parameter_names.push_back(nm);
      c.units.push_back(mc_.combined.coefficient_info(mc_.active.coefficients[static_cast<std::size_t>(j)]).unit);
    }
    return c;
  }

 private:
  const MachineCandidates& mc_;
  std::map<std::string, int> col_;
  std::vector<bool> zero_;
  std::shared_ptr<const Eigen::MatrixXd> shared_;
};

// One candidate per machine spec with coefficients on this machine, and in reference mode the
// base set refitted (`location_errors`).
Status AddMachineCandidates(const kinematics::MachineModel& machine, std::span<const kinematics::Observation> obs,
                            MachineCandidates& mc, const std::vector<std::string>& base_names, bool reference_mode,
                            const kinematics::SlotDesign* design, CandidateCatalogue* out) {
  auto J_lin = MachineCandidateColumns(machine, obs, mc, design);
  if (!J_lin.ok()) return J_lin.status();
  std::map<std::string, std::pair<int, int>> line_columns;
  auto column_of = [&](const std::string& name) {
    return static_cast<int>(std::find(mc.lin_names.begin(), mc.lin_names.end(), name) - mc.lin_names.begin());
  };
  for (const auto& [symbol, names] : mc.line_names) line_columns[symbol] = {column_of(names.first), column_of(names.second)};
  diagnosis_internal::RemoveReferenceLines(obs, mc.combined, mc.active.coefficients, line_columns, &*J_lin);
  const SharedCandidates shared(std::move(*J_lin), mc);
  for (const auto& spec : mc.specs) {
    std::vector<std::string> names;
    for (const auto& item : spec.items) {
      const auto& v = mc.item_names[item];
      names.insert(names.end(), v.begin(), v.end());
    }
    if (names.empty()) continue;
    out->candidates.push_back(shared.Make(spec.family, spec.name, names));
  }
  if (reference_mode) out->candidates.push_back(shared.Make("location_errors", "location errors and squareness refitted", base_names));
  return {};
}

}  // namespace

Result<std::vector<kinematics::ErrorSlot>> CandidateSlots(const testpieces::TestPiece& piece,
                                                          const kinematics::MachineModel& machine,
                                                          const kinematics::ErrorState& errors,
                                                          const std::vector<std::string>& base_names,
                                                          bool reference_mode) {
  std::vector<std::pair<std::string, std::string>> not_applicable;
  auto mc = CombineMachineCandidates(piece, machine, errors, base_names, reference_mode, &not_applicable);
  if (!mc.ok()) return mc.status();
  return kinematics::SlotsOf(mc->combined, mc->active.coefficients);
}

Result<CandidateCatalogue> BuildCandidates(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const kinematics::ErrorState& errors,
                                           const testpieces::MeasuredObservations& mo,
                                           const std::vector<std::string>& base_names, bool reference_mode,
                                           const kinematics::SlotDesign* design) {
  CandidateCatalogue out;
  // Machine-error families: one linearisation with every candidate coefficient active.
  auto mc = CombineMachineCandidates(piece, machine, errors, base_names, reference_mode, &out.not_applicable);
  if (!mc.ok()) return mc.status();
  if (!mc->lin_names.empty())
    TPCAL_RETURN_IF_ERROR(AddMachineCandidates(machine, mo.observations, *mc, base_names, reference_mode, design, &out));
  // Process families: columns from the cut model.
  diagnosis_internal::AddProcessCandidates(piece, machine, mo, &out);
  return out;
}

}  // namespace tpcal::pipeline
