#include "kinematics/axis_state.h"

#include <cstdio>

#include "core/units.h"

namespace tpcal::kinematics {

char AxisLetter(Axis a) { return "XYZABC"[AxisIndex(a)]; }

std::optional<Axis> AxisFromName(std::string_view name) {
  if (name.size() != 1) return std::nullopt;
  switch (name[0]) {
    case 'X': return Axis::kX;
    case 'Y': return Axis::kY;
    case 'Z': return Axis::kZ;
    case 'A': return Axis::kA;
    case 'B': return Axis::kB;
    case 'C': return Axis::kC;
    default: return std::nullopt;
  }
}

AxisState Advance(const AxisState& s, const AxisDelta& d, double k) {
  AxisState out = s;
  out.x_mm += k * d.x_mm;
  out.y_mm += k * d.y_mm;
  out.z_mm += k * d.z_mm;
  out.a_rad += k * d.a_rad;
  out.b_rad += k * d.b_rad;
  out.c_rad += k * d.c_rad;
  return out;
}

std::string ToString(const AxisState& s) {
  char buf[200];
  std::snprintf(buf, sizeof(buf),
                "X=%.4fmm Y=%.4fmm Z=%.4fmm A=%.4fdeg B=%.4fdeg C=%.4fdeg t=%.1fs op=%d", s.x_mm,
                s.y_mm, s.z_mm, RadToDeg(s.a_rad), RadToDeg(s.b_rad), RadToDeg(s.c_rad), s.t_s,
                s.op);
  return buf;
}

}  // namespace tpcal::kinematics
