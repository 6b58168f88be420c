// Machine axis positions (commands) at one instant, and axis-space increments.
// Linear axes in mm, rotary axes in rad (ISO 841 signs, see kinematics/conventions.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace tpcal::kinematics {

// The six machine axes. Rotary A, B, C turn about X, Y, Z.
enum class Axis : int { kX = 0, kY = 1, kZ = 2, kA = 3, kB = 4, kC = 5 };
inline constexpr int kNumAxes = 6;

constexpr bool IsRotary(Axis a) { return static_cast<int>(a) >= 3; }
constexpr int AxisIndex(Axis a) { return static_cast<int>(a); }
constexpr Axis AxisFromIndex(int i) { return static_cast<Axis>(i); }
// 'X', 'Y', 'Z', 'A', 'B', 'C'.
char AxisLetter(Axis a);
// Axis from "X".."C" (exactly one upper-case letter); nullopt otherwise.
std::optional<Axis> AxisFromName(std::string_view name);

// Commanded axis positions when a point is cut or probed, plus the machining clock.
struct AxisState {
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0;  // linear axes: tool reference point in the MCS
  double a_rad = 0.0, b_rad = 0.0, c_rad = 0.0;  // rotary axis commands (ISO 841)
  double t_s = 0.0;  // machining time since the start of the program, s (thermal drift terms)
  int op = 0;        // machining operation index (1 = first); 0 = none (operation offsets)
};

// Increment of the axis positions per unit of a sweep parameter (mm or rad per unit).
struct AxisDelta {
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0;
  double a_rad = 0.0, b_rad = 0.0, c_rad = 0.0;
};

// Position of one axis (mm or rad).
inline double Position(const AxisState& s, Axis a) {
  switch (a) {
    case Axis::kX: return s.x_mm;
    case Axis::kY: return s.y_mm;
    case Axis::kZ: return s.z_mm;
    case Axis::kA: return s.a_rad;
    case Axis::kB: return s.b_rad;
    case Axis::kC: return s.c_rad;
  }
  return 0.0;
}
inline void SetPosition(AxisState* s, Axis a, double v) {
  switch (a) {
    case Axis::kX: s->x_mm = v; return;
    case Axis::kY: s->y_mm = v; return;
    case Axis::kZ: s->z_mm = v; return;
    case Axis::kA: s->a_rad = v; return;
    case Axis::kB: s->b_rad = v; return;
    case Axis::kC: s->c_rad = v; return;
  }
}
inline double Increment(const AxisDelta& d, Axis a) {
  switch (a) {
    case Axis::kX: return d.x_mm;
    case Axis::kY: return d.y_mm;
    case Axis::kZ: return d.z_mm;
    case Axis::kA: return d.a_rad;
    case Axis::kB: return d.b_rad;
    case Axis::kC: return d.c_rad;
  }
  return 0.0;
}
// s + k * d (time and operation unchanged).
AxisState Advance(const AxisState& s, const AxisDelta& d, double k);

// "X=140.000mm Y=0.000mm Z=-5.000mm A=0.000deg B=0.000deg C=22.500deg t=0.0s op=2".
std::string ToString(const AxisState& s);

}  // namespace tpcal::kinematics
