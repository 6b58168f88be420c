// The virtual touch (kinematics/probe_touch.h) on the A/C table (MakeMachine, pivots at the MCS
// origin) with seed 000's three boxes, every face, at A in {0, -30, -60, -90} deg and C every
// 60 deg; targets at each face centre and at an off-centre point of the face.
//
// Truths and tolerances:
//  - zero errors: the reading is the nominal machine position of the target (the ball centre
//    sits r off the face along the normal, the reading adds r back along the approach), exact up
//    to rounding of ~200 mm coordinates: 1e-9 mm.
//  - a translation of the table (E_X0C): the face moves rigidly, the ball meets it after the
//    normal displacement n_m . (T_err p - T_nom p); exact, so to the Newton stop (1e-9 mm) plus
//    rounding: 2e-9 mm. The reading moves only along the approach.
//  - a 50 urad angular error (E_B0C, E_A0A): the same first-order prediction; the neglected terms
//    are theta^2 (|p| + r) <= (5e-5)^2 * 135 mm = 3.4e-7 mm, so 1e-6 mm.
//  - any part-side location errors: the closed-form intersection of the approach line with the
//    erroneous face plane (from MachineFromPart), to 2e-9 mm.
//  - error motions of the linear axes (not affine in the commands): the contact condition itself,
//    n . ToolPointInPart(reading - r d) = offset + r, to the Newton stop 1e-9 mm plus rounding.
//  - pre-travel: p0 moves the reading by p0 along the approach; p3 by p3 |d_xy| cos(3 phi), zero
//    on a vertical approach; pure arithmetic on the same Newton solution: 1e-12 mm.
// No random numbers are used.
#include "kinematics/probe_touch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::kinematics {
namespace {

constexpr double kTouchExact_mm = 1e-9;        // zero errors: rounding of ~200 mm coordinates
constexpr double kTouchNewton_mm = 2e-9;       // Newton stop 1e-9 mm plus rounding
constexpr double kTouchSecondOrder_mm = 1e-6;  // theta^2 (|p| + r) = 3.4e-7 mm at 50 urad
constexpr double kTouchArithmetic_mm = 1e-12;  // same solution, a shift along a unit vector

MachineModel TouchMachine() {
  Result<MachineModel> m = MakeMachine(MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

AxisState TouchRotary(double a_deg, double c_deg) {
  AxisState s;
  s.a_rad = DegToRad(a_deg);
  s.c_rad = DegToRad(c_deg);
  return s;
}

// A in {0, -30, -60, -90} deg, C = 0, 60, ..., 300 deg (or only A = 0 with `a_zero_only`).
std::vector<AxisState> TouchRotaryGrid(bool a_zero_only = false) {
  std::vector<AxisState> out;
  for (double a : {0.0, -30.0, -60.0, -90.0}) {
    if (a_zero_only && a != 0.0) continue;
    for (double c = 0.0; c < 360.0; c += 60.0) out.push_back(TouchRotary(a, c));
  }
  return out;
}

struct TouchTarget {
  FaceGeometry face;
  Eigen::Vector3d point_mm;  // part frame, on the face's plane
  std::string name;          // "box 1 +X centre"
};

// Every face of Seed000Artifacts(), at its centre and at (+0.5 half_u, -0.5 half_v) from it.
std::vector<TouchTarget> TouchTargets() {
  std::vector<TouchTarget> out;
  for (const ArtifactBox& box : Seed000Artifacts().boxes) {
    for (BoxFace f : kBoxFaces) {
      const FaceGeometry g = FaceOf(box, f);
      const std::string stem = "box " + box.name + " " + BoxFaceName(f);
      out.push_back({g, g.centre_mm, stem + " centre"});
      out.push_back({g, g.centre_mm + 0.5 * g.half_u_mm * g.u - 0.5 * g.half_v_mm * g.v, stem + " off-centre"});
    }
  }
  return out;
}

std::string TouchWhere(const TouchTarget& t, const AxisState& rotary) {
  return t.name + " at A=" + std::to_string(RadToDeg(rotary.a_rad)) + " C=" + std::to_string(RadToDeg(rotary.c_rad));
}

Eigen::Vector3d TouchOrDie(const MachineModel& m, const ErrorState& e, const AxisState& rotary, const TouchTarget& t,
                           const TouchOptions& options = {}) {
  Result<Eigen::Vector3d> c = SimulateTouch(m, e, rotary, t.face, t.point_mm, options);
  EXPECT_TRUE(c.ok()) << TouchWhere(t, rotary) << ": " << c.status().ToString();
  return c.ok() ? *c : Eigen::Vector3d::Constant(std::nan(""));
}

ErrorState TouchErrors(const MachineModel& m, const std::vector<std::pair<const char*, double>>& values) {
  ErrorState e(m);
  for (const auto& [name, value] : values) EXPECT_TRUE(e.SetParameter(m, name, value).ok()) << name;
  return e;
}

// The normal displacement of the face at the target, predicted to first order from the table's
// pose alone: n_m . (machine_from_part_err p - machine_from_part_nom p), n_m the nominal machine
// normal. Returns the largest |deviation| of the simulated readings from it over the grid, and
// the largest |prediction| in *max_predicted_mm (so a vacuous test shows).
double TouchMaxNormalDeviation(const MachineModel& m, const ErrorState& e, const std::vector<AxisState>& grid,
                               double* max_predicted_mm, double* max_tangential_mm) {
  double worst = 0.0;
  *max_predicted_mm = 0.0;
  *max_tangential_mm = 0.0;
  for (const AxisState& rotary : grid) {
    Workspace ws;
    const Rigid3 actual = MachineFromPart(m, e, rotary, &ws);
    const Rigid3 nominal = NominalMachineFromTable(m, rotary);
    for (const TouchTarget& t : TouchTargets()) {
      const Eigen::Vector3d n_m = nominal.linear() * t.face.normal;
      const Eigen::Vector3d nominal_mm = nominal * t.point_mm;
      const double predicted_mm = n_m.dot(actual * t.point_mm - nominal_mm);
      const Eigen::Vector3d moved_mm = TouchOrDie(m, e, rotary, t) - nominal_mm;
      const double deviation_mm = std::abs(n_m.dot(moved_mm) - predicted_mm);
      EXPECT_FALSE(std::isnan(deviation_mm)) << TouchWhere(t, rotary);
      if (!(deviation_mm <= worst)) worst = deviation_mm;  // NaN propagates
      *max_predicted_mm = std::max(*max_predicted_mm, std::abs(predicted_mm));
      *max_tangential_mm = std::max(*max_tangential_mm, (moved_mm - n_m.dot(moved_mm) * n_m).norm());
    }
  }
  return worst;
}

TEST(ProbeTouch, ZeroErrorsReportTheNominalTarget) {
  const MachineModel m = TouchMachine();
  const ErrorState none(m);
  for (const AxisState& rotary : TouchRotaryGrid()) {
    const Rigid3 machine_from_table = NominalMachineFromTable(m, rotary);
    for (const TouchTarget& t : TouchTargets()) {
      const Eigen::Vector3d reading = TouchOrDie(m, none, rotary, t);
      EXPECT_LT((reading - machine_from_table * t.point_mm).norm(), kTouchExact_mm) << TouchWhere(t, rotary);
    }
  }
}

TEST(ProbeTouch, TableTranslationMovesTheReadingByTheFaceDisplacement) {
  const MachineModel m = TouchMachine();
  const ErrorState e = TouchErrors(m, {{"E_X0C", UmToMm(10.0)}});
  double max_predicted_mm = 0.0, max_tangential_mm = 0.0;
  const double worst = TouchMaxNormalDeviation(m, e, TouchRotaryGrid(/*a_zero_only=*/true), &max_predicted_mm,
                                               &max_tangential_mm);
  EXPECT_LT(worst, kTouchNewton_mm);
  EXPECT_NEAR(max_predicted_mm, UmToMm(10.0), kTouchNewton_mm);  // the +-X faces at C = 0 see it all
  EXPECT_LT(max_tangential_mm, kTouchNewton_mm);                 // the reading moves along the approach
}

TEST(ProbeTouch, AngularErrorsMoveTheReadingByTheFaceDisplacementToFirstOrder) {
  const MachineModel m = TouchMachine();
  for (const char* name : {"E_B0C", "E_A0A"}) {
    const ErrorState e = TouchErrors(m, {{name, UradToRad(50.0)}});
    double max_predicted_mm = 0.0, max_tangential_mm = 0.0;
    const double worst = TouchMaxNormalDeviation(m, e, TouchRotaryGrid(), &max_predicted_mm, &max_tangential_mm);
    EXPECT_LT(worst, kTouchSecondOrder_mm) << name;
    // 50 urad on lever arms of ~100 mm: the prediction is micrometres, not vacuous.
    EXPECT_GT(max_predicted_mm, UmToMm(3.0)) << name;
  }
}

TEST(ProbeTouch, PartSideErrorsMatchTheClosedFormPlaneIntersection) {
  const MachineModel m = TouchMachine();
  // All location errors of the A and C axes (both carry the part), seed 001 Table 1(a) sizes.
  const ErrorState e = TouchErrors(m, {{"E_Y0A", UmToMm(-12.0)}, {"E_Z0A", UmToMm(19.0)}, {"E_B0A", UradToRad(-17.0)},
                                       {"E_C0A", UradToRad(75.0)}, {"E_A0A", UradToRad(40.0)}, {"E_X0C", UmToMm(10.0)},
                                       {"E_Y0C", UmToMm(-15.0)}, {"E_B0C", UradToRad(42.0)}, {"E_C0C", UradToRad(-87.0)}});
  const double r_mm = TouchOptions{}.probe_radius_mm;
  for (const AxisState& rotary : TouchRotaryGrid()) {
    Workspace ws;
    const Rigid3 actual = MachineFromPart(m, e, rotary, &ws);  // the tool side is error-free
    for (const TouchTarget& t : TouchTargets()) {
      // The ball centre c0 + s d meets the plane n' . x = n' . p' + r of the moved face.
      const Eigen::Vector3d c0 = NominalMachineFromTable(m, rotary) * (t.point_mm + r_mm * t.face.normal);
      const Eigen::Vector3d d = NominalApproach(m, rotary, t.face);
      const Eigen::Vector3d n_actual = actual.linear() * t.face.normal;
      const double s_mm = (n_actual.dot(actual * t.point_mm) + r_mm - n_actual.dot(c0)) / n_actual.dot(d);
      const Eigen::Vector3d expected = c0 + (s_mm + r_mm) * d;
      EXPECT_LT((TouchOrDie(m, e, rotary, t) - expected).norm(), kTouchNewton_mm) << TouchWhere(t, rotary);
    }
  }
}

TEST(ProbeTouch, LinearAxisErrorMotionsSatisfyTheContactCondition) {
  const MachineModel m = TouchMachine();
  ErrorState e(m);
  // Curved positioning and straightness of X and a pitch growing with X: the tool point is no
  // longer affine in the commands, so Newton iterates.
  const std::vector<std::pair<std::string, double>> values = {
      {"E_XX.c2", 2e-6}, {"E_ZX.c2", -3e-6}, {"E_BX.c1", 1e-6}, {"E_ZY.c2", 2e-6}};
  std::vector<std::string> names;
  for (const auto& v : values) names.push_back(v.first);
  ASSERT_TRUE(ActivateParameters(m, &e, names).ok());
  for (const auto& [name, value] : values) {
    const std::optional<int> i = e.FindCoefficient(name);
    ASSERT_TRUE(i.has_value()) << name;
    e.set_coefficient(*i, value);
  }
  const double r_mm = TouchOptions{}.probe_radius_mm;
  double max_shift_mm = 0.0;
  for (const AxisState& rotary : TouchRotaryGrid()) {
    const Rigid3 nominal = NominalMachineFromTable(m, rotary);
    for (const TouchTarget& t : TouchTargets()) {
      const Eigen::Vector3d reading = TouchOrDie(m, e, rotary, t);
      const Eigen::Vector3d d = NominalApproach(m, rotary, t.face);
      const Eigen::Vector3d centre = reading - r_mm * d;
      AxisState at = rotary;
      at.x_mm = centre.x();
      at.y_mm = centre.y();
      at.z_mm = centre.z();
      Workspace ws;
      const Eigen::Vector3d q = ToolPointInPart(m, e, at, Eigen::Vector3d::Zero(), &ws);
      EXPECT_LT(std::abs(t.face.normal.dot(q) - (t.face.offset_mm() + r_mm)), kTouchNewton_mm) << TouchWhere(t, rotary);
      // On the nominal approach line through the planned ball centre.
      const Eigen::Vector3d c0 = nominal * (t.point_mm + r_mm * t.face.normal);
      EXPECT_LT((centre - c0).cross(d).norm(), kTouchNewton_mm) << TouchWhere(t, rotary);
      max_shift_mm = std::max(max_shift_mm, (reading - nominal * t.point_mm).norm());
    }
  }
  EXPECT_GT(max_shift_mm, UmToMm(10.0));  // the errors are visible (x ~ 100 mm: 2e-6 * 1e4 = 20 um)
}

TEST(ProbeTouch, ConstantPretravelDelaysTheReadingAlongTheApproach) {
  const MachineModel m = TouchMachine();
  const ErrorState e = TouchErrors(m, {{"E_X0C", UmToMm(10.0)}, {"E_B0C", UradToRad(50.0)}});
  TouchOptions p0;
  p0.pretravel_um = 2.0;
  for (const AxisState& rotary : TouchRotaryGrid()) {
    for (const TouchTarget& t : TouchTargets()) {
      const Eigen::Vector3d d = NominalApproach(m, rotary, t.face);
      const Eigen::Vector3d shift = TouchOrDie(m, e, rotary, t, p0) - TouchOrDie(m, e, rotary, t);
      EXPECT_LT((shift - UmToMm(2.0) * d).norm(), kTouchArithmetic_mm) << TouchWhere(t, rotary);
    }
  }
}

TEST(ProbeTouch, LobedPretravelFollowsTheApproachAzimuth) {
  const MachineModel m = TouchMachine();
  const ErrorState none(m);
  TouchOptions p3;
  p3.pretravel_lobing_um = 1.5;
  for (const AxisState& rotary : TouchRotaryGrid()) {
    for (const TouchTarget& t : TouchTargets()) {
      const Eigen::Vector3d d = NominalApproach(m, rotary, t.face);
      const double shift_mm = d.dot(TouchOrDie(m, none, rotary, t, p3) - TouchOrDie(m, none, rotary, t));
      // |d_xy| cos(3 phi) = Re((d_x + i d_y)^3) / |d_xy|^2; 0 on a vertical approach.
      const double dxy2 = d.x() * d.x() + d.y() * d.y();
      const double lobe = dxy2 > 1e-18 ? (d.x() * d.x() * d.x() - 3.0 * d.x() * d.y() * d.y()) / dxy2 : 0.0;
      EXPECT_NEAR(shift_mm, UmToMm(1.5) * lobe, kTouchArithmetic_mm) << TouchWhere(t, rotary);
    }
  }
  // Stated cases at A = C = 0 on box 1: +Z approached along -Z (vertical, nothing), -X along +X
  // (phi = 0, +p3), +X along -X (phi = 180 deg, -p3), +Y along -Y (phi = -90 deg, 0).
  const ArtifactBox box = Seed000Artifacts().boxes[0];
  const AxisState home = TouchRotary(0.0, 0.0);
  const std::pair<BoxFace, double> cases[] = {
      {BoxFace::kPlusZ, 0.0}, {BoxFace::kMinusX, 1.5}, {BoxFace::kPlusX, -1.5}, {BoxFace::kPlusY, 0.0}};
  for (const auto& [face, expected_um] : cases) {
    const FaceGeometry g = FaceOf(box, face);
    const TouchTarget t{g, g.centre_mm, std::string("box 1 ") + BoxFaceName(face)};
    const Eigen::Vector3d shift = TouchOrDie(m, none, home, t, p3) - TouchOrDie(m, none, home, t);
    EXPECT_LT((shift - UmToMm(expected_um) * NominalApproach(m, home, g)).norm(), kTouchArithmetic_mm) << t.name;
  }
}

TEST(ProbeTouch, OptionsValidate) {
  EXPECT_TRUE(TouchOptions{}.Validate().ok());
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  std::vector<TouchOptions> bad(6);
  bad[0].probe_radius_mm = 0.0;
  bad[1].probe_radius_mm = -1.0;
  bad[2].probe_radius_mm = nan;
  bad[3].probe_radius_mm = inf;
  bad[4].pretravel_um = nan;
  bad[5].pretravel_lobing_um = inf;
  const MachineModel m = TouchMachine();
  const ErrorState none(m);
  const FaceGeometry g = FaceOf(Seed000Artifacts().boxes[0], BoxFace::kPlusZ);
  for (std::size_t i = 0; i < bad.size(); ++i) {
    EXPECT_EQ(bad[i].Validate().code(), StatusCode::kInvalidArgument) << i;
    const Result<Eigen::Vector3d> c = SimulateTouch(m, none, TouchRotary(0, 0), g, g.centre_mm, bad[i]);
    ASSERT_FALSE(c.ok()) << i;
    EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument) << i;
  }
}

TEST(ProbeTouch, ApproachParallelToTheFaceIsNotConverged) {
  const MachineModel m = TouchMachine();
  // The C axis tilted 90 deg about Y: the top face stands vertical, the nominal approach (-Z)
  // slides along it.
  const ErrorState e = TouchErrors(m, {{"E_B0C", kPi / 2.0}});
  const FaceGeometry g = FaceOf(Seed000Artifacts().boxes[0], BoxFace::kPlusZ);
  const Result<Eigen::Vector3d> c = SimulateTouch(m, e, TouchRotary(0, 0), g, g.centre_mm, {});
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kNotConverged);
  EXPECT_NE(c.status().message().find("parallel"), std::string::npos) << c.status().ToString();
}

}  // namespace
}  // namespace tpcal::kinematics
