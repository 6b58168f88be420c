#include "kinematics/slot_linearisation.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "core/parallel.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics {

std::vector<ErrorSlot> SlotsOf(const ErrorState& errors, const std::vector<int>& coefficients) {
  std::vector<ErrorSlot> slots;
  for (int c : coefficients) {
    const auto& term = errors.terms()[static_cast<std::size_t>(errors.coefficient_info(c).term)];
    for (const auto& e : term.effects)
      if (std::find(slots.begin(), slots.end(), ErrorSlot{e.axis, e.component}) == slots.end())
        slots.push_back(ErrorSlot{e.axis, e.component});
  }
  return slots;
}

void AddSlots(const std::vector<ErrorSlot>& more, std::vector<ErrorSlot>* slots) {
  for (const ErrorSlot& s : more)
    if (std::find(slots->begin(), slots->end(), s) == slots->end()) slots->push_back(s);
}

Result<SlotDesign> LineariseSlots(const MachineModel& machine, const ErrorState& errors,
                                  const std::vector<ErrorSlot>& slots, std::span<const Observation> obs) {
  SlotDesign out;
  out.slots = slots;
  // The state without its zero-valued terms (the candidate terms): they add exactly 0 to every
  // link error, and would only be evaluated at every chain call.
  ErrorState nonzero(machine);
  for (const auto& t : errors.terms()) {
    if (std::all_of(t.coefficients.begin(), t.coefficients.end(), [](double c) { return c == 0.0; })) continue;
    if (Status st = nonzero.AddTerm(machine, t); !st.ok()) return st.WithContext("diagnosis slot design");
  }
  auto lin = LineariseSlotObservations(machine, nonzero, out.slots, obs);
  if (!lin.ok()) return lin.status();
  out.dslot_um = std::move(lin->J_dev_params);
  lin->J_dev_params.resize(static_cast<Eigen::Index>(obs.size()), 0);
  out.lin = std::move(*lin);
  return out;
}

Result<Eigen::MatrixXd> CoefficientColumns(const SlotDesign& design, const ErrorState& errors,
                                           const std::vector<int>& coefficients,
                                           std::span<const Observation> obs) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  if (design.dslot_um.rows() != n)
    return Status(StatusCode::kInvalidArgument, "diagnosis: slot design of " + std::to_string(design.dslot_um.rows()) +
                                                    " observations for " + std::to_string(n));
  // Chain rule per coefficient (the basis of each term evaluated once per point for all its
  // coefficients), over the points on all cores (each point writes its own row).
  // Not zero-filled here: every column belongs to one term, which writes all its rows (the first
  // touch of the pages then happens on the worker threads, not serially).
  Eigen::MatrixXd J(n, static_cast<Eigen::Index>(coefficients.size()));
  struct Column {
    Eigen::Index j;              // column of J
    std::size_t basis;           // index in the term's basis
    double per_display;          // 1 / display_per_internal
  };
  struct TermColumns {
    const ErrorTerm* term;
    std::vector<Column> columns;
    std::vector<std::pair<int, double>> slot_gain;
  };
  std::map<int, TermColumns> by_term;
  for (std::size_t j = 0; j < coefficients.size(); ++j) {
    const auto& info = errors.coefficient_info(coefficients[j]);
    const int t = info.term;
    auto [it, inserted] = by_term.try_emplace(t, TermColumns{&errors.terms()[static_cast<std::size_t>(t)], {}, {}});
    it->second.columns.push_back(
        {static_cast<Eigen::Index>(j), static_cast<std::size_t>(info.index), 1.0 / info.display_per_internal});
    if (!inserted) continue;
    for (const auto& e : it->second.term->effects) {
      const auto at = std::find(design.slots.begin(), design.slots.end(), ErrorSlot{e.axis, e.component});
      if (at == design.slots.end())
        return Status(StatusCode::kInvalidArgument,
                      "diagnosis: term " + it->second.term->label + " writes a slot the design lacks");
      it->second.slot_gain.emplace_back(static_cast<int>(at - design.slots.begin()), e.gain);
    }
  }
  // Qualified: identification.cc has a file-local ParallelChunks of its own (unity builds).
  tpcal::ParallelChunks(static_cast<std::size_t>(n), 8192, [&](std::size_t begin, std::size_t end) {
    std::vector<double> w;
    for (const auto& [term_index, tc] : by_term) {
      for (std::size_t ii = begin; ii < end; ++ii) {
        const auto i = static_cast<Eigen::Index>(ii);
        EvaluateTermBasis(*tc.term, obs[ii].cut.axes, &w);
        double v = 0;
        for (const auto& [k, g] : tc.slot_gain) v += g * design.dslot_um(i, k);
        for (const Column& c : tc.columns) {
          const double b = w[c.basis];
          J(i, c.j) = b != 0.0 ? b * v * c.per_display : 0.0;
        }
      }
    }
    return true;
  });
  return J;
}

Result<LinearDesign> LineariseBySlots(const MachineModel& machine, const ErrorState& errors,
                                      const std::vector<int>& coefficients, std::span<const Observation> obs) {
  auto design = LineariseSlots(machine, errors, SlotsOf(errors, coefficients), obs);
  if (!design.ok()) return design.status();
  auto J = CoefficientColumns(*design, errors, coefficients, obs);
  if (!J.ok()) return J.status();
  LinearDesign lin = std::move(design->lin);
  lin.J_dev_params = std::move(*J);
  return lin;
}

namespace {

Eigen::MatrixXd SelectRows(const Eigen::MatrixXd& m, std::span<const int> rows) {
  if (m.rows() == 0) return m;
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), m.cols());
  if (m.cols() == 0) return out;  // row() of a matrix without storage offsets a null pointer
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = m.row(rows[k]);
  return out;
}

}  // namespace

LinearDesign RowsOf(const LinearDesign& design, std::span<const int> rows) {
  LinearDesign out;
  out.J_dev_params = SelectRows(design.J_dev_params, rows);
  out.J_dev_alignment = SelectRows(design.J_dev_alignment, rows);
  out.measured_dev_um = SelectRows(design.measured_dev_um, rows);
  out.predicted_dev_um = SelectRows(design.predicted_dev_um, rows);
  return out;
}

SlotDesign RowsOf(const SlotDesign& design, std::span<const int> rows) {
  SlotDesign out;
  out.slots = design.slots;
  out.dslot_um = SelectRows(design.dslot_um, rows);
  out.lin = RowsOf(design.lin, rows);
  return out;
}

Eigen::Vector3d MachineNormal(const MachineModel& machine, const Observation& o) {
  const ErrorState zero(machine);
  Workspace ws;
  return MachineFromPart(machine, zero, o.cut.axes, &ws).linear() * o.cut.nominal_normal;
}

}  // namespace tpcal::kinematics
