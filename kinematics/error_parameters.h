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
// ISO 230-1 location errors that a machining or probing test can in principle see: for each
// rotary axis the two line positions, the two line orientations and (for the last rotary axis of
// a two-axis table: none, for a carried axis: its zero, except where redundant), plus the three
// squareness errors E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z. bc_table: the 11 errors of seed 001.
std::vector<std::string> IsoLocationSet(const MachineModel& model);
// Seed 002 Table 2 (ac_table only; empty otherwise): dx_CR(0), dy_CR(0), alpha_CR(0),
// beta_CR(0), dy_AR(-90), dz_AR(-90), dy_CA(-90), alpha_CR(-90), gamma_CR(-90), beta_ZX, alpha_ZY.
std::vector<std::string> Seed002Set(const MachineModel& model);

}  // namespace tpcal::kinematics
