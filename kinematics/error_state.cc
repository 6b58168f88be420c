#include "kinematics/error_state.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <set>

#include "core/input_echo.h"
#include "core/units.h"
#include "kinematics/errors_yaml.h"

namespace tpcal::kinematics {

namespace {

constexpr double kTwoPi = 2.0 * kPi;

const char* BaseUnit(Quantity q) { return q == Quantity::kLength ? "um" : "urad"; }
double BaseScale(Quantity q) { return q == Quantity::kLength ? kUmPerMm : kUradPerRad; }

std::string TermKindName(TermKind k) {
  switch (k) {
    case TermKind::kConstant: return "constant";
    case TermKind::kPolynomial: return "polynomial";
    case TermKind::kFourier: return "Fourier";
    case TermKind::kTable: return "table";
    case TermKind::kExponentialDrift: return "exponential drift";
    case TermKind::kLinearDrift: return "linear drift";
    case TermKind::kOperationOffset: return "operation offset";
  }
  return "?";
}

Status TermError(const ErrorTerm& t, const std::string& what) {
  return Status(StatusCode::kInvalidArgument,
                "error term '" + t.label + "' (" + TermKindName(t.kind) + "): " + what);
}

bool StrictlyIncreasing(const std::vector<double>& v) {
  for (size_t i = 1; i < v.size(); ++i) {
    if (!(v[i] > v[i - 1])) return false;
  }
  return true;
}

bool AllFinite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// Linear weights over non-periodic increasing nodes, held constant outside. Writes (index,
// weight) pairs; returns the count (1 or 2).
int LinearWeights(const std::vector<double>& x, double q, int idx[2], double w[2]) {
  const int n = static_cast<int>(x.size());
  if (q <= x.front()) { idx[0] = 0; w[0] = 1.0; return 1; }
  if (q >= x.back()) { idx[0] = n - 1; w[0] = 1.0; return 1; }
  const int i = static_cast<int>(std::upper_bound(x.begin(), x.end(), q) - x.begin()) - 1;
  const double t = (q - x[i]) / (x[i + 1] - x[i]);
  idx[0] = i; w[0] = 1.0 - t;
  idx[1] = i + 1; w[1] = t;
  return 2;
}

// Table weights of the own-axis interpolation: calls add(node, weight) for each node with a
// non-zero weight (at most four).
template <typename Add>
void TableWeights1D(const ErrorTerm& t, double q, Add&& add) {
  const std::vector<double>& x = t.nodes;
  const int n = static_cast<int>(x.size());
  // Locate the interval [x_i, x_{i+1}] (periodic: the last interval wraps to x_0 + 2 pi).
  int i = 0;
  double x0 = 0.0, x1 = 0.0;
  if (t.periodic) {
    double qq = std::fmod(q - x.front(), kTwoPi);
    if (qq < 0.0) qq += kTwoPi;
    qq += x.front();
    i = static_cast<int>(std::upper_bound(x.begin(), x.end(), qq) - x.begin()) - 1;
    i = std::clamp(i, 0, n - 1);
    x0 = x[i];
    x1 = i + 1 < n ? x[i + 1] : x.front() + kTwoPi;
    q = qq;
  } else {
    if (q <= x.front()) { add(0, 1.0); return; }
    if (q >= x.back()) { add(n - 1, 1.0); return; }
    i = static_cast<int>(std::upper_bound(x.begin(), x.end(), q) - x.begin()) - 1;
    x0 = x[i];
    x1 = x[i + 1];
  }
  const double h = x1 - x0;
  const double s = (q - x0) / h;
  const int ip1 = (i + 1) % n;
  if (t.interpolation == Interpolation::kLinear || n < 3) {
    add(i, 1.0 - s);
    add(ip1, s);
    return;
  }
  // Cubic Hermite with finite-difference slopes m_j = (y_{j+1} - y_{j-1}) / (x_{j+1} - x_{j-1})
  // (one-sided at the ends of a non-periodic table): linear in the node values.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  add(i, h00);
  add(ip1, h01);
  auto add_slope = [&](int j, double c) {
    int jm, jp;
    double xm, xp;
    if (t.periodic) {
      jm = (j - 1 + n) % n;
      jp = (j + 1) % n;
      xm = j == 0 ? x[n - 1] - kTwoPi : x[j - 1];
      xp = j == n - 1 ? x[0] + kTwoPi : x[j + 1];
    } else {
      jm = std::max(j - 1, 0);
      jp = std::min(j + 1, n - 1);
      xm = x[jm];
      xp = x[jp];
    }
    const double d = xp - xm;
    add(jp, c / d);
    add(jm, -c / d);
  };
  add_slope(i, h10 * h);
  add_slope(ip1, h11 * h);
}

// Calls add(coefficient index, weight) for the table's weights at `axes` (condition not checked).
template <typename Add>
void TableWeights(const ErrorTerm& t, const AxisState& axes, Add&& add) {
  const double q = Position(axes, t.argument);
  if (!t.second_argument) {
    TableWeights1D(t, q, add);
    return;
  }
  int idx[2];
  double w[2];
  const int m = LinearWeights(t.second_nodes, Position(axes, *t.second_argument), idx, w);
  const int nn = static_cast<int>(t.nodes.size());
  for (int j = 0; j < m; ++j) {
    const double wj = w[j];
    const int offset = idx[j] * nn;
    TableWeights1D(t, q, [&](int node, double wi) { add(offset + node, wj * wi); });
  }
}

// cos(k q), sin(k q) for k = 0..kmax by the angle-addition recurrence (kmax < 64).
void Harmonics(double q, int kmax, double* c, double* s) {
  c[0] = 1.0;
  s[0] = 0.0;
  if (kmax < 1) return;
  const double c1 = std::cos(q), s1 = std::sin(q);
  c[1] = c1;
  s[1] = s1;
  for (int k = 2; k <= kmax; ++k) {
    c[k] = c[k - 1] * c1 - s[k - 1] * s1;
    s[k] = s[k - 1] * c1 + c[k - 1] * s1;
  }
}

}  // namespace

int ErrorTerm::ExpectedCoefficients() const {
  switch (kind) {
    case TermKind::kConstant:
    case TermKind::kExponentialDrift:
    case TermKind::kLinearDrift:
    case TermKind::kOperationOffset: return 1;
    case TermKind::kPolynomial: return static_cast<int>(powers.size());
    case TermKind::kFourier: return static_cast<int>(orders.size());
    case TermKind::kTable:
      return static_cast<int>(nodes.size() *
                              (second_argument ? std::max<size_t>(second_nodes.size(), 1) : 1));
  }
  return 0;
}

Status ErrorTerm::Validate(const MachineModel& model) const {
  if (label.empty()) return TermError(*this, "empty label");
  if (effects.empty()) return TermError(*this, "no slot effects");
  for (const SlotEffect& e : effects) {
    if (!model.HasAxis(e.axis)) {
      return TermError(*this, std::string("machine has no axis ") + AxisLetter(e.axis));
    }
    const int c = ComponentIndex(e.component);
    if (c < 0 || c >= kNumComponents) return TermError(*this, "bad component");
    if (!IsRotary(e.axis) && c >= ComponentIndex(Component::kLineTx) &&
        c <= ComponentIndex(Component::kLineTz)) {
      return TermError(*this, std::string("line displacement is undefined on linear axis ") +
                                  AxisLetter(e.axis));
    }
    if (IsAngular(e.component) != (quantity == Quantity::kAngle)) {
      return TermError(*this, std::string("component ") + ComponentName(e.component) +
                                  " does not match the term's quantity");
    }
    if (!std::isfinite(e.gain)) return TermError(*this, "gain is not finite");
  }
  if (condition.axis && !model.HasAxis(*condition.axis)) {
    return TermError(*this, std::string("condition on missing axis ") +
                                AxisLetter(*condition.axis));
  }
  if (condition.axis && !(condition.tol > 0.0)) return TermError(*this, "condition tolerance <= 0");
  if (static_cast<int>(coefficients.size()) != ExpectedCoefficients()) {
    return TermError(*this, "expected " + std::to_string(ExpectedCoefficients()) +
                                " coefficients, got " + std::to_string(coefficients.size()));
  }
  if (!AllFinite(coefficients)) return TermError(*this, "coefficient is not finite");
  switch (kind) {
    case TermKind::kPolynomial:
      if (IsRotary(argument) || !model.HasAxis(argument)) {
        return TermError(*this, "polynomial argument must be a linear axis of the machine");
      }
      for (int p : powers) {
        if (p < 0 || p > 12) return TermError(*this, "polynomial power outside [0, 12]");
      }
      break;
    case TermKind::kFourier:
      if (!IsRotary(argument) || !model.HasAxis(argument)) {
        return TermError(*this, "Fourier argument must be a rotary axis of the machine");
      }
      if (is_sine.size() != orders.size()) return TermError(*this, "orders / is_sine size mismatch");
      for (int k : orders) {
        if (k < 0 || k > 360) return TermError(*this, "harmonic order outside [0, 360]");
      }
      break;
    case TermKind::kTable:
      if (!model.HasAxis(argument)) return TermError(*this, "table argument axis is missing");
      if (nodes.size() < 2) return TermError(*this, "a table needs at least 2 nodes");
      if (!AllFinite(nodes) || !StrictlyIncreasing(nodes)) {
        return TermError(*this, "table positions must be finite and strictly increasing");
      }
      if (periodic) {
        if (!IsRotary(argument)) return TermError(*this, "only a rotary table can be periodic");
        if (nodes.front() < 0.0 || nodes.back() >= kTwoPi) {
          return TermError(*this, "periodic table positions must lie in [0, 360) deg");
        }
      }
      if (second_argument) {
        if (!model.HasAxis(*second_argument) || *second_argument == argument) {
          return TermError(*this, "bad second table axis");
        }
        if (second_nodes.size() < 2 || !AllFinite(second_nodes) ||
            !StrictlyIncreasing(second_nodes)) {
          return TermError(*this, "second-axis positions: at least 2, strictly increasing");
        }
      } else if (!second_nodes.empty()) {
        return TermError(*this, "second-axis positions without a second axis");
      }
      break;
    case TermKind::kExponentialDrift:
      if (!(tau_s > 0.0) || !std::isfinite(tau_s)) return TermError(*this, "tau_s must be > 0");
      if (!std::isfinite(t0_s)) return TermError(*this, "t0_s is not finite");
      break;
    case TermKind::kLinearDrift:
      if (!std::isfinite(t0_s)) return TermError(*this, "t0_s is not finite");
      break;
    case TermKind::kOperationOffset:
      if (op < 1) return TermError(*this, "operation index must be >= 1");
      break;
    case TermKind::kConstant: break;
  }
  return Status::Ok();
}

void EvaluateTermBasis(const ErrorTerm& t, const AxisState& axes, std::vector<double>* weights) {
  const int n = t.ExpectedCoefficients();
  weights->assign(n, 0.0);
  if (!t.condition.Holds(axes)) return;
  switch (t.kind) {
    case TermKind::kConstant: (*weights)[0] = 1.0; return;
    case TermKind::kOperationOffset: (*weights)[0] = axes.op == t.op ? 1.0 : 0.0; return;
    case TermKind::kPolynomial: {
      const double q = Position(axes, t.argument);
      for (int k = 0; k < n; ++k) {
        double v = 1.0;
        for (int p = 0; p < t.powers[k]; ++p) v *= q;
        (*weights)[k] = v;
      }
      return;
    }
    case TermKind::kFourier: {
      const double q = Position(axes, t.argument);
      for (int k = 0; k < n; ++k) {
        const double a = t.orders[k] * q;
        (*weights)[k] = t.is_sine[k] ? std::sin(a) : std::cos(a);
      }
      return;
    }
    case TermKind::kTable:
      TableWeights(t, axes, [&](int k, double w) { (*weights)[k] += w; });
      return;
    case TermKind::kExponentialDrift: {
      const double dt = axes.t_s - t.t0_s;
      (*weights)[0] = dt > 0.0 ? -std::expm1(-dt / t.tau_s) : 0.0;
      return;
    }
    case TermKind::kLinearDrift: {
      const double dt = axes.t_s - t.t0_s;
      (*weights)[0] = dt > 0.0 ? dt : 0.0;
      return;
    }
  }
}

ErrorState::ErrorState(const MachineModel& model)
    : type_(model.type), num_links_(model.num_links()), link_of_axis_(kNumAxes, -1) {
  for (int a = 0; a < kNumAxes; ++a) link_of_axis_[a] = model.LinkIndex(AxisFromIndex(a));
  Rebuild();
}

namespace {

std::vector<CoefficientInfo> CoefficientInfos(const ErrorTerm& t, int term_index) {
  std::vector<CoefficientInfo> out;
  const std::string base = BaseUnit(t.quantity);
  const double scale = BaseScale(t.quantity);
  auto push = [&](std::string name, std::string unit, double f, int k) {
    out.push_back(CoefficientInfo{std::move(name), std::move(unit), f, term_index, k});
  };
  switch (t.kind) {
    case TermKind::kConstant: push(t.label, base, scale, 0); break;
    case TermKind::kPolynomial:
      for (size_t k = 0; k < t.powers.size(); ++k) {
        const int p = t.powers[k];
        push(t.label + ".c" + std::to_string(p),
             p == 0 ? base : base + "_per_mm_pow" + std::to_string(p), scale, static_cast<int>(k));
      }
      break;
    case TermKind::kFourier:
      for (size_t k = 0; k < t.orders.size(); ++k) {
        std::string name = t.label;
        name += t.is_sine[k] ? ".sin" : ".cos";
        name += std::to_string(t.orders[k]);
        push(std::move(name), base, scale, static_cast<int>(k));
      }
      break;
    case TermKind::kTable: {
      const int n = static_cast<int>(t.nodes.size());
      const int m = t.second_argument ? static_cast<int>(t.second_nodes.size()) : 1;
      for (int j = 0; j < m; ++j) {
        for (int i = 0; i < n; ++i) {
          std::string name = t.label + ".n" + std::to_string(i);
          if (t.second_argument) {
            name += '_';
            name += std::to_string(j);
          }
          push(name, base, scale, j * n + i);
        }
      }
      break;
    }
    case TermKind::kExponentialDrift: push(t.label + ".drift_K", base, scale, 0); break;
    case TermKind::kLinearDrift: push(t.label + ".drift_rate", base + "_per_h", scale * 3600.0, 0); break;
    case TermKind::kOperationOffset: push(t.label + ".op" + std::to_string(t.op), base, scale, 0); break;
  }
  return out;
}

bool SameSlots(const ErrorTerm& a, const ErrorTerm& b) {
  if (a.effects.size() != b.effects.size()) return false;
  for (size_t i = 0; i < a.effects.size(); ++i) {
    if (a.effects[i].axis != b.effects[i].axis || a.effects[i].component != b.effects[i].component ||
        a.effects[i].gain != b.effects[i].gain) {
      return false;
    }
  }
  return a.condition.axis == b.condition.axis && a.condition.at == b.condition.at &&
         a.condition.op == b.condition.op;
}

}  // namespace

Status ErrorState::AddTerm(const MachineModel& model, ErrorTerm term) {
  if (model.type != type_ || model.num_links() != num_links_) {
    return Status(StatusCode::kInvalidArgument, "error term added with a different machine model");
  }
  TPCAL_RETURN_IF_ERROR(term.Validate(model));
  for (const ErrorTerm& t : terms_) {
    if (term.kind == TermKind::kConstant && t.kind == TermKind::kConstant && SameSlots(t, term)) {
      return Status(StatusCode::kInvalidArgument,
                    "error parameters '" + t.label + "' and '" + term.label +
                        "' are the same parameter (same slots and condition)");
    }
  }
  const std::vector<CoefficientInfo> infos = CoefficientInfos(term, static_cast<int>(terms_.size()));
  for (const CoefficientInfo& c : infos) {
    if (FindCoefficient(c.name)) {
      return Status(StatusCode::kInvalidArgument, "duplicate error coefficient '" + c.name + "'");
    }
  }
  terms_.push_back(std::move(term));
  Rebuild();
  return Status::Ok();
}

Status ErrorState::SetParameter(const MachineModel& model, std::string_view name, double value) {
  if (!std::isfinite(value)) {
    return Status(StatusCode::kInvalidArgument,
                  "error parameter '" + std::string(name) + "': value is not finite");
  }
  Result<ParameterInfo> p = LookupParameter(model, name);
  TPCAL_RETURN_IF_ERROR(p);
  for (ErrorTerm& t : terms_) {
    if (t.kind == TermKind::kConstant && t.label == p->name) {
      t.coefficients[0] = value;
      Rebuild();
      return Status::Ok();
    }
  }
  ErrorTerm t;
  t.kind = TermKind::kConstant;
  t.label = p->name;
  t.aliases = p->aliases;
  t.quantity = p->quantity;
  t.effects = p->effects;
  t.condition = p->condition;
  t.coefficients = {value};
  return AddTerm(model, std::move(t));
}

Result<double> ErrorState::Parameter(const MachineModel& model, std::string_view name) const {
  Result<ParameterInfo> p = LookupParameter(model, name);
  TPCAL_RETURN_IF_ERROR(p);
  for (const ErrorTerm& t : terms_) {
    if (t.kind == TermKind::kConstant && t.label == p->name) return t.coefficients[0];
  }
  return 0.0;
}

double ErrorState::coefficient(int i) const {
  const CoefficientInfo& c = coefficient_info_[i];
  return terms_[c.term].coefficients[c.index];
}

void ErrorState::set_coefficient(int i, double value_internal) {
  const CoefficientInfo& c = coefficient_info_[i];
  ErrorTerm& t = terms_[c.term];
  t.coefficients[c.index] = value_internal;
  if (t.kind == TermKind::kConstant && t.condition.always()) RebuildStatic();
}

std::optional<int> ErrorState::FindCoefficient(std::string_view name) const {
  for (int i = 0; i < num_coefficients(); ++i) {
    if (coefficient_info_[i].name == name) return i;
  }
  // Catalog aliases of constant parameters: "E_Y(0A)C" finds "E_Y0C", "beta_ZX" finds "E_B(0X)Z".
  for (int i = 0; i < num_coefficients(); ++i) {
    const ErrorTerm& t = terms_[coefficient_info_[i].term];
    if (t.kind != TermKind::kConstant) continue;
    for (const std::string& a : t.aliases) {
      if (a == name) return i;
    }
  }
  return std::nullopt;
}

void ErrorState::Rebuild() {
  coefficient_info_.clear();
  for (int i = 0; i < static_cast<int>(terms_.size()); ++i) {
    for (CoefficientInfo& c : CoefficientInfos(terms_[i], i)) coefficient_info_.push_back(std::move(c));
  }
  RebuildStatic();
}

void ErrorState::RebuildStatic() {
  LinkErrors zero;
  zero.fill(0.0);
  static_errors_.assign(num_links_, zero);
  dynamic_terms_.clear();
  for (int i = 0; i < static_cast<int>(terms_.size()); ++i) {
    const ErrorTerm& t = terms_[i];
    if (t.kind == TermKind::kConstant && t.condition.always()) {
      for (const SlotEffect& e : t.effects) {
        static_errors_[link_of_axis_[AxisIndex(e.axis)]][ComponentIndex(e.component)] +=
            e.gain * t.coefficients[0];
      }
    } else {
      dynamic_terms_.push_back(i);
    }
  }
}

double TermValue(const ErrorTerm& t, const AxisState& axes) {
  if (!t.condition.Holds(axes)) return 0.0;
  const std::vector<double>& c = t.coefficients;
  switch (t.kind) {
    case TermKind::kConstant: return c[0];
    case TermKind::kOperationOffset: return axes.op == t.op ? c[0] : 0.0;
    case TermKind::kPolynomial: {
      const double q = Position(axes, t.argument);
      double v = 0.0;
      for (size_t k = 0; k < c.size(); ++k) {
        double b = 1.0;
        for (int p = 0; p < t.powers[k]; ++p) b *= q;
        v += c[k] * b;
      }
      return v;
    }
    case TermKind::kFourier: {
      const double q = Position(axes, t.argument);
      int kmax = 0;
      for (int k : t.orders) kmax = std::max(kmax, k);
      double v = 0.0;
      if (kmax < 64) {
        double co[64], si[64];
        Harmonics(q, kmax, co, si);
        for (size_t k = 0; k < c.size(); ++k) v += c[k] * (t.is_sine[k] ? si[t.orders[k]] : co[t.orders[k]]);
      } else {
        for (size_t k = 0; k < c.size(); ++k) {
          const double a = t.orders[k] * q;
          v += c[k] * (t.is_sine[k] ? std::sin(a) : std::cos(a));
        }
      }
      return v;
    }
    case TermKind::kTable: {
      double v = 0.0;
      TableWeights(t, axes, [&](int k, double w) { v += c[k] * w; });
      return v;
    }
    case TermKind::kExponentialDrift: {
      const double dt = axes.t_s - t.t0_s;
      return dt > 0.0 ? -c[0] * std::expm1(-dt / t.tau_s) : 0.0;
    }
    case TermKind::kLinearDrift: {
      const double dt = axes.t_s - t.t0_s;
      return dt > 0.0 ? c[0] * dt : 0.0;
    }
  }
  return 0.0;
}

void EvaluateLinkErrors(const ErrorState& errors, const AxisState& axes,
                        std::vector<LinkErrors>* link_errors) {
  *link_errors = errors.static_errors();
  for (int ti : errors.dynamic_terms()) {
    const ErrorTerm& t = errors.terms()[ti];
    const double value = TermValue(t, axes);
    if (value == 0.0) continue;
    for (const SlotEffect& e : t.effects) {
      (*link_errors)[errors.LinkIndex(e.axis)][ComponentIndex(e.component)] += e.gain * value;
    }
  }
}

Result<ActiveSet> SelectCoefficients(const ErrorState& errors, const std::vector<std::string>& names) {
  ActiveSet out;
  std::set<int> seen;
  for (const std::string& n : names) {
    std::optional<int> i = errors.FindCoefficient(n);
    if (!i) {
      return Status(StatusCode::kInvalidArgument,
                    "no error coefficient named '" + n + "' (set the parameter or add the term first)");
    }
    if (!seen.insert(*i).second) {
      return Status(StatusCode::kInvalidArgument, "error coefficient '" + n + "' selected twice");
    }
    out.coefficients.push_back(*i);
  }
  return out;
}

namespace {

constexpr std::size_t kMaxNamesListed = 16;  // of the catalog, in an unknown-parameter message

Status UnknownParameter(const MachineModel& model, const std::string& name) {
  const std::vector<ParameterInfo> catalog = ParameterCatalog(model);
  std::string known;
  for (std::size_t k = 0; k < catalog.size() && k < kMaxNamesListed; ++k) known += (k ? ", " : "") + catalog[k].name;
  if (catalog.size() > kMaxNamesListed) known += ", ...; every one in kinematics/errors_yaml.md";
  return Status(StatusCode::kInvalidArgument,
                "unknown parameter '" + EchoInput(name) + "'; expected one of the " + std::to_string(catalog.size()) +
                    " parameters of the " + MachineTypeName(model.type) + " machine (" + known +
                    "), a polynomial error-motion coefficient such as E_ZX.c2, or a coefficient of the error terms");
}

}  // namespace

Result<ActiveSet> ActivateParameters(const MachineModel& model, ErrorState* errors,
                                     const std::vector<std::string>& names) {
  // Polynomial error motions of linear axes asked for by coefficient name ("E_ZX.c2"): symbol ->
  // powers, for symbols the state has no term of.
  static const std::regex kPolynomial("^(E_[XYZABC][XYZ])\\.c([0-9]{1,2})$");
  std::map<std::string, std::vector<int>> powers;
  for (const std::string& n : names) {
    if (errors->FindCoefficient(n)) continue;
    if (LookupParameter(model, n).ok()) {
      TPCAL_RETURN_IF_ERROR(errors->SetParameter(model, n, 0.0));
      continue;
    }
    std::smatch m;
    if (!std::regex_match(n, m, kPolynomial)) return UnknownParameter(model, n);
    powers[m[1].str()].push_back(std::stoi(m[2].str()));
  }
  for (auto& [symbol, p] : powers) {
    const bool exists = std::any_of(errors->terms().begin(), errors->terms().end(),
                                    [&label = symbol](const ErrorTerm& t) { return t.label == label; });
    if (exists) continue;  // SelectCoefficients names the power that term lacks
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    std::string list, zeros;
    for (std::size_t k = 0; k < p.size(); ++k) {
      list += (k ? ", " : "") + std::to_string(p[k]);
      zeros += k ? ", 0" : "0";
    }
    const bool angular = symbol[2] == 'A' || symbol[2] == 'B' || symbol[2] == 'C';
    const std::string text = "effects:\n  - linear_error_motion: {symbol: " + symbol + ", powers: [" + list +
                             "], coefficients_" + (angular ? "urad" : "um") + "_per_mm_pow: [" + zeros + "]}\n";
    auto parsed = ParseErrorState(text, "<parameters " + symbol + ">", model);
    if (!parsed.ok())  // the generated text is no file: name the parameters instead
      return Status(parsed.status().code(), "parameters of " + symbol + " (powers " + list + "): " + parsed.status().message());
    for (const ErrorTerm& t : parsed->terms()) TPCAL_RETURN_IF_ERROR(errors->AddTerm(model, t));
  }
  return SelectCoefficients(*errors, names);
}

ActiveSet AllCoefficients(const ErrorState& errors) {
  ActiveSet out;
  for (int i = 0; i < errors.num_coefficients(); ++i) out.coefficients.push_back(i);
  return out;
}

}  // namespace tpcal::kinematics
