#include "pipeline/diagnosis/diagnosis_candidates.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "core/parallel.h"
#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/forward_kinematics.h"
#include "testpieces/process_effects.h"

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

std::vector<MachineSpec> MachineSpecs(const kinematics::MachineModel& m, double duration_s,
                                      std::vector<std::pair<std::string, std::string>>* not_applicable) {
  std::vector<MachineSpec> specs;
  // Rotary axes: the first on the workpiece branch carries the part; the last is the spindle-like table.
  std::vector<Axis> rotary;
  for (Axis a : {Axis::kA, Axis::kB, Axis::kC})
    if (m.HasAxis(a)) rotary.push_back(a);
  const std::string letters = "XYZABC";
  auto L = [&](Axis a) { return std::string(1, letters[static_cast<std::size_t>(kinematics::AxisIndex(a))]); };

  // thermal_drift
  if (!rotary.empty()) {
    std::vector<std::string> params;
    const std::string first = L(rotary.front());
    for (const char* d : {"X", "Y", "Z"}) params.push_back(std::string("E_") + d + "0" + first);
    if (rotary.size() > 1) {
      const std::string last = L(rotary.back());
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
    specs.push_back(lin);
    specs.push_back(ex);
  } else {
    MachineSpec sq{"thermal_drift", "linear drift of the squareness of X, Y, Z with machining time", {}};
    for (const char* p : {"E_C(0X)Y", "E_B(0X)Z", "E_A(0Y)Z"})
      sq.items.push_back(std::string("{thermal_drift: {parameter: ") + p + ", rate_urad_per_h: 0}}");
    specs.push_back(sq);
  }
  // linear_straightness
  {
    MachineSpec q{"linear_straightness", "quadratic straightness of X, Y, Z", {}};
    MachineSpec c{"linear_straightness", "quadratic to quartic straightness of X, Y, Z", {}};
    MachineSpec x{"linear_straightness", "quadratic to sextic straightness of X, Y, Z", {}};
    const char* syms[] = {"E_YX", "E_ZX", "E_XY", "E_ZY", "E_XZ", "E_YZ"};
    for (const char* s : syms) {
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
    specs.push_back(q);
    specs.push_back(c);
    specs.push_back(x);
  }
  // linear_positioning
  {
    MachineSpec s1{"linear_positioning", "scale error of X, Y, Z", {}};
    MachineSpec s2{"linear_positioning", "scale and quadratic positioning error of X, Y, Z", {}};
    for (const char* s : {"E_XX", "E_YY", "E_ZZ"}) {
      const std::string i1 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [1]}}";
      const std::string i2 = std::string("{linear_error_motion: {symbol: ") + s + ", coefficients_um_per_mm_pow: [0], powers: [2]}}";
      s1.items.push_back(i1);
      s2.items.push_back(i1);
      s2.items.push_back(i2);
    }
    specs.push_back(s1);
    specs.push_back(s2);
  }
  // rotary_error_motion and rotary_positioning of the last rotary axis
  if (!rotary.empty()) {
    const std::string k = L(rotary.back());
    const std::string h_um = Harmonics(2, 5, "um"), h_urad = Harmonics(2, 5, "urad");
    auto item = [&](const std::string& sym, const std::string& h) {
      return "{rotary_error_motion: {symbol: " + sym + ", harmonics: " + h + "}}";
    };
    std::string radial_a = "X", radial_b = "Y", tilt_a = "A", tilt_b = "B";
    if (k == "A") { radial_a = "Y"; radial_b = "Z"; tilt_a = "B"; tilt_b = "C"; }
    if (k == "B") { radial_a = "X"; radial_b = "Z"; tilt_a = "A"; tilt_b = "C"; }
    const std::string axial = k == "A" ? "X" : k == "B" ? "Y" : "Z";
    specs.push_back({"rotary_error_motion", "radial error motion of " + k + ", 2 to 5 lobes",
                     {item("E_" + radial_a + k, h_um), item("E_" + radial_b + k, h_um)}});
    specs.push_back({"rotary_error_motion", "axial error motion of " + k + ", 2 to 5 lobes", {item("E_" + axial + k, h_um)}});
    specs.push_back({"rotary_error_motion", "tilt error motion of " + k + ", 2 to 5 lobes",
                     {item("E_" + tilt_a + k, h_urad), item("E_" + tilt_b + k, h_urad)}});
    specs.push_back({"rotary_positioning", "angular positioning error of " + k + ", orders 1 to 4",
                     {"{rotary_error_motion: {symbol: E_" + k + k + ", harmonics: " + Harmonics(1, 4, "urad") + "}}"}});
  } else {
    not_applicable->push_back({"rotary_error_motion", "the machine has no rotary axis"});
    not_applicable->push_back({"rotary_positioning", "the machine has no rotary axis"});
  }
  return specs;
}

double Wrap2Pi(double a) {
  a = std::fmod(a, 2.0 * std::numbers::pi);
  return a < 0 ? a + 2.0 * std::numbers::pi : a;
}

// Drops all-zero columns (the effect never acts on this piece).
void DropZeroColumns(CandidateColumns* c) {
  std::vector<int> keep;
  for (int j = 0; j < c->J_dev_effect.cols(); ++j)
    if (c->J_dev_effect.col(j).squaredNorm() > 1e-20) keep.push_back(j);
  if (static_cast<int>(keep.size()) == c->J_dev_effect.cols()) return;
  Eigen::MatrixXd J(c->J_dev_effect.rows(), static_cast<Eigen::Index>(keep.size()));
  std::vector<std::string> names, units;
  for (std::size_t k = 0; k < keep.size(); ++k) {
    J.col(static_cast<Eigen::Index>(k)) = c->J_dev_effect.col(keep[k]);
    names.push_back(c->parameter_names[static_cast<std::size_t>(keep[k])]);
    units.push_back(c->units[static_cast<std::size_t>(keep[k])]);
  }
  c->J_dev_effect = std::move(J);
  c->parameter_names = std::move(names);
  c->units = std::move(units);
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
};

Result<MachineCandidates> CombineMachineCandidates(const testpieces::TestPiece& piece,
                                                   const kinematics::MachineModel& machine,
                                                   const kinematics::ErrorState& errors,
                                                   const std::vector<std::string>& base_names, bool reference_mode,
                                                   std::vector<std::pair<std::string, std::string>>* not_applicable) {
  MachineCandidates mc{MachineSpecs(machine, piece.duration_s(), not_applicable), errors, {}, {}, {}};
  for (const auto& spec : mc.specs) {
    for (const auto& item : spec.items) {
      if (mc.item_names.count(item)) continue;
      auto parsed = kinematics::ParseErrorState("effects: [" + item + "]", "<diagnosis candidate>", machine);
      if (!parsed.ok()) { mc.item_names[item] = {}; continue; }  // not on this machine
      std::vector<std::string> names;
      for (int c = 0; c < parsed->num_coefficients(); ++c) names.push_back(parsed->coefficient_info(c).name);
      bool ok = true;
      for (const auto& t : parsed->terms())
        if (!mc.combined.AddTerm(machine, t).ok()) ok = false;
      if (!ok) names.clear();
      mc.item_names[item] = names;
      mc.lin_names.insert(mc.lin_names.end(), names.begin(), names.end());
    }
  }
  if (reference_mode) mc.lin_names.insert(mc.lin_names.end(), base_names.begin(), base_names.end());
  if (!mc.lin_names.empty()) {
    auto active = kinematics::SelectCoefficients(mc.combined, mc.lin_names);
    if (!active.ok()) return active.status();
    mc.active = *active;
  }
  return mc;
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
  const auto& obs = mo.observations;
  const auto n = static_cast<Eigen::Index>(obs.size());

  // ---- machine-error families: one linearisation with every candidate coefficient active.
  auto mc = CombineMachineCandidates(piece, machine, errors, base_names, reference_mode, &out.not_applicable);
  if (!mc.ok()) return mc.status();
  const auto& specs = mc->specs;
  const auto& combined = mc->combined;
  const auto& lin_names = mc->lin_names;
  auto& item_names = mc->item_names;
  if (!lin_names.empty()) {
    const kinematics::ActiveSet* active = &mc->active;
    Eigen::MatrixXd J_lin;
    if (design) {
      auto J = kinematics::CoefficientColumns(*design, combined, active->coefficients, obs);
      if (!J.ok()) return J.status();
      J_lin = std::move(*J);
    } else {
      auto lin = kinematics::LineariseBySlots(machine, combined, active->coefficients, obs);
      if (!lin.ok()) return lin.status();
      J_lin = std::move(lin->J_dev_params);
    }
    std::map<std::string, int> col;
    for (std::size_t k = 0; k < lin_names.size(); ++k) col[lin_names[k]] = static_cast<int>(k);
    std::vector<bool> zero(static_cast<std::size_t>(J_lin.cols()));
    for (Eigen::Index j = 0; j < J_lin.cols(); ++j) zero[static_cast<std::size_t>(j)] = J_lin.col(j).squaredNorm() <= 1e-20;
    const auto shared = std::make_shared<const Eigen::MatrixXd>(std::move(J_lin));
    // Columns that never act on this piece are left out (as DropZeroColumns does).
    auto make = [&](const std::string& family, const std::string& name, const std::vector<std::string>& names) {
      CandidateColumns c{family, name, {}, {}, {}, shared, {}};
      for (const auto& nm : names) {
        const int j = col.at(nm);
        if (zero[static_cast<std::size_t>(j)]) continue;
        c.shared_columns.push_back(j);
        c.parameter_names.push_back(nm);
        c.units.push_back(combined.coefficient_info(active->coefficients[static_cast<std::size_t>(j)]).unit);
      }
      return c;
    };
    for (const auto& spec : specs) {
      std::vector<std::string> names;
      for (const auto& item : spec.items) {
        const auto& v = item_names[item];
        names.insert(names.end(), v.begin(), v.end());
      }
      if (names.empty()) continue;
      out.candidates.push_back(make(spec.family, spec.name, names));
    }
    if (reference_mode) out.candidates.push_back(make("location_errors", "location errors and squareness refitted", base_names));
  }

  // ---- process families: columns from the cut model.
  std::vector<Eigen::Vector3d> nm(static_cast<std::size_t>(n));
  const kinematics::ErrorState zero(machine);
  std::vector<Eigen::Matrix3d> mfp(static_cast<std::size_t>(n));
  ParallelChunks(static_cast<std::size_t>(n), 8192, [&](std::size_t begin, std::size_t end) {
    kinematics::Workspace ws;
    for (std::size_t i = begin; i < end; ++i) {
      mfp[i] = kinematics::MachineFromPart(machine, zero, obs[i].cut.axes, &ws).linear();
      nm[i] = mfp[i] * obs[i].cut.nominal_normal;
    }
    return true;
  });
  // The cut of each feature (looked up once per feature, not per point).
  std::vector<const testpieces::FeatureCut*> cut_of_group(mo.feature_names.size());
  for (std::size_t g = 0; g < mo.feature_names.size(); ++g) cut_of_group[g] = piece.Cut(mo.feature_names[g]);
  auto cut_of = [&](Eigen::Index i) { return cut_of_group[static_cast<std::size_t>(obs[static_cast<std::size_t>(i)].group)]; };
  {  // tool_deflection
    enum Class { kTurnSide, kTurnFace, kMillSide, kMillFloor, kNumClasses };
    const char* class_names[] = {"turned_side", "turned_face", "milled_wall", "milled_floor"};
    const int per_class = 4;  // xx, yy, zz, xy
    CandidateColumns c{"tool_deflection",
                       "cutting-force deflection: compliance along machine X, Y, Z per cut class, force along the normal",
                       Eigen::MatrixXd::Zero(n, kNumClasses * per_class), {}, {}, {}, {}};
    for (int k = 0; k < kNumClasses; ++k)
      for (const char* comp : {"xx", "yy", "zz", "xy"}) {
        c.parameter_names.push_back(std::string(class_names[k]) + ".c_" + comp);
        c.units.push_back("um");
      }
    for (Eigen::Index i = 0; i < n; ++i) {
      const testpieces::FeatureCut* fc = cut_of(i);
      if (!fc) continue;
      int cls = -1;
      if (const auto* t = std::get_if<testpieces::TurnedCut>(&fc->model)) cls = t->radial_feed ? kTurnFace : kTurnSide;
      if (const auto* m = std::get_if<testpieces::PathMillCut>(&fc->model)) cls = m->end_face ? kMillFloor : kMillSide;
      if (cls < 0) continue;
      const Eigen::Vector3d& v = nm[static_cast<std::size_t>(i)];
      c.J_dev_effect(i, cls * per_class + 0) = v.x() * v.x();
      c.J_dev_effect(i, cls * per_class + 1) = v.y() * v.y();
      c.J_dev_effect(i, cls * per_class + 2) = v.z() * v.z();
      c.J_dev_effect(i, cls * per_class + 3) = v.x() * v.y();
    }
    DropZeroColumns(&c);
    if (c.J_dev_effect.cols() > 0) out.candidates.push_back(std::move(c));
    else out.not_applicable.push_back({"tool_deflection", "no turned or milled feature is measured"});
  }
  {  // servo_reversal
    CandidateColumns spikes{"servo_reversal", "quadrant glitches at X and Y reversals of circular interpolation",
                            Eigen::MatrixXd::Zero(n, 2), {"glitch_X", "glitch_Y"}, {"um", "um"}, {}, {}};
    CandidateColumns lost{"servo_reversal", "quadrant glitches and lost motion (backlash) of X and Y",
                          Eigen::MatrixXd::Zero(n, 4), {"glitch_X", "glitch_Y", "backlash_X", "backlash_Y"},
                          {"um", "um", "um", "um"}, {}, {}};
    const double half_width = DegToRad(12.0);
    struct Crossing { double theta; Eigen::Vector3d outward; int axis; };
    const Crossing crossings[4] = {{0.0, Eigen::Vector3d::UnitX(), 0},
                                   {std::numbers::pi, -Eigen::Vector3d::UnitX(), 0},
                                   {0.5 * std::numbers::pi, Eigen::Vector3d::UnitY(), 1},
                                   {1.5 * std::numbers::pi, -Eigen::Vector3d::UnitY(), 1}};
    for (Eigen::Index i = 0; i < n; ++i) {
      const testpieces::FeatureCut* fc = cut_of(i);
      if (!fc) continue;
      const auto& o = obs[static_cast<std::size_t>(i)];
      auto arc = testpieces::ArcTravelAt(*fc, o.cut.nominal_point_mm, mfp[static_cast<std::size_t>(i)]);
      if (!arc) continue;
      const double alpha_p = Wrap2Pi(arc->direction * (arc->theta_rad - arc->theta_start_rad));
      double last_alpha[2] = {-1, -1};
      double last_proj[2] = {0, 0};
      for (const auto& cr : crossings) {
        const double alpha_c = Wrap2Pi(arc->direction * (cr.theta - arc->theta_start_rad));
        if (alpha_c > alpha_p || alpha_c > arc->sweep_rad) continue;
        const double phi = alpha_p - alpha_c;
        const double proj = nm[static_cast<std::size_t>(i)].dot(cr.outward);
        const double tri = std::max(0.0, 1.0 - phi / half_width);
        spikes.J_dev_effect(i, cr.axis) += tri * proj;
        lost.J_dev_effect(i, cr.axis) += tri * proj;
        if (alpha_c > last_alpha[cr.axis]) { last_alpha[cr.axis] = alpha_c; last_proj[cr.axis] = proj; }
      }
      lost.J_dev_effect(i, 2) = last_proj[0];
      lost.J_dev_effect(i, 3) = last_proj[1];
    }
    DropZeroColumns(&spikes);
    DropZeroColumns(&lost);
    if (spikes.J_dev_effect.cols() > 0) out.candidates.push_back(std::move(spikes));
    if (lost.J_dev_effect.cols() > 0) out.candidates.push_back(std::move(lost));
    if (out.candidates.empty() || out.candidates.back().family != "servo_reversal")
      out.not_applicable.push_back({"servo_reversal", "no feature is side-milled on a circle interpolated in machine X-Y"});
  }
  {  // probe_radius
    CandidateColumns r{"probe_radius", "CMM probe-radius error", Eigen::MatrixXd::Ones(n, 1), {"probe_radius_error"}, {"um"}, {}, {}};
    CandidateColumns rs{"probe_radius", "CMM probe-radius and scale error", Eigen::MatrixXd::Ones(n, 2),
                        {"probe_radius_error", "scale"}, {"um", "ppm"}, {}, {}};
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& o = obs[static_cast<std::size_t>(i)];
      rs.J_dev_effect(i, 1) = 1e-3 * o.cut.nominal_normal.dot(o.cut.nominal_point_mm);  // um per ppm
    }
    out.candidates.push_back(std::move(r));
    out.candidates.push_back(std::move(rs));
  }
  return out;
}

}  // namespace tpcal::pipeline
