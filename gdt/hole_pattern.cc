#include "gdt/hole_pattern.h"

#include <cmath>
#include <string>

#include "core/units.h"

namespace tpcal::gdt {

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [-pi, pi]
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

Result<HolePatternResult> EvaluateHolePattern(const fitting::Circle2& pitch, std::span<const Eigen::Vector2d> centers_mm,
                                              std::span<const double> nominal_angles_rad) {
  if (centers_mm.size() != nominal_angles_rad.size())
    return Status(StatusCode::kInvalidArgument, "hole pattern: " + std::to_string(centers_mm.size()) + " centres but " +
                                                    std::to_string(nominal_angles_rad.size()) + " nominal angles");
  HolePatternResult r;
  r.pitch = pitch;
  // Mean of the wrapped errors, as a mean of unit phasors (robust to the wrap at +-pi).
  double s = 0.0, c = 0.0;
  for (std::size_t i = 0; i < centers_mm.size(); ++i) {
    const Eigen::Vector2d d = centers_mm[i] - pitch.center_mm;
    HolePosition h;
    h.angle_rad = WrapAngle(std::atan2(d.y(), d.x()));
    h.angle_error_rad = WrapAngle(h.angle_rad - nominal_angles_rad[i]);
    h.radial_error_mm = d.norm() - pitch.radius_mm;
    s += std::sin(h.angle_error_rad);
    c += std::cos(h.angle_error_rad);
    r.holes.push_back(h);
  }
  r.mean_angle_error_rad = centers_mm.empty() ? 0.0 : std::atan2(s, c);
  return r;
}

}  // namespace tpcal::gdt
