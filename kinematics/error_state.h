// ErrorState: the values of a machine's errors, as a list of terms. Every term adds
//   value(state) = sum_k coefficient_k * basis_k(state)      (times the term's condition)
// with gain g to each of its slots (axis link, Component; conventions.h). Coefficients enter
// linearly, so identification can free any subset of them (ActiveSet) and differentiate exactly.
//
// Term kinds and their basis (q = position of the argument axis, mm or rad; t = AxisState::t_s):
//   kConstant         1                                   location / squareness / seed 002
//   kPolynomial       q^power_k                           linear-axis error motion (mm argument)
//   kFourier          cos(order_k q) or sin(order_k q)    rotary error motion
//   kTable            interpolation weight of node k      error map (1-D, or 2-D over a second axis)
//   kExponentialDrift 1 - exp(-(t - t0) / tau), 0 before t0   thermal drift, coefficient K
//   kLinearDrift      (t - t0), 0 before t0               thermal drift, coefficient = rate
//   kOperationOffset  1 in operation `op`                 per-operation offset
// The YAML form is documented in kinematics/errors_yaml.md.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/conventions.h"
#include "kinematics/error_parameters.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

enum class TermKind {
  kConstant, kPolynomial, kFourier, kTable, kExponentialDrift, kLinearDrift, kOperationOffset,
};
enum class Interpolation { kLinear, kCubic };  // kCubic: Catmull-Rom (linear in node values)

struct ErrorTerm {
  TermKind kind = TermKind::kConstant;
  // Stem of the coefficient names: a catalog parameter ("E_X0C"), or an ISO error-motion symbol
  // with its condition ("E_XC@A=0"). Coefficient names are label + suffix (see ErrorState).
  std::string label;
  std::vector<std::string> aliases;  // kConstant from the catalog: accepted alternative names
  Quantity quantity = Quantity::kLength;  // dimension of the term value (mm or rad)
  std::vector<SlotEffect> effects;
  Condition condition;

  // kPolynomial, kFourier, kTable: the axis whose position is the argument.
  Axis argument = Axis::kX;
  std::vector<int> powers;   // kPolynomial: power of each coefficient
  std::vector<int> orders;   // kFourier: harmonic order of each coefficient (>= 0)
  std::vector<bool> is_sine; // kFourier: sine (true) or cosine (false) of each coefficient
  // kTable: node positions (mm or rad, strictly increasing). A rotary argument with `periodic`
  // wraps over 2 pi (nodes within [0, 2 pi)); otherwise the value is held constant outside.
  std::vector<double> nodes;
  bool periodic = false;
  Interpolation interpolation = Interpolation::kLinear;
  // kTable, optional 2-D map: linear interpolation over a second axis, held outside.
  // Coefficient index = j * nodes.size() + i for node i of `argument`, node j of `second`.
  std::optional<Axis> second_argument;
  std::vector<double> second_nodes;
  double tau_s = 0.0;  // kExponentialDrift
  double t0_s = 0.0;   // drifts start at t0
  int op = 0;          // kOperationOffset

  std::vector<double> coefficients;  // internal units: mm or rad, per mm^power, per s (drift rate)
  // Checks sizes and values (nodes increasing, tau > 0, ...). `model` checks the slots exist.
  Status Validate(const MachineModel& model) const;
  // Number of coefficients the configuration implies.
  int ExpectedCoefficients() const;
};

// Name and units of one coefficient, for reports and YAML output.
struct CoefficientInfo {
  std::string name;      // "E_X0C", "E_YX.c2", "E_XC@A=0.cos2", "E_CC.n3", "E_X0C.drift_K"
  std::string unit;      // "um", "urad", "um_per_mm_pow2", "um_per_h", ...
  double display_per_internal = 1.0;  // value_in_unit = internal value * this
  int term = 0;          // index into terms()
  int index = 0;         // index into terms()[term].coefficients
};

class ErrorState {
 public:
  // Zero errors (no terms) for `model`.
  explicit ErrorState(const MachineModel& model);

  MachineType machine_type() const { return type_; }
  int num_links() const { return num_links_; }
  // Link index of each axis (-1 if absent), copied from the model.
  int LinkIndex(Axis a) const { return link_of_axis_[AxisIndex(a)]; }

  // Sets a catalog parameter (name or alias, LookupParameter) to `value` (mm or rad), adding a
  // kConstant term if needed. Fails on unknown names.
  Status SetParameter(const MachineModel& model, std::string_view name, double value);
  // Value of a catalog parameter's constant term (0 if not set); error if the name is unknown.
  Result<double> Parameter(const MachineModel& model, std::string_view name) const;

  // Adds a validated term. Fails if its coefficient names collide with existing ones, or if it
  // is a kConstant term writing the same slots under the same condition as an existing one
  // (e.g. "E_Y0C" and its alias "E_Y(0A)C").
  Status AddTerm(const MachineModel& model, ErrorTerm term);

  const std::vector<ErrorTerm>& terms() const { return terms_; }

  // Flat view of all coefficients, in term order.
  int num_coefficients() const { return static_cast<int>(coefficient_info_.size()); }
  const CoefficientInfo& coefficient_info(int i) const { return coefficient_info_[i]; }
  double coefficient(int i) const;
  void set_coefficient(int i, double value_internal);  // O(terms), no allocation of names
  std::optional<int> FindCoefficient(std::string_view name) const;

  // Sum of the always-on kConstant terms per link: errors()[link][component] (mm, rad).
  const std::vector<LinkErrors>& static_errors() const { return static_errors_; }
  // Indices of the terms not folded into static_errors() (position-, time-, op-dependent or
  // conditional); evaluated per call.
  const std::vector<int>& dynamic_terms() const { return dynamic_terms_; }
  // True if no term is present.
  bool empty() const { return terms_.empty(); }

 private:
  void Rebuild();        // coefficient index, then RebuildStatic()
  void RebuildStatic();  // static_errors_ and dynamic_terms_

  MachineType type_;
  int num_links_ = 0;
  std::vector<int> link_of_axis_;
  std::vector<ErrorTerm> terms_;
  std::vector<CoefficientInfo> coefficient_info_;
  std::vector<LinkErrors> static_errors_;
  std::vector<int> dynamic_terms_;
};

// A subset of an ErrorState's coefficients freed for identification / differentiation.
struct ActiveSet {
  std::vector<int> coefficients;  // indices into ErrorState coefficients, no repeats
  int size() const { return static_cast<int>(coefficients.size()); }
};
// By names (FindCoefficient); kInvalidArgument naming the first unknown or repeated name.
Result<ActiveSet> SelectCoefficients(const ErrorState& errors, const std::vector<std::string>& names);
// All coefficients.
ActiveSet AllCoefficients(const ErrorState& errors);
// Like SelectCoefficients, but first adds a zero-valued constant term for each name that is a
// catalog parameter (LookupParameter) not yet present in `errors`: e.g. freeing Seed002Set() or
// IsoLocationSet() of a machine starting from zero errors; and for names of polynomial error
// motions of a linear axis, "E_ZX.c2" (ISO 230-1 symbol, power of the axis position in mm), one
// zero-valued polynomial term per symbol with the powers named (when the state has no term of
// that symbol). Errors: unknown names, axes the machine lacks (kInvalidArgument).
Result<ActiveSet> ActivateParameters(const MachineModel& model, ErrorState* errors,
                                     const std::vector<std::string>& names);

// Basis value of each coefficient of term `term` at `axes`, including the condition
// (0 when it does not hold). `weights` is resized to the term's coefficient count.
void EvaluateTermBasis(const ErrorTerm& term, const AxisState& axes, std::vector<double>* weights);

// Value of a term at `axes` (sum of coefficient * basis; 0 when its condition does not hold).
double TermValue(const ErrorTerm& term, const AxisState& axes);

// Error components of every link at `axes`: static_errors() plus the dynamic terms (mm, rad).
void EvaluateLinkErrors(const ErrorState& errors, const AxisState& axes,
                        std::vector<LinkErrors>* link_errors);

}  // namespace tpcal::kinematics
