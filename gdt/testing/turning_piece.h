// Test support (header only, not part of the library): the seed 002 turning test piece built
// exactly in its part frame P with known errors. P is the nominal datum frame: B_R on z = 0,
// S_R centred on the Z axis, holes H1..H16 at 140 mm from 0 deg in 22.5 deg steps, faces at the
// seed's heights z_i - z_R. The datum frame D the measured features define differs from P by a
// rotation phi about Z when the hole pattern is shifted: D_from_P = RotZ(-phi).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <string>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/units.h"
#include "gdt/synthetic.h"

namespace tpcal::gdt::testing {

// "H1" .. "H16" (built by appending: GCC 12 -Wrestrict misfires on "H" + std::to_string(k)).
inline std::string HoleName(int k) {
  std::string name = "H";
  name += std::to_string(k);
  return name;
}

// Known errors of the synthetic piece, in the part frame P (mm, rad).
struct TurningTruth {
  Eigen::Vector2d holes_shift_mm{0.0101, -0.0172};  // pitch circle centre (Table 1 #1)
  int rotated_hole = 5;                              // this hole turned about the pitch centre...
  double rotated_hole_rad = 30e-6;                   // ...by this angle (counter-clockwise)
  double b1_about_x_rad = -8.7e-6;                   // B1 tilt, RotX(a) RotY(b) (Table 1 #2)
  double b1_about_y_rad = 1.7e-6;
  double b3_shift_mm = 0.023;                        // B3 along +Z (Table 1 #3)
  double s3_radius_error_mm = -0.0145;               // (Table 1 #4)
  Eigen::Vector2d s1_shift_mm{0.0141, -0.0226};
  Eigen::Vector2d s4_shift_mm{0.0129, -0.0233};      // #5; #6 = s4 - s1 = (-1.2, -0.7) um
  Eigen::Vector2d s3_shift_mm{0.0050, 0.0030};
  Eigen::Vector2d s6_shift_mm{0.0047, 0.0008};       // #7 = s6 - s3 = (-0.3, -2.2) um
  int h3_points = 8;
  bool with_s6 = true;
  // Radial profiles dr(theta_P) in mm: harmonics 2..7 leave the LS circle of 16 even points unchanged.
  std::function<double(double)> dr_s1 = [](double t) { return 0.0015 * std::cos(3 * t) + 0.0008 * std::sin(2 * t); };
  std::function<double(double)> dr_s2 = [](double t) { return 0.0010 * std::cos(4 * t); };
  std::function<double(double)> dr_s3 = [](double t) { return 0.0020 * std::sin(3 * t); };
  std::function<double(double)> dr_s4 = [](double t) { return 0.0005 * std::cos(2 * t); };
  std::function<double(double)> dr_s5 = [](double t) { return -0.0007 * std::sin(5 * t); };
  std::function<double(double)> dr_s6 = [](double t) { return -0.0010 * std::cos(5 * t); };

  // D_from_P = RotZ(-phi): +X of D points from S_R's centre (the origin) to H1's centre.
  double Phi() const { return std::atan2(holes_shift_mm.y(), 140.0 + holes_shift_mm.x()); }
  Eigen::Vector2d InD(const Eigen::Vector2d& v_in_p) const {
    return Eigen::Rotation2Dd(-Phi()) * v_in_p;
  }
};

// Geometry of testpieces/README.md (seed 002 heights; our radii for S4-S6 and shoulders 5 mm
// below the probing heights), as heights above B_R (z - z_R, z_R = 405.702 mm) and radii, mm.
inline constexpr double kZR = 405.702;
inline constexpr double kZSR = 2.5, kZHoles = 403.202 - kZR;  // probing heights of S_R, holes
inline constexpr double kZ1 = 400.702 - kZR, kZ2 = 390.702 - kZR, kZ3 = 380.702 - kZR, kZ4 = 160.702 - kZR,
                        kZ5 = 150.702 - kZR, kZ6 = 140.702 - kZR;
inline constexpr double kZB1 = 395.702 - kZR, kZB3 = 375.702 - kZR;  // shoulders (B1, B3)
inline constexpr double kRBR = 114.0, kRSR = 119.0, kRB1 = 163.0, kRB3 = 173.0;  // probing radii
inline constexpr double kR[7] = {0, 160.0, 165.0, 170.0, 175.0, 180.0, 185.0};    // S1..S6

// The piece in P; every feature the turning plan names, 16 points per face, 8 per hole.
inline PointSet MakeTurningPiece(const TurningTruth& t) {
  PointSet ps;
  ps.source = "synthetic turning piece";
  AppendPlaneRing(&ps, "B_R", {.center_mm = {0, 0, 0}, .radius_mm = kRBR});
  AppendCircle(&ps, "S_R", {.center_mm = {0, 0, kZSR}, .radius_mm = kRSR, .hole = true});
  for (int k = 1; k <= 16; ++k) {
    const double a = DegToRad(22.5 * (k - 1)) + (k == t.rotated_hole ? t.rotated_hole_rad : 0.0);
    const Eigen::Vector2d c = t.holes_shift_mm + 140.0 * Eigen::Vector2d(std::cos(a), std::sin(a));
    AppendCircle(&ps, HoleName(k),
                 {.center_mm = {c.x(), c.y(), kZHoles}, .radius_mm = 5.35, .n_points = k == 3 ? t.h3_points : 8,
                  .hole = true});
  }
  auto circle = [&](const char* name, const Eigen::Vector2d& shift, double z, double r,
                    const std::function<double(double)>& dr) {
    AppendCircle(&ps, name, {.center_mm = {shift.x(), shift.y(), z}, .radius_mm = r, .dr_mm = dr});
  };
  circle("S1", t.s1_shift_mm, kZ1, kR[1], t.dr_s1);
  circle("S2", Eigen::Vector2d::Zero(), kZ2, kR[2], t.dr_s2);
  circle("S3", t.s3_shift_mm, kZ3, kR[3] + t.s3_radius_error_mm, t.dr_s3);
  circle("S4", t.s4_shift_mm, kZ4, kR[4], t.dr_s4);
  circle("S5", Eigen::Vector2d::Zero(), kZ5, kR[5], t.dr_s5);
  if (t.with_s6) circle("S6", t.s6_shift_mm, kZ6, kR[6], t.dr_s6);
  // B1: a ring on the shoulder face, tilted about its centre.
  PointSet b1;
  AppendPlaneRing(&b1, "B1", {.center_mm = {0, 0, 0}, .radius_mm = kRB1});
  const Rigid3 b1_pose =
      MakeRigid(RotX(t.b1_about_x_rad) * RotY(t.b1_about_y_rad), Eigen::Vector3d(0, 0, kZB1));
  for (std::size_t i = 0; i < b1.size(); ++i) {
    ps.xyz_mm.push_back(b1_pose * b1.xyz_mm[i]);
    ps.normal.push_back(b1_pose.linear() * b1.normal[i]);
    ps.feature.push_back(ps.InternFeature("B1"));
    ps.line.push_back(ps.line.back() + 1);
  }
  AppendPlaneRing(&ps, "B3", {.center_mm = {0, 0, kZB3 + t.b3_shift_mm}, .radius_mm = kRB3});
  return ps;
}

}  // namespace tpcal::gdt::testing
