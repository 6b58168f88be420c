// Conventions of tpcal::kinematics, written once. Tests: kinematics/sign_convention_test.cc,
// kinematics/chain_reference_test.cc (an independent 4x4 composition of the formulas below).
//
// FRAMES
// - MCS (machine coordinate system, ISO 230-1 Annex A, ISO 841): X, Y, Z right-handed, fixed to
//   the bed. Table machines: origin at the intersection of the nominal rotary axes (seed 002:
//   A and C). Linear axis commands X, Y, Z place the tool reference point in the MCS when all
//   rotary axes are at zero and the machine is nominal.
// - part frame: attached to the last element of the workpiece branch (the rotary table, or the
//   bed), coinciding with the MCS at home (all axes zero) on the nominal machine.
// - tool frame: attached to the last element of the tool branch; origin at the tool reference
//   point (tool tip centre), +z along the spindle axis away from the workpiece; coincides with the
//   MCS at home on the nominal machine (vertical spindle: the tool points along -Z).
// - p_in_part = part_from_tool * p_in_tool;  part_from_tool = part_from_machine * machine_from_tool.
//
// ROTARY COMMANDS (ISO 841): a positive A/B/C command turns the TOOL relative to the workpiece
// positively (right-hand rule about +X/+Y/+Z). A rotary TABLE therefore turns the workpiece by the
// negative angle (motion sign s = -1 on the workpiece branch, s = +1 on the tool branch).
// Nominal A/C table with pivots at the MCS origin: part_from_machine = RotZ(C) * RotX(A); the tool
// at machine (140, 0, z) cuts part azimuth +C; at A = -90 deg part +Z points along machine -Y.
// Linear axes on the workpiece branch (a moving table) likewise move the table by -q, so a
// positive X command always moves the tool in +X relative to the workpiece.
//
// AXIS CHAIN. Each branch is a list of axis links from the bed outwards. A link has a nominal
// pivot p (mm, in its parent frame at home: a point of the nominal rotary axis line, or for a
// linear axis the reference point of its angular error motions), a unit direction a (X/A: x,
// Y/B: y, Z/C: z), a motion sign s and twelve error components e (struct Component below).
//   rotary: parent_from_child = T(p) * T(e_t) * R(e_r) * G * T(-p),
//           G = T(l_t) * R(l_r) * Rot_a(s q) * R(l_r)^-1 * T(-l_t)
//   linear: parent_from_child = T(p) * T(s q R(l_r) a) * T(e_t) * R(e_r) * T(-p)
// with T(v) a translation, R(r) = RotX(r_x) * RotY(r_y) * RotZ(r_z) (the D4 D5 D6 order of
// seed 000 eq. 2-3 and seed 003 eq. 5), e_t = (Tx, Ty, Tz), e_r = (Rx, Ry, Rz), l_t = (LineTx,
// LineTy, LineTz), l_r = (LineRx, LineRy, LineRz). Every term is an exact rigid transform; nothing
// is linearised. machine_from_part and machine_from_tool are the products of their branch's links.
//
// ERROR SIGNS (ISO 230-1): an error value is the actual minus nominal position/orientation of the
// MOVING element, expressed in its parent (reference) frame, angles by the right-hand rule.
// - Tx..Rz, "pose" components: rigid displacement of the moving element (location errors E_X0C,
//   E_B0A, ...; error motions E_XC(c), E_BC(c), E_XX(x), E_YX(x), ...). Rotations act about the
//   pivot for rotary axes and about the moving reference point p + s q a for linear axes. For a
//   rotary axis this is the ISO 230-1 HTM form D(delta) D(eps) D(q): the element AND its axis line
//   move, and axes carried by it (C on A) move with it, so a child's location errors are relative
//   to the parent's actual axis (ISO 230-1 "E_Y(0A)C").
// - LineTx..LineRz on a rotary axis, "line" components: the axis average line is displaced /
//   tilted about the pivot while the element is undisplaced at q = 0 (rotation about the displaced
//   line). Used by the seed 002 Table 2 parameters, which describe the line about which the part
//   turned in each A position (see kinematics/SEED002_SIGNS.md).
// - LineRx..LineRz on a linear axis: tilt of its direction of travel (squareness, ISO 230-1
//   E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z); zero offset at q = 0. LineTx..LineTz are invalid on linear axes.
// Examples (tested): E_X0C = +10 um moves the C axis average line and the table +10 um in +X, so
//   the tool at machine (x, y, z), A = C = 0, is at part (x - 0.010, y, z);
//   E_B0C = +20 urad tilts the C axis direction from +Z toward +X (R(r) z = (sin ry, 0, cos ry));
//   E_C(0X)Y = +e: a +Y move of y also moves the tool by -e y in X;
//   E_B(0X)Z = +e: a +Z move of z also moves the tool by +e z in X;
//   E_A(0Y)Z = +e: a +Z move of z also moves the tool by -e z in Y;
//   E_CC(c) = +e on a C TABLE turns the table +e about +Z, i.e. the part lags the command: the
//   tool at machine azimuth 0 cuts part azimuth C - e;
//   E_XX(x) = +e on a tool-side X: the tool reaches x + e.
//
// UNITS: inside mm and rad; YAML keys and reports carry um / urad (core/units.h).
#pragma once

#include <array>

namespace tpcal::kinematics {

// The twelve error components of one axis link (see the chain formula above).
enum class Component : int {
  kTx = 0, kTy, kTz,            // displacement of the moving element, mm, parent frame
  kRx, kRy, kRz,                // rotation of the moving element, rad, about parent X, Y, Z
  kLineTx, kLineTy, kLineTz,    // rotary only: displacement of the axis line, mm
  kLineRx, kLineRy, kLineRz,    // rotary: tilt of the axis line; linear: tilt of the travel direction
};
inline constexpr int kNumComponents = 12;

constexpr int ComponentIndex(Component c) { return static_cast<int>(c); }
constexpr bool IsAngular(Component c) {
  const int i = static_cast<int>(c);
  return (i >= 3 && i <= 5) || i >= 9;
}
// "Tx", "Ry", "LineTy", ...
const char* ComponentName(Component c);

// Error values of one link, indexed by Component (mm or rad).
using LinkErrors = std::array<double, kNumComponents>;

// Tolerance of an indexed-position condition (seed 002: A = 0 and A = -90 deg), rad.
inline constexpr double kDefaultConditionTol_rad = 1e-6;

}  // namespace tpcal::kinematics
