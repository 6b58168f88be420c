#include "kinematics/errors_yaml.h"

#include <cstdio>
#include <cstdlib>
#include <set>

#include "core/units.h"
#include "kinematics/internal/yaml_util.h"

namespace tpcal::kinematics {

namespace y = yaml_internal;

namespace {

constexpr const char* kErrorsSchema = "tpcal.errors/1";

// Internal units per unit named in a key suffix, for a quantity; nullopt if not allowed.
std::optional<double> UnitScale(const std::string& unit, Quantity q) {
  if (q == Quantity::kLength) {
    if (unit == "um") return 1e-3;
    if (unit == "mm") return 1.0;
  } else {
    if (unit == "urad") return 1e-6;
    if (unit == "mrad") return 1e-3;
    if (unit == "deg") return kPi / 180.0;
  }
  return std::nullopt;
}
const char* Unit(Quantity q) { return q == Quantity::kLength ? "um" : "urad"; }
double DisplayScale(Quantity q) { return q == Quantity::kLength ? 1e3 : 1e6; }

// Shortest of %.15g / %.17g that reads back to the same double.
std::string Fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// "E_<D><K>" -> (direction, axis).
struct Symbol {
  Axis direction;
  Axis axis;
};
std::optional<Symbol> ParseSymbol(const std::string& s) {
  if (s.size() != 4 || s[0] != 'E' || s[1] != '_') return std::nullopt;
  const auto d = AxisFromName(s.substr(2, 1)), k = AxisFromName(s.substr(3, 1));
  if (!d || !k) return std::nullopt;
  return Symbol{*d, *k};
}

class Reader {
 public:
  Reader(const std::string& src, const MachineModel& model, ErrorState* errors)
      : src_(src), model_(model), errors_(errors) {}

  Status Root(const YAML::Node& root) {
    Result<std::vector<y::MapEntry>> entries = y::Entries(src_, root, "errors file");
    TPCAL_RETURN_IF_ERROR(entries);
    for (const y::MapEntry& e : *entries) {
      if (e.key == "schema") {
        Result<std::string> s = y::String(src_, e.value, "schema");
        TPCAL_RETURN_IF_ERROR(s);
        if (*s != kErrorsSchema) return y::Error(src_, e.value, "schema: expected " + std::string(kErrorsSchema));
      } else if (e.key == "machine") {
        Result<std::string> s = y::String(src_, e.value, "machine");
        TPCAL_RETURN_IF_ERROR(s);
        if (*s != MachineTypeName(model_.type)) {
          return y::Error(src_, e.value, "machine: file is for '" + EchoInput(*s) + "' but the model is " +
                                             MachineTypeName(model_.type));
        }
      } else if (e.key == "effects") {
        if (!e.value.IsSequence()) return y::Error(src_, e.value, "effects: expected a list");
        for (std::size_t i = 0; i < e.value.size(); ++i) TPCAL_RETURN_IF_ERROR(Effect(e.value[i]));
      } else {
        TPCAL_RETURN_IF_ERROR(Constant(e));
      }
    }
    return Status::Ok();
  }

 private:
  Status At(const y::MapEntry& e, const Status& s) {
    if (s.ok()) return s;
    return Status(StatusCode::kParseError, s.message(), src_, y::Line(e.key_node));
  }

  // name_unit: value
  Status Constant(const y::MapEntry& e) {
    const std::size_t us = e.key.rfind('_');
    const std::string name = us == std::string::npos ? e.key : e.key.substr(0, us);
    const std::string unit = us == std::string::npos ? "" : e.key.substr(us + 1);
    Result<ParameterInfo> p = LookupParameter(model_, name);
    if (!p.ok()) {
      return y::Error(src_, e.key_node,
                      "unknown key '" + EchoInput(e.key) + "': not schema, machine, effects or <parameter>_<unit>; " +
                          p.status().message());
    }
    const std::optional<double> scale = UnitScale(unit, p->quantity);
    if (!scale) {
      return y::Error(src_, e.key_node,
                      "key '" + EchoInput(e.key) + "': " + p->name + " is " +
                          (p->quantity == Quantity::kLength ? "a length: end the key with _um or _mm"
                                                            : "an angle: end the key with _urad, _mrad or _deg"));
    }
    Result<double> v = y::Double(src_, e.value, e.key);
    TPCAL_RETURN_IF_ERROR(v);
    if (!seen_.insert(p->name).second) {
      return y::Error(src_, e.key_node, "parameter " + p->name + " is given twice (an alias?)");
    }
    return At(e, errors_->SetParameter(model_, name, *v * *scale));
  }

  Result<Condition> ParseCondition(const YAML::Node& n) {
    Result<std::vector<y::MapEntry>> entries = y::Entries(src_, n, "at");
    TPCAL_RETURN_IF_ERROR(entries);
    Condition c;
    for (const y::MapEntry& e : *entries) {
      if (e.key == "op") {
        Result<int> op = y::Int(src_, e.value, "at.op");
        TPCAL_RETURN_IF_ERROR(op);
        c.op = *op;
        continue;
      }
      const std::size_t us = e.key.find('_');
      const std::string head = us == std::string::npos ? e.key : e.key.substr(0, us);
      const std::string unit = us == std::string::npos ? "" : e.key.substr(us + 1);
      Result<double> v = y::Double(src_, e.value, "at." + e.key);
      TPCAL_RETURN_IF_ERROR(v);
      if (head == "tol") {
        if (unit == "deg") c.tol = *v * kPi / 180.0;
        else if (unit == "mm") c.tol = *v;
        else return y::Error(src_, e.key_node, "at: tolerance key is tol_deg or tol_mm");
        continue;
      }
      const std::optional<Axis> a = AxisFromName(head);
      if (!a || !model_.HasAxis(*a) || c.axis || unit != (IsRotary(*a) ? "deg" : "mm")) {
        return y::Error(src_, e.key_node,
                        "unknown key '" + EchoInput(e.key) + "' in at (one axis position such as A_deg or X_mm, "
                        "optional tol_deg / tol_mm and op)");
      }
      c.axis = *a;
      c.at = IsRotary(*a) ? *v * kPi / 180.0 : *v;
    }
    return c;
  }

  Status Effect(const YAML::Node& item) {
    Result<std::vector<y::MapEntry>> entries = y::Entries(src_, item, "effect");
    TPCAL_RETURN_IF_ERROR(entries);
    if (entries->size() != 1) {
      return y::Error(src_, item, "effect: expected one key (linear_error_motion, rotary_error_motion, "
                                  "thermal_drift or operation_offset)");
    }
    const y::MapEntry& e = entries->front();
    if (e.key == "linear_error_motion") return ErrorMotion(e, false);
    if (e.key == "rotary_error_motion") return ErrorMotion(e, true);
    if (e.key == "thermal_drift") return Drift(e);
    if (e.key == "operation_offset") return OperationOffset(e);
    return y::Error(src_, e.key_node, "unknown effect '" + e.key +
                                          "' (linear_error_motion, rotary_error_motion, thermal_drift, operation_offset)");
  }

  Status ErrorMotion(const y::MapEntry& effect, bool rotary) {
    const std::string what = effect.key;
    Result<std::vector<y::MapEntry>> f = y::Entries(src_, effect.value, what);
    TPCAL_RETURN_IF_ERROR(f);
    const y::MapEntry* sym_e = y::Find(*f, "symbol");
    if (!sym_e) return y::Error(src_, effect.value, what + ": missing 'symbol' (ISO 230-1, e.g. E_YX, E_XC)");
    Result<std::string> sym_s = y::String(src_, sym_e->value, what + ".symbol");
    TPCAL_RETURN_IF_ERROR(sym_s);
    const std::optional<Symbol> sym = ParseSymbol(*sym_s);
    if (!sym || IsRotary(sym->axis) != rotary || !model_.HasAxis(sym->axis)) {
      return y::Error(src_, sym_e->value,
                      what + ": symbol '" + EchoInput(*sym_s) + "' is not E_<direction><" +
                          (rotary ? "rotary" : "linear") + " axis of this machine> (e.g. " +
                          (rotary ? "E_XC, E_CC" : "E_YX, E_XX") + ")");
    }
    ErrorTerm t;
    t.quantity = IsRotary(sym->direction) ? Quantity::kAngle : Quantity::kLength;
    t.effects = {SlotEffect{sym->axis, static_cast<Component>(AxisIndex(sym->direction)), 1.0}};
    t.argument = sym->axis;
    const std::string u = Unit(t.quantity);
    const double to_internal = 1.0 / DisplayScale(t.quantity);
    if (const y::MapEntry* a = y::Find(*f, "at")) {
      Result<Condition> c = ParseCondition(a->value);
      TPCAL_RETURN_IF_ERROR(c);
      t.condition = *c;
    }
    t.label = *sym_s + t.condition.Label();
    const std::string poly_key = "coefficients_" + u + "_per_mm_pow";
    const std::string pos_key = rotary ? "positions_deg" : "positions_mm";
    const std::string values_key = "values_" + u;
    std::set<std::string> allowed = {"symbol", "at"};
    if (y::Find(*f, "harmonics")) {
      if (!rotary) return y::Error(src_, effect.value, what + ": harmonics are for rotary axes");
      allowed.insert("harmonics");
      TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *f, allowed, what));
      const YAML::Node& h = y::Find(*f, "harmonics")->value;
      if (!h.IsSequence() || h.size() == 0) return y::Error(src_, h, what + ".harmonics: expected a list");
      t.kind = TermKind::kFourier;
      std::set<int> orders;
      for (std::size_t i = 0; i < h.size(); ++i) {
        Result<std::vector<y::MapEntry>> he = y::Entries(src_, h[i], "harmonic");
        TPCAL_RETURN_IF_ERROR(he);
        TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *he, {"order", "cos_" + u, "sin_" + u}, "harmonic"));
        const y::MapEntry* o = y::Find(*he, "order");
        if (!o) return y::Error(src_, h[i], "harmonic: missing 'order'");
        Result<int> order = y::Int(src_, o->value, "order");
        TPCAL_RETURN_IF_ERROR(order);
        if (*order < 0 || !orders.insert(*order).second) {
          return y::Error(src_, o->value, "harmonic: order must be >= 0 and not repeated");
        }
        for (const char* part : {"cos_", "sin_"}) {
          const y::MapEntry* c = y::Find(*he, part + u);
          if (!c) continue;
          if (*order == 0 && std::string(part) == "sin_") {
            return y::Error(src_, c->key_node, "harmonic order 0 has no sine term");
          }
          Result<double> v = y::Double(src_, c->value, part + u);
          TPCAL_RETURN_IF_ERROR(v);
          t.orders.push_back(*order);
          t.is_sine.push_back(std::string(part) == "sin_");
          t.coefficients.push_back(*v * to_internal);
        }
      }
    } else if (y::Find(*f, poly_key)) {
      if (rotary) return y::Error(src_, effect.value, what + ": use harmonics or a table for a rotary axis");
      allowed.insert(poly_key);
      allowed.insert("powers");
      TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *f, allowed, what));
      Result<std::vector<double>> c = y::Doubles(src_, y::Find(*f, poly_key)->value, poly_key);
      TPCAL_RETURN_IF_ERROR(c);
      t.kind = TermKind::kPolynomial;
      if (const y::MapEntry* p = y::Find(*f, "powers")) {
        if (!p->value.IsSequence()) return y::Error(src_, p->value, "powers: expected a list of integers");
        for (std::size_t i = 0; i < p->value.size(); ++i) {
          Result<int> k = y::Int(src_, p->value[i], "powers");
          TPCAL_RETURN_IF_ERROR(k);
          t.powers.push_back(*k);
        }
        if (t.powers.size() != c->size()) {
          return y::Error(src_, p->value, "powers and " + poly_key + " differ in length");
        }
      } else {
        for (std::size_t k = 0; k < c->size(); ++k) t.powers.push_back(static_cast<int>(k));
      }
      for (double v : *c) t.coefficients.push_back(v * to_internal);
    } else if (y::Find(*f, pos_key)) {
      allowed.insert(pos_key);
      allowed.insert(values_key);
      allowed.insert("interpolation");
      if (rotary) allowed.insert("periodic");
      allowed.insert("second_axis");
      TPCAL_RETURN_IF_ERROR(TableFields(*f, rotary, pos_key, values_key, &allowed, &t));
      TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *f, allowed, what));
    } else {
      return y::Error(src_, effect.value,
                      what + ": give " + (rotary ? "harmonics or " : poly_key + " or ") + pos_key +
                          " with " + values_key);
    }
    return At(effect, errors_->AddTerm(model_, std::move(t)));
  }

  Status TableFields(const std::vector<y::MapEntry>& f, bool rotary, const std::string& pos_key,
                     const std::string& values_key, std::set<std::string>* allowed, ErrorTerm* t) {
    t->kind = TermKind::kTable;
    const double pos_scale = rotary ? kPi / 180.0 : 1.0;
    const double to_internal = 1.0 / DisplayScale(t->quantity);
    Result<std::vector<double>> pos = y::Doubles(src_, y::Find(f, pos_key)->value, pos_key);
    TPCAL_RETURN_IF_ERROR(pos);
    for (double p : *pos) t->nodes.push_back(p * pos_scale);
    const y::MapEntry* ve = y::Find(f, values_key);
    if (!ve) return y::Error(src_, y::Find(f, pos_key)->key_node, "table: missing " + values_key);
    if (const y::MapEntry* ie = y::Find(f, "interpolation")) {
      Result<std::string> s = y::String(src_, ie->value, "interpolation");
      TPCAL_RETURN_IF_ERROR(s);
      if (*s == "linear") t->interpolation = Interpolation::kLinear;
      else if (*s == "cubic") t->interpolation = Interpolation::kCubic;
      else return y::Error(src_, ie->value, "interpolation: linear or cubic");
    }
    t->periodic = rotary && model_.links[model_.LinkIndex(t->argument)].continuous;
    if (const y::MapEntry* pe = y::Find(f, "periodic")) {
      Result<bool> b = y::Bool(src_, pe->value, "periodic");
      TPCAL_RETURN_IF_ERROR(b);
      t->periodic = *b;
    }
    if (const y::MapEntry* se = y::Find(f, "second_axis")) {
      Result<std::string> s = y::String(src_, se->value, "second_axis");
      TPCAL_RETURN_IF_ERROR(s);
      const std::optional<Axis> a = AxisFromName(*s);
      if (!a || !model_.HasAxis(*a)) return y::Error(src_, se->value, "second_axis: not an axis of this machine");
      t->second_argument = *a;
      const std::string key2 = IsRotary(*a) ? "second_positions_deg" : "second_positions_mm";
      allowed->insert(key2);
      const y::MapEntry* pe2 = y::Find(f, key2);
      if (!pe2) return y::Error(src_, se->key_node, "second_axis needs " + key2);
      Result<std::vector<double>> p2 = y::Doubles(src_, pe2->value, key2);
      TPCAL_RETURN_IF_ERROR(p2);
      for (double p : *p2) t->second_nodes.push_back(IsRotary(*a) ? p * kPi / 180.0 : p);
      if (!ve->value.IsSequence() || ve->value.size() != p2->size()) {
        return y::Error(src_, ve->value, values_key + ": one row per " + key2 + " entry");
      }
      for (std::size_t j = 0; j < ve->value.size(); ++j) {
        Result<std::vector<double>> row = y::Doubles(src_, ve->value[j], values_key);
        TPCAL_RETURN_IF_ERROR(row);
        if (row->size() != pos->size()) {
          return y::Error(src_, ve->value[j], values_key + ": each row needs one value per " + pos_key + " entry");
        }
        for (double v : *row) t->coefficients.push_back(v * to_internal);
      }
    } else {
      Result<std::vector<double>> vals = y::Doubles(src_, ve->value, values_key);
      TPCAL_RETURN_IF_ERROR(vals);
      if (vals->size() != pos->size()) {
        return y::Error(src_, ve->value, values_key + ": one value per " + pos_key + " entry");
      }
      for (double v : *vals) t->coefficients.push_back(v * to_internal);
    }
    return Status::Ok();
  }

  Result<ParameterInfo> ParameterField(const std::vector<y::MapEntry>& f, const YAML::Node& where,
                                       const std::string& what) {
    const y::MapEntry* pe = y::Find(f, "parameter");
    if (!pe) return y::Error(src_, where, what + ": missing 'parameter' (a catalog name such as E_X0C)");
    Result<std::string> name = y::String(src_, pe->value, what + ".parameter");
    TPCAL_RETURN_IF_ERROR(name);
    Result<ParameterInfo> p = LookupParameter(model_, *name);
    if (!p.ok()) return y::Error(src_, pe->value, what + ".parameter: " + p.status().message());
    return p;
  }

  ErrorTerm FromParameter(const ParameterInfo& p, TermKind kind) {
    ErrorTerm t;
    t.kind = kind;
    t.label = p.name;
    t.quantity = p.quantity;
    t.effects = p.effects;
    t.condition = p.condition;
    return t;
  }

  Status Drift(const y::MapEntry& effect) {
    Result<std::vector<y::MapEntry>> f = y::Entries(src_, effect.value, "thermal_drift");
    TPCAL_RETURN_IF_ERROR(f);
    Result<ParameterInfo> p = ParameterField(*f, effect.value, "thermal_drift");
    TPCAL_RETURN_IF_ERROR(p);
    const std::string u = Unit(p->quantity);
    const double to_internal = 1.0 / DisplayScale(p->quantity);
    const std::string k_key = "K_" + u, rate_key = "rate_" + u + "_per_h";
    TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *f, {"parameter", k_key, "tau_s", "t0_s", rate_key},
                                       "thermal_drift of " + p->name));
    const y::MapEntry* k = y::Find(*f, k_key);
    const y::MapEntry* rate = y::Find(*f, rate_key);
    if ((k == nullptr) == (rate == nullptr)) {
      return y::Error(src_, effect.value, "thermal_drift: give either " + k_key + " with tau_s, or " + rate_key);
    }
    ErrorTerm t = FromParameter(*p, k ? TermKind::kExponentialDrift : TermKind::kLinearDrift);
    if (const y::MapEntry* t0 = y::Find(*f, "t0_s")) {
      Result<double> v = y::Double(src_, t0->value, "t0_s");
      TPCAL_RETURN_IF_ERROR(v);
      t.t0_s = *v;
    }
    if (k) {
      Result<double> v = y::Double(src_, k->value, k_key);
      TPCAL_RETURN_IF_ERROR(v);
      const y::MapEntry* tau = y::Find(*f, "tau_s");
      if (!tau) return y::Error(src_, effect.value, "thermal_drift: " + k_key + " needs tau_s");
      Result<double> tv = y::Double(src_, tau->value, "tau_s");
      TPCAL_RETURN_IF_ERROR(tv);
      if (!(*tv > 0.0)) return y::Error(src_, tau->value, "tau_s must be > 0");
      t.tau_s = *tv;
      t.coefficients = {*v * to_internal};
    } else {
      if (y::Find(*f, "tau_s")) return y::Error(src_, effect.value, "thermal_drift: tau_s goes with " + k_key);
      Result<double> v = y::Double(src_, rate->value, rate_key);
      TPCAL_RETURN_IF_ERROR(v);
      t.coefficients = {*v * to_internal / 3600.0};
    }
    return At(effect, errors_->AddTerm(model_, std::move(t)));
  }

  Status OperationOffset(const y::MapEntry& effect) {
    Result<std::vector<y::MapEntry>> f = y::Entries(src_, effect.value, "operation_offset");
    TPCAL_RETURN_IF_ERROR(f);
    Result<ParameterInfo> p = ParameterField(*f, effect.value, "operation_offset");
    TPCAL_RETURN_IF_ERROR(p);
    const std::string value_key = std::string("value_") + Unit(p->quantity);
    TPCAL_RETURN_IF_ERROR(y::CheckKeys(src_, *f, {"parameter", "op", value_key}, "operation_offset of " + p->name));
    const y::MapEntry* op = y::Find(*f, "op");
    const y::MapEntry* val = y::Find(*f, value_key);
    if (!op || !val) return y::Error(src_, effect.value, "operation_offset: needs op and " + value_key);
    Result<int> o = y::Int(src_, op->value, "op");
    TPCAL_RETURN_IF_ERROR(o);
    if (*o < 1) return y::Error(src_, op->value, "op: operations count from 1");
    Result<double> v = y::Double(src_, val->value, value_key);
    TPCAL_RETURN_IF_ERROR(v);
    ErrorTerm t = FromParameter(*p, TermKind::kOperationOffset);
    t.op = *o;
    t.coefficients = {*v / DisplayScale(p->quantity)};
    return At(effect, errors_->AddTerm(model_, std::move(t)));
  }

  const std::string& src_;
  const MachineModel& model_;
  ErrorState* errors_;
  std::set<std::string> seen_;
};

std::string ConditionYaml(const Condition& c) {
  std::string s;
  if (c.axis) {
    const bool rot = IsRotary(*c.axis);
    s += std::string(1, AxisLetter(*c.axis)) + (rot ? "_deg: " : "_mm: ") +
         Fmt(rot ? c.at * 180.0 / kPi : c.at);
    if (c.tol != kDefaultConditionTol_rad) {
      s += std::string(rot ? ", tol_deg: " : ", tol_mm: ") + Fmt(rot ? c.tol * 180.0 / kPi : c.tol);
    }
  }
  if (c.op) s += (s.empty() ? "" : ", ") + std::string("op: ") + std::to_string(*c.op);
  return s;
}

std::string List(const std::vector<double>& v, double scale) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Fmt(v[i] * scale);
  return s + "]";
}

}  // namespace

Result<ErrorState> ParseErrorState(const std::string& yaml_text, const std::string& source,
                                   const MachineModel& model) {
  Result<YAML::Node> root = y::Parse(yaml_text, source);
  TPCAL_RETURN_IF_ERROR(root);
  ErrorState errors(model);
  if (root->IsNull()) return errors;  // empty file: no errors
  try {
    Reader r(source, model, &errors);
    TPCAL_RETURN_IF_ERROR(r.Root(*root));
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, std::string("YAML: ") + e.what(), source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  }
  return errors;
}

Result<ErrorState> LoadErrorState(const std::string& path, const MachineModel& model) {
  Result<std::string> text = y::ReadFile(path);
  TPCAL_RETURN_IF_ERROR(text);
  return ParseErrorState(*text, path, model);
}

std::string FormatErrorState(const ErrorState& errors, const MachineModel& model) {
  std::string out = "schema: tpcal.errors/1\n";
  out += std::string("machine: ") + MachineTypeName(model.type) + "\n";
  std::string effects;
  for (const ErrorTerm& t : errors.terms()) {
    const std::string u = Unit(t.quantity);
    const double k = DisplayScale(t.quantity);
    const std::string symbol = t.label.substr(0, t.label.find('@'));
    const std::string at = t.condition.always() || t.kind == TermKind::kExponentialDrift ||
                                   t.kind == TermKind::kLinearDrift ||
                                   t.kind == TermKind::kOperationOffset
                               ? ""
                               : ", at: {" + ConditionYaml(t.condition) + "}";
    switch (t.kind) {
      case TermKind::kConstant:
        out += t.label + "_" + u + ": " + Fmt(t.coefficients[0] * k) + "\n";
        break;
      case TermKind::kPolynomial: {
        std::vector<double> p(t.powers.begin(), t.powers.end());
        effects += "  - linear_error_motion: {symbol: " + symbol + at + ", powers: " + List(p, 1.0) +
                   ", coefficients_" + u + "_per_mm_pow: " + List(t.coefficients, k) + "}\n";
        break;
      }
      case TermKind::kFourier: {
        effects += "  - rotary_error_motion: {symbol: " + symbol + at + ", harmonics: [";
        for (std::size_t i = 0; i < t.orders.size(); ++i) {
          effects += std::string(i ? ", " : "") + "{order: " + std::to_string(t.orders[i]) + ", " +
                     (t.is_sine[i] ? "sin_" : "cos_") + u + ": " + Fmt(t.coefficients[i] * k);
          // A cosine followed by the sine of the same order is one harmonic entry.
          if (!t.is_sine[i] && i + 1 < t.orders.size() && t.is_sine[i + 1] &&
              t.orders[i + 1] == t.orders[i]) {
            ++i;
            effects += ", sin_" + u + ": " + Fmt(t.coefficients[i] * k);
          }
          effects += "}";
        }
        effects += "]}\n";
        break;
      }
      case TermKind::kTable: {
        const bool rot = IsRotary(t.argument);
        effects += std::string("  - ") + (rot ? "rotary_error_motion" : "linear_error_motion") +
                   ": {symbol: " + symbol + at + ", " + (rot ? "positions_deg: " : "positions_mm: ") +
                   List(t.nodes, rot ? 180.0 / kPi : 1.0) + ", interpolation: " +
                   (t.interpolation == Interpolation::kLinear ? "linear" : "cubic");
        if (rot) effects += std::string(", periodic: ") + (t.periodic ? "true" : "false");
        if (t.second_argument) {
          const bool rot2 = IsRotary(*t.second_argument);
          effects += std::string(", second_axis: ") + AxisLetter(*t.second_argument) +
                     (rot2 ? ", second_positions_deg: " : ", second_positions_mm: ") +
                     List(t.second_nodes, rot2 ? 180.0 / kPi : 1.0) + ", values_" + u + ": [";
          const std::size_t n = t.nodes.size();
          for (std::size_t j = 0; j < t.second_nodes.size(); ++j) {
            std::vector<double> row(t.coefficients.begin() + j * n, t.coefficients.begin() + (j + 1) * n);
            effects += (j ? ", " : "") + List(row, k);
          }
          effects += "]}\n";
        } else {
          effects += ", values_" + u + ": " + List(t.coefficients, k) + "}\n";
        }
        break;
      }
      case TermKind::kExponentialDrift:
        effects += "  - thermal_drift: {parameter: " + t.label + ", K_" + u + ": " +
                   Fmt(t.coefficients[0] * k) + ", tau_s: " + Fmt(t.tau_s) + ", t0_s: " + Fmt(t.t0_s) + "}\n";
        break;
      case TermKind::kLinearDrift:
        effects += "  - thermal_drift: {parameter: " + t.label + ", rate_" + u + "_per_h: " +
                   Fmt(t.coefficients[0] * k * 3600.0) + ", t0_s: " + Fmt(t.t0_s) + "}\n";
        break;
      case TermKind::kOperationOffset:
        effects += "  - operation_offset: {parameter: " + t.label + ", op: " + std::to_string(t.op) +
                   ", value_" + u + ": " + Fmt(t.coefficients[0] * k) + "}\n";
        break;
    }
  }
  if (!effects.empty()) out += "effects:\n" + effects;
  return out;
}

Status AtErrorsFile(const Status& status, const std::string& path) {
  if (status.code() != StatusCode::kNotConverged || !status.file().empty() || path.empty()) return status;
  return Status(StatusCode::kNotConverged,
                status.message() + "; expected machine errors small against the piece (a machine tool's: "
                                   "micrometres and microradians)",
                path);
}

}  // namespace tpcal::kinematics
