// Certified reference data for the least-squares fitters, built the way ISO 10360-6 and the
// NIST StRD construct theirs: exact points on a known feature, each displaced along the
// feature's normal by a deviation e_i, with e orthogonal to every column of the fit Jacobian
// at the true parameters (J^T e = 0). The Gaussian (orthogonal distance) fit of the displaced
// points is then the known feature exactly, and e are its residuals.
//
// J is built here independently of the fitters: its columns are the first-order residual
// changes under the feature's rigid motions (dr_i = -n_i . (t + w x (f_i - o)) at foot point
// f_i with unit normal n_i) and under its size parameters (radius; the cone's half angle).
// This holds exactly, not only to first order: the orthogonal-distance gradient depends only
// on the foot point, which a displacement along n_i does not move. Lengths in mm, angles in rad.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/units.h"
#include "fitting/features.h"

namespace tpcal::fitting {

// The construction certifies a stationary point of the LS cost; it is the minimum while the
// deviations are small against the feature (second-order terms ~ deviation / radius or
// deviation / extent stay below the weakest curvature of the cost). Keep deviation_rms_mm
// below ~1% of the smallest extent and of radius x arc^2 for short arcs.
struct ReferenceOptions {
  std::size_t n_points = 50;
  double deviation_rms_mm = 0.001;  // RMS of the certified residuals; 0 = points on the feature
  // Circle, cylinder, cone: sampled arc [arc_start_rad, arc_start_rad + arc_rad] about the
  // axis, angle 0 along AnyPerpendicular(axis) (Circle2: along +x). Sphere: arc_rad is the
  // half angle of the sampled cap about cap_axis (pi = whole sphere).
  double arc_start_rad = 0.0;
  double arc_rad = 2.0 * kPi;
  Eigen::Vector3d cap_axis = Eigen::Vector3d::UnitZ();
  // Lines, cylinders, cones: axial extent centred on the feature's point (mm).
  // Planes: the patch is length_mm x width_mm about point_mm, length along AnyPerpendicular(normal).
  double length_mm = 10.0;
  double width_mm = 10.0;
  Status Validate() const;
};

// The certified set: points, the feature their least-squares fit must return, and the fit's
// residuals (signed as the fitters report them; Line3: unsigned distances; Circle3: the
// radial deviation in the circle's plane).
template <typename F, typename P>
struct ReferenceSet {
  F truth;
  std::vector<P> points_mm;
  std::vector<double> residuals_mm;
};

// Positions are stratified-random along the arc / length (one per equal slot), deviations
// are Gaussian, projected onto the null space of J^T and scaled to deviation_rms_mm.
// Errors: kInvalidArgument (bad options, or a cone whose apex falls inside length_mm),
// kTooFewPoints (fewer points than the feature has parameters).
Result<ReferenceSet<Line2, Eigen::Vector2d>> MakeReferenceLine2(const Line2& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng);
Result<ReferenceSet<Line3, Eigen::Vector3d>> MakeReferenceLine3(const Line3& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng);
Result<ReferenceSet<Plane, Eigen::Vector3d>> MakeReferencePlane(const Plane& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng);
Result<ReferenceSet<Circle2, Eigen::Vector2d>> MakeReferenceCircle2(const Circle2& truth, const ReferenceOptions& o,
                                                                    std::mt19937_64& rng);
// Circle in space, certified for FitCircle3's two-step method: the deviations normal to the
// plane are orthogonal to the plane's Jacobian, the in-plane radial ones to the circle's;
// both have RMS deviation_rms_mm.
Result<ReferenceSet<Circle3, Eigen::Vector3d>> MakeReferenceCircle3(const Circle3& truth, const ReferenceOptions& o,
                                                                    std::mt19937_64& rng);
Result<ReferenceSet<Sphere, Eigen::Vector3d>> MakeReferenceSphere(const Sphere& truth, const ReferenceOptions& o,
                                                                  std::mt19937_64& rng);
Result<ReferenceSet<Cylinder, Eigen::Vector3d>> MakeReferenceCylinder(const Cylinder& truth,
                                                                      const ReferenceOptions& o,
                                                                      std::mt19937_64& rng);
Result<ReferenceSet<Cone, Eigen::Vector3d>> MakeReferenceCone(const Cone& truth, const ReferenceOptions& o,
                                                              std::mt19937_64& rng);

// Deviations e (size = J.rows()) with J^T e = 0 to working precision and RMS rms_mm, from
// Gaussian draws; zero when J has no null space left (as many rows as its rank).
Eigen::VectorXd NullSpaceDeviations(const Eigen::MatrixXd& j, double rms_mm, std::mt19937_64& rng);

}  // namespace tpcal::fitting
