// The catalog of named constant error parameters of a machine: ISO 230-1 location errors of
// the rotary axes, squareness of the linear axes, and (A/C table) the seed 002 Table 2 set whose
// values may differ at A = 0 and A = -90 deg. Each parameter is a scalar that adds
// gain * value to one or more error components (conventions.h), optionally only when an axis is
// at an indexed position. Error motions and drifts are terms of kinematics/error_state.h.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/conventions.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

enum class Quantity { kLength, kAngle };  // mm / rad inside; um / urad outside

// Where a scalar goes: component `component` of the link of `axis`, times `gain`.
struct SlotEffect {
  Axis axis = Axis::kX;
  Component component = Component::kTx;
  double gain = 1.0;
};

// A term applies only when every set field holds.
struct Condition {
  std::optional<Axis> axis;  // ... when this axis is at `at` (mm or rad) within `tol`
  double at = 0.0;
  double tol = kDefaultConditionTol_rad;
  std::optional<int> op;     // ... in this machining operation

  bool always() const { return !axis && !op; }
  bool Holds(const AxisState& s) const;
  // "" (always), "@A=-90", "@A=0,op=3" (degrees for rotary axes, mm for linear ones).
  std::string Label() const;
};

struct ParameterInfo {
  std::string name;         // catalog name, also the YAML key stem: "E_X0C", "dx_CR(0)"
  std::string iso_symbol;   // ISO 230-1 symbol or relation: "E_X0C", "E_B(0X)Z", "~E_X0C at A=0"
  Quantity quantity = Quantity::kLength;
  std::vector<SlotEffect> effects;
  Condition condition;
  std::string description;  // what it is and its sign, one line
  std::vector<std::string> aliases;  // other accepted names for the same parameter ("E_Y(0A)C")
};

// Every named parameter of `model`, in a stable order: rotary-axis location errors
// (E_<D>0<K> for D in X,Y,Z,A,B,C; the own-axis ones are redundant with part setup or the zero
// position, listed for completeness), linear-axis squareness, and for ac_table the seed 002 set.
std::vector<ParameterInfo> ParameterCatalog(const MachineModel& model);

// Parameter by name or alias (exact match). kInvalidArgument listing the close names otherwise.
Result<ParameterInfo> LookupParameter(const MachineModel& model, std::string_view name);

// Standard sets (names in the catalog):
// ISO 230-1 location errors usually identified for the machine type, plus the three squareness
// errors E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z:
//   ac_table: E_Y0A E_Z0A E_B0A E_C0A E_A0A, E_X0C E_Y0C E_B0C E_C0C (E_A0C is left out: with the
//             C pivot on the A axis it is the same as E_A0A);
//   bc_table: E_X0B E_Z0B E_A0B E_C0B, E_X0C E_Y0C E_A0C E_B0C (with the squareness: the 11
//             position-independent errors of seed 001);
//   bhead_ctable: E_X0B E_Z0B E_A0B E_C0B E_B0B, E_X0C E_Y0C E_A0C E_B0C;  xyz: squareness only.
// Whether a given test piece can separate them is for identification to report.
std::vector<std::string> IsoLocationSet(const MachineModel& model);
// The three squareness errors of the linear axes: E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z.
std::vector<std::string> LinearSquarenessSet();
// Seed 002 Table 2 (ac_table only; empty otherwise): dx_CR(0), dy_CR(0), alpha_CR(0),
// beta_CR(0), dy_AR(-90), dz_AR(-90), dy_CA(-90), alpha_CR(-90), gamma_CR(-90), beta_ZX, alpha_ZY.
std::vector<std::string> Seed002Set(const MachineModel& model);

}  // namespace tpcal::kinematics
