#include "kinematics/error_parameters.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/units.h"

namespace tpcal::kinematics {

bool Condition::Holds(const AxisState& s) const {
  if (axis && std::abs(Position(s, *axis) - at) > tol) return false;
  if (op && s.op != *op) return false;
  return true;
}

std::string Condition::Label() const {
  std::string out;
  if (axis) {
    char buf[64];
    const double v = IsRotary(*axis) ? RadToDeg(at) : at;
    std::snprintf(buf, sizeof(buf), "%c=%.10g", AxisLetter(*axis), v == 0.0 ? 0.0 : v);
    out += buf;
  }
  if (op) {
    if (!out.empty()) out += ",";
    out += "op=" + std::to_string(*op);
  }
  return out.empty() ? out : "@" + out;
}

namespace {

// Component of a pose error named by an ISO direction letter: X,Y,Z -> Tx..Tz; A,B,C -> Rx..Rz.
Component PoseComponent(Axis d) { return static_cast<Component>(AxisIndex(d)); }

std::string DirWord(Axis d) {
  switch (d) {
    case Axis::kX: return "X";
    case Axis::kY: return "Y";
    case Axis::kZ: return "Z";
    case Axis::kA: return "X";
    case Axis::kB: return "Y";
    case Axis::kC: return "Z";
  }
  return "?";
}

std::string Name(const char* fmt, char a, char b) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), fmt, a, b);
  return buf;
}

void AddRotaryLocationErrors(const MachineModel& model, const AxisLink& link,
                             std::vector<ParameterInfo>* out) {
  const Axis k = link.axis;
  const char kl = AxisLetter(k);
  const std::optional<Axis> parent = model.ParentRotary(k);
  const std::string element = link.branch == Branch::kWorkpiece
                                  ? std::string("table/carrier of ") + kl
                                  : std::string("head of ") + kl;
  for (int d = 0; d < kNumAxes; ++d) {
    const Axis dir = AxisFromIndex(d);
    const char dl = AxisLetter(dir);
    ParameterInfo p;
    p.name = Name("E_%c0%c", dl, kl);
    p.iso_symbol = p.name;
    p.quantity = IsRotary(dir) ? Quantity::kAngle : Quantity::kLength;
    p.effects = {SlotEffect{k, PoseComponent(dir), 1.0}};
    if (parent) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "E_%c(0%c)%c", dl, AxisLetter(*parent), kl);
      p.aliases.push_back(buf);
    }
    const bool own = (d % 3) == (AxisIndex(k) % 3);
    if (!IsRotary(dir)) {
      if (own) {
        p.description = std::string("axial position of the ") + kl +
                        " axis: +value moves the " + element + " along +" + DirWord(dir) +
                        " (redundant with part setup or the next axis)";
      } else {
        p.description = std::string("position of the ") + kl + " axis average line in " +
                        DirWord(dir) + ": +value moves the line and the " + element + " +" +
                        DirWord(dir) + " (mm), measured at the pivot";
      }
    } else if (own) {
      p.description = std::string("zero position error of ") + kl + ": the " + element +
                      " is turned +value about +" + DirWord(dir) +
                      " at every command (a table lags a positive command)";
    } else {
      p.description = std::string("orientation of the ") + kl + " axis average line about " +
                      DirWord(dir) + ": the line and the " + element + " turn +value about +" +
                      DirWord(dir) + " through the pivot";
    }
    out->push_back(std::move(p));
  }
}

void AddSquareness(const MachineModel& model, std::vector<ParameterInfo>* out) {
  struct Sq {
    const char* name;
    Axis axis;
    Component comp;
    const char* alias;
    const char* description;
  };
  const Sq sq[] = {
      {"E_C(0X)Y", Axis::kY, Component::kLineRz, "",
       "squareness of Y to X: the Y direction of travel is turned +value about +Z, so a +Y move "
       "of y also moves the tool -value*y in X"},
      {"E_B(0X)Z", Axis::kZ, Component::kLineRy, "beta_ZX",
       "squareness of Z to X: the Z direction of travel is turned +value about +Y, so a +Z move "
       "of z also moves the tool +value*z in X (seed 002 beta_ZX)"},
      {"E_A(0Y)Z", Axis::kZ, Component::kLineRx, "alpha_ZY",
       "squareness of Z to Y: the Z direction of travel is turned +value about +X, so a +Z move "
       "of z also moves the tool -value*z in Y (seed 002 alpha_ZY)"},
  };
  for (const Sq& s : sq) {
    if (!model.HasAxis(s.axis)) continue;
    ParameterInfo p;
    p.name = s.name;
    p.iso_symbol = s.name;
    p.quantity = Quantity::kAngle;
    p.effects = {SlotEffect{s.axis, s.comp, 1.0}};
    if (s.alias[0]) p.aliases.push_back(s.alias);
    p.description = s.description;
    out->push_back(std::move(p));
  }
}

void AddSeed002(std::vector<ParameterInfo>* out) {
  const double a0 = 0.0, a90 = DegToRad(-90.0);
  auto make = [&](const char* name, const char* iso, Quantity q, std::vector<SlotEffect> effects,
                  double at, const char* description) {
    ParameterInfo p;
    p.name = name;
    p.iso_symbol = iso;
    p.quantity = q;
    p.effects = std::move(effects);
    if (!std::isnan(at)) {  // NaN: at every A
      p.condition.axis = Axis::kA;
      p.condition.at = at;
    }
    p.description = description;
    out->push_back(std::move(p));
  };
  const Quantity L = Quantity::kLength, R = Quantity::kAngle;
  // A turns about X, so the X position of the C line is the same at every A (for location errors;
  // the A axis's axial error motion E_XA is an error motion). Active at A = -90 too: the faces
  // turned there (S2, S3, S5, S6) are centred on the C line, the milled S_R is not, so their
  // X concentricity to S_R carries it (kinematics/SEED002_SIGNS.md).
  make("dx_CR(0)", "delta x_CR(0 deg) = E_X0C (seed 002 eq. 1, printed E_X0A)", L,
       {{Axis::kC, Component::kLineTx, 1.0}}, std::numeric_limits<double>::quiet_NaN(),
       "X position of the C axis average line, at A = 0 and every other A (A turns about X) "
       "(line only: the table is not displaced at C = 0); +value moves the line +X");
  make("dy_CR(0)", "delta y_CR(0 deg) = E_Y0A + E_Y(0A)C (seed 002 eq. 2)", L,
       {{Axis::kC, Component::kLineTy, 1.0}}, a0,
       "Y position of the C axis average line at A = 0; +value moves the line +Y");
  make("alpha_CR(0)", "alpha_CR(0 deg) = E_A0A (seed 002 eq. 3)", R,
       {{Axis::kC, Component::kLineRx, 1.0}}, a0,
       "orientation of the C axis line about X at A = 0 (squareness of C to Y): +value turns "
       "the line direction from +Z toward -Y");
  make("beta_CR(0)", "beta_CR(0 deg) = E_B0A + E_B(0A)C (seed 002 eq. 4)", R,
       {{Axis::kC, Component::kLineRy, 1.0}}, a0,
       "orientation of the C axis line about Y at A = 0 (squareness of C to X): +value turns "
       "the line direction from +Z toward +X");
  make("dy_AR(-90)", "delta y_AR(-90 deg) = E_Y0A (seed 002 eq. 5)", L,
       {{Axis::kA, Component::kLineTy, 1.0}, {Axis::kC, Component::kLineTy, 1.0}}, a90,
       "Y position of the A axis average line, for the A = 0 -> -90 deg rotation: +value moves "
       "the A line +Y; the C line keeps its offset dy_CA(-90) from the A line");
  make("dz_AR(-90)", "delta z_AR(-90 deg) = E_Z0A (seed 002 eq. 6)", L,
       {{Axis::kA, Component::kLineTz, 1.0}}, a90,
       "Z position of the A axis average line, for the A = 0 -> -90 deg rotation: +value moves "
       "the A line +Z");
  make("dy_CA(-90)", "delta y_CA(-90 deg) = E_Y(0A)C (seed 002 eq. 7)", L,
       {{Axis::kC, Component::kLineTy, 1.0}}, a90,
       "intersection error of C to A at A = -90: offset of the C line from the A line along the "
       "table's Y (machine +Z at A = -90)");
  make("alpha_CR(-90)", "alpha_CR(-90 deg) = E_A0A (seed 002 eq. 8)", R,
       {{Axis::kC, Component::kLineRx, 1.0}}, a90,
       "orientation of the C axis line about machine X at A = -90 (parallelism to Y): +value "
       "turns the line direction from -Y toward -Z");
  make("gamma_CR(-90)",
       "gamma_CR(-90 deg) = E_B0A + E_B(0A)C for constant errors (seed 002 eq. 9 prints E_C0A + "
       "E_B(0A)C, the machine-frame tilt; see kinematics/SEED002_SIGNS.md)",
       R, {{Axis::kC, Component::kLineRy, 1.0}}, a90,
       "orientation of the C axis line about machine Z at A = -90 relative to the table (its Y "
       "axis): +value turns the line direction from -Y toward +X");
}

}  // namespace

std::vector<ParameterInfo> ParameterCatalog(const MachineModel& model) {
  std::vector<ParameterInfo> out;
  for (const AxisLink& l : model.links) {
    if (IsRotary(l.axis)) AddRotaryLocationErrors(model, l, &out);
  }
  AddSquareness(model, &out);
  if (model.type == MachineType::kAcTable) AddSeed002(&out);
  return out;
}

Result<ParameterInfo> LookupParameter(const MachineModel& model, std::string_view name) {
  std::vector<ParameterInfo> all = ParameterCatalog(model);
  for (ParameterInfo& p : all) {
    if (p.name == name) return std::move(p);
    for (const std::string& a : p.aliases) {
      if (a == name) return std::move(p);
    }
  }
  std::string known;
  int n = 0;
  for (const ParameterInfo& p : all) {
    if (n++) known += ", ";
    known += p.name;
  }
  return Status(StatusCode::kInvalidArgument,
                "unknown error parameter '" + std::string(name) + "' for machine type " +
                    MachineTypeName(model.type) + " (known: " + known + ")");
}

std::vector<std::string> IsoLocationSet(const MachineModel& model) {
  std::vector<std::string> out;
  switch (model.type) {
    case MachineType::kAcTable:
      out = {"E_Y0A", "E_Z0A", "E_B0A", "E_C0A", "E_A0A", "E_X0C", "E_Y0C", "E_B0C", "E_C0C"};
      break;
    case MachineType::kBcTable:  // seed 001: 11 position-independent errors
      out = {"E_X0B", "E_Z0B", "E_A0B", "E_C0B", "E_X0C", "E_Y0C", "E_A0C", "E_B0C"};
      break;
    case MachineType::kBheadCtable:
      out = {"E_X0B", "E_Z0B", "E_A0B", "E_C0B", "E_B0B", "E_X0C", "E_Y0C", "E_A0C", "E_B0C"};
      break;
    case MachineType::kXyz: break;
  }
  for (std::string& s : LinearSquarenessSet()) out.push_back(std::move(s));
  return out;
}

std::vector<std::string> LinearSquarenessSet() { return {"E_C(0X)Y", "E_B(0X)Z", "E_A(0Y)Z"}; }

std::vector<std::string> Seed002Set(const MachineModel& model) {
  if (model.type != MachineType::kAcTable) return {};
  return {"dx_CR(0)",   "dy_CR(0)",   "alpha_CR(0)",   "beta_CR(0)",    "dy_AR(-90)", "dz_AR(-90)",
          "dy_CA(-90)", "alpha_CR(-90)", "gamma_CR(-90)", "beta_ZX", "alpha_ZY"};
}

}  // namespace tpcal::kinematics
