// Datum reference frames (ISO 5459) built from fitted datum features, all inputs in the CMM
// frame (mm). Output: datum_from_cmm (core/frames.h naming): p_in_datum = datum_from_cmm * p_in_cmm.
// Nothing here assumes the CMM frame is the part frame: the part may sit anywhere, in any
// orientation; axis senses come from the caller (part-intrinsic rules, gdt/plan.h AxisSense).
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>

#include "core/frames.h"
#include "core/status.h"
#include "fitting/features.h"
#include "fitting/fit_result.h"

namespace tpcal::gdt {

// Unit vector `direction` flipped if needed so that direction . sense > 0.
// Errors: kDegenerate if |direction . sense| <= 1e-6 |sense| (the sense does not decide), or
// sense is zero. `what` names the axis in the message.
Result<Eigen::Vector3d> OrientAlong(const Eigen::Vector3d& direction, const Eigen::Vector3d& sense,
                                    const std::string& what);

// Right-handed frame: +Z = unit `z_axis`, +X = `x_direction` made perpendicular to z (its
// component along z removed), +Y = Z x X, origin at `origin_mm`; all in the CMM frame.
// Errors: kDegenerate if x_direction is (nearly, < 1e-9 rad) parallel to z_axis.
Result<Rigid3> DatumFromAxes(const Eigen::Vector3d& origin_mm, const Eigen::Vector3d& z_axis,
                             const Eigen::Vector3d& x_direction);

// Centre, in the CMM frame and on `plane`, of the least-squares circle (fitting::FitCircle2)
// of `points_mm` projected orthogonally into `plane`. This is how a circle's centre is measured
// "projected in the datum plane": it does not depend on the points' own (noisy) plane, and
// works for points probed at a single height. Errors: those of FitCircle2 (kTooFewPoints < 3,
// kDegenerate for collinear projections).
Result<Eigen::Vector3d> ProjectedCircleCenter(std::span<const Eigen::Vector3d> points_mm, const fitting::Plane& plane,
                                              const fitting::FitOptions& options = {});

// Turning test piece frame of seed 002 section 2.2. `primary`: LS plane of B_R with its
// normal already oriented to the part's +Z (the Z axis and z = 0). `center_mm`: LS centre of
// S_R (ProjectedCircleCenter into `primary`): the XY origin. `x_target_mm`: centre of hole H1:
// +X points from the origin toward its projection into the plane. Errors: kDegenerate if the
// x target projects onto the origin.
Result<Rigid3> TurningDatumFromCmm(const fitting::Plane& primary, const Eigen::Vector3d& center_mm,
                                   const Eigen::Vector3d& x_target_mm);

// 3-2-1 frame: +Z = primary.normal (oriented by the caller), z = 0 on `primary`; +X along
// `secondary.direction` (oriented by the caller) projected into the primary plane, y = 0 on the
// secondary line's projection; x = 0 at the foot of `tertiary_mm` on that projected line.
// Errors: kDegenerate if the secondary line is (nearly) normal to the primary plane.
Result<Rigid3> ThreeTwoOneDatumFromCmm(const fitting::Plane& primary, const fitting::Line3& secondary,
                                       const Eigen::Vector3d& tertiary_mm);

// Datum-target frame (plan type `targets`): +Z = primary.normal (oriented by the caller), z = 0
// on `primary`; origin at the foot of `center_mm` on the primary plane; +X (or +Y when
// `target_sets_y`) points from the origin toward the projection of `target_mm` into the plane.
// Errors: kDegenerate if the target projects onto the origin.
Result<Rigid3> TargetsDatumFromCmm(const fitting::Plane& primary, const Eigen::Vector3d& center_mm,
                                   const Eigen::Vector3d& target_mm, bool target_sets_y);

}  // namespace tpcal::gdt
