#include "kinematics/probe_touch.h"

#include <cmath>
#include <string>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics {
namespace {

// Newton stop: the ball centre within 1e-9 mm of its contact plane (header contract).
constexpr double kTouchContactTol_mm = 1e-9;
constexpr int kTouchMaxNewtonSteps = 20;
// Central-difference step for df/ds. ToolPointInPart is affine in the linear commands unless the
// linear axes carry position-dependent errors (then smooth and of micrometre size over
// millimetres), so the O(h^2) truncation at 1e-3 mm is far below what Newton needs.
constexpr double kTouchDiffStep_mm = 1e-3;
// |df/ds| = |cos| of the angle between the approach (mapped into the part) and the face normal;
// nominally 1. Below this the approach runs parallel to the face.
constexpr double kTouchMinSlope = 1e-6;
// Below this horizontal component the approach is vertical and its azimuth undefined.
constexpr double kTouchVerticalXy = 1e-9;

// The probe-centre command on the approach line at parameter s (mm); the rotary commands, time and
// operation of `rotary` are kept (drift and operation terms see the touch's instant).
AxisState TouchCommandAt(const AxisState& rotary, const Eigen::Vector3d& c_mm) {
  AxisState s = rotary;
  s.x_mm = c_mm.x();
  s.y_mm = c_mm.y();
  s.z_mm = c_mm.z();
  return s;
}

// Pre-travel (um) along the unit approach `d` (machine frame): p0 + p3 |d_xy| cos(3 phi),
// phi = atan2(d_y, d_x). The three-lobed term is scaled by the horizontal component |d_xy| so it
// fades continuously to zero as the approach turns vertical (where phi is undefined): a vertical
// approach gets only p0, a horizontal one the full p0 + p3 cos(3 phi).
double TouchPretravel_um(const TouchOptions& options, const Eigen::Vector3d& d) {
  double p_um = options.pretravel_um;
  const double dxy = std::hypot(d.x(), d.y());
  if (dxy > kTouchVerticalXy) {
    p_um += options.pretravel_lobing_um * dxy * std::cos(3.0 * std::atan2(d.y(), d.x()));
  }
  return p_um;
}

}  // namespace

Status TouchOptions::Validate() const {
  if (!std::isfinite(probe_radius_mm) || probe_radius_mm <= 0.0) {
    return Status(StatusCode::kInvalidArgument,
                  "probe_radius_mm must be finite and > 0, got " + std::to_string(probe_radius_mm));
  }
  if (!std::isfinite(pretravel_um)) {
    return Status(StatusCode::kInvalidArgument, "pretravel_um must be finite");
  }
  if (!std::isfinite(pretravel_lobing_um)) {
    return Status(StatusCode::kInvalidArgument, "pretravel_lobing_um must be finite");
  }
  return Status::Ok();
}

Result<Eigen::Vector3d> SimulateTouch(const MachineModel& model, const ErrorState& errors,
                                      const AxisState& rotary, const FaceGeometry& face,
                                      const Eigen::Vector3d& target_part_mm, const TouchOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  const double r_mm = options.probe_radius_mm;
  const Eigen::Vector3d& n = face.normal;
  const double plane_mm = face.offset_mm() + r_mm;  // the ball centre's plane: n . q = offset + r

  // 1. The nominal approach line c(s) = c0 + s d through the planned probe-centre command.
  const Eigen::Vector3d c0 = NominalMachineFromTable(model, rotary) * (target_part_mm + r_mm * n);
  const Eigen::Vector3d d = NominalApproach(model, rotary, face);

  // 2. Newton on f(s) = n . ToolPointInPart(c(s)) - (offset + r), df/ds by a central difference.
  Workspace ws;
  const Eigen::Vector3d no_offset = Eigen::Vector3d::Zero();
  auto f = [&](double s) {
    return n.dot(ToolPointInPart(model, errors, TouchCommandAt(rotary, c0 + s * d), no_offset, &ws)) - plane_mm;
  };
  double s = 0.0;
  double fs = f(s);
  for (int step = 0; std::abs(fs) > kTouchContactTol_mm; ++step) {
    if (step == kTouchMaxNewtonSteps || !std::isfinite(fs)) {
      return Status(StatusCode::kNotConverged,
                    "probe touch: no contact within " + std::to_string(kTouchMaxNewtonSteps) +
                        " Newton steps (distance to the contact plane " + std::to_string(fs) + " mm)");
    }
    const double slope = (f(s + kTouchDiffStep_mm) - f(s - kTouchDiffStep_mm)) / (2.0 * kTouchDiffStep_mm);
    if (!(std::abs(slope) >= kTouchMinSlope)) {
      return Status(StatusCode::kNotConverged,
                    "probe touch: the approach runs parallel to the face under the errors (df/ds = " +
                        std::to_string(slope) + ")");
    }
    s -= fs / slope;
    fs = f(s);
  }

  // 3. The reading: the ball centre plus the radius and the pre-travel along the approach.
  const double reach_mm = r_mm + UmToMm(TouchPretravel_um(options, d));
  return Eigen::Vector3d(c0 + s * d + reach_mm * d);
}

}  // namespace tpcal::kinematics
