// Minimum-zone (Chebyshev, ISO 1101 / ISO 12781, 12180, 12181, 12780) form evaluations with a
// certificate the caller can check, and the minimum circumscribed / maximum inscribed circles.
//
// Every result carries a ZoneCertificate: the indices of the contact points that define the zone,
// and whether optimality was verified, over which scope, with which proven gap.
//
// What is exact and what is floating point (input coordinates are taken as exact binary numbers):
//  - Flatness, 2D straightness, minimum circumscribed circle, maximum inscribed circle: the zone
//    is computed in exact rational/integer arithmetic (CGAL Width_3 with homogeneous GMP integers,
//    exact convex hull predicates, GMP rationals); the contact sets are exact (points lying exactly
//    on the zone boundary), optimality is global by construction (scope kGlobal, gap 0, exact).
//    Only the reported doubles (width_mm, normal, centre) are rounded, to ~1e-16 relative.
//  - Circularity (true minimum R - r, not minimum area): a sequential exact-LP refinement finds the
//    zone; the centre is then recomputed exactly (GMP rationals) from its 2 outer + 2 inner contact
//    points, containment of every point in the annulus and the alternation of the contacts (the
//    first-order optimality condition) are checked in exact arithmetic. A global exclusion search
//    (branch and bound with rigorous Lipschitz bounds, floating point with rounding margins) then
//    proves no other centre gives a narrower zone by more than gap_tolerance_mm / 2: scope kGlobal,
//    exact = true. Where the far region cannot be excluded (short arcs whose width does not exceed
//    the zone) or the search budget runs out, the scope stays kLocal and the message says why.
//  - 3D straightness (cylindrical zone about a line): sequential exact-LP refinement; the global
//    certificate is a proven lower bound (exact LP on a convex minorant, see straightness_zone.cc)
//    valid for every line in space: scope kGlobal with optimality_gap_mm ~ width * (width/length)^2.
//  - Cylindricity: sequential exact-LP refinement from the least-squares cylinder; certificate is
//    local: no cylinder whose axis end points move by at most certified_radius_mm (each coordinate,
//    in the plane normal to the axis) gives a zone narrower than width_mm - optimality_gap_mm.
//    A global guarantee for cylindricity is not attempted (the problem is non-convex in 4D).
// Floating-point quantities in certificates include explicit rounding margins.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "fitting/features.h"

namespace tpcal::fitting {

// Which boundary of the zone a contact point touches.
//   planes / strips: kUpper = the plane on the +normal side, kLower = the -normal side;
//   annuli / cylinders: kUpper = the outer circle/cylinder, kLower = the inner one;
//   single-boundary references (circumscribed, inscribed, 3D straightness): kUpper.
enum class ZoneSide { kLower, kUpper };

struct ZoneContact {
  std::size_t index;  // into the input span
  ZoneSide side;
  bool operator==(const ZoneContact&) const = default;
};

enum class OptimalityScope {
  kNotVerified,  // no certificate (the message says why); the zone is still a valid enclosing zone
  kLocal,        // optimal among features within certified_radius_mm of the reported one
  kGlobal,       // optimal among all features of that type
};
const char* OptimalityScopeName(OptimalityScope scope);

struct ZoneCertificate {
  std::vector<ZoneContact> contacts;  // sorted by index; the points on the zone boundary
  bool verified_optimal = false;      // scope != kNotVerified and optimality_gap_mm <= tolerance
  OptimalityScope scope = OptimalityScope::kNotVerified;
  bool exact = false;              // zone and contacts decided in exact arithmetic
  double optimality_gap_mm = std::numeric_limits<double>::infinity();  // proven: no feature in
                                   // scope has a zone narrower than width - gap
  double certified_radius_mm = std::numeric_limits<double>::infinity();  // kLocal neighbourhood
  std::string method;   // algorithm, e.g. "exact Width_3 on extreme subset"
  std::string message;  // how optimality was verified, or why not
};

struct ZoneOptions {
  double gap_tolerance_mm = 1e-9;  // verified_optimal needs optimality_gap_mm <= this (1 pm:
                                   // far below CMM resolution, far above double rounding)
  int max_iterations = 200;        // sequential-LP iterations (circularity, cylindricity, 3D line)
  bool certify_global = true;      // circularity: run the global exclusion search
  int max_global_boxes = 200000;   // circularity: budget of the exclusion search
  Status Validate() const;         // kInvalidArgument if a value is out of range
};

// ---- Flatness (ISO 12781): minimum distance between two parallel planes containing all points.
struct FlatnessZone {
  Plane plane;        // mid-plane of the zone; normal sign as FitPlane (or along normal_hint)
  double width_mm = 0;  // the minimum-zone flatness
  ZoneCertificate certificate;  // kGlobal, exact
  std::size_t n_points = 0;
};
// Errors: kTooFewPoints (< 3), kDegenerate (all points collinear or coincident), kInvalidArgument
// (non-finite coordinate). All points coplanar gives width 0.
Result<FlatnessZone> MinimumZoneFlatness(std::span<const Eigen::Vector3d> points_mm,
                                         const ZoneOptions& options = {},
                                         std::optional<Eigen::Vector3d> normal_hint = std::nullopt);

// ---- Straightness in a plane (ISO 12780 2D): minimum width strip.
struct StraightnessZone2 {
  Line2 line;           // mid-line; direction sign as FitLine2 (positive dot with last - first)
  double width_mm = 0;  // strip width
  ZoneCertificate certificate;  // kGlobal, exact; kUpper = the side to the left of direction
  std::size_t n_points = 0;
};
// Errors: kTooFewPoints (< 2), kDegenerate (all points coincide), kInvalidArgument.
Result<StraightnessZone2> MinimumZoneStraightness2(std::span<const Eigen::Vector2d> points_mm,
                                                   const ZoneOptions& options = {});

// ---- Straightness of a line in space with a cylindrical zone (ISO 1101 "diameter t"):
// minimum diameter of a cylinder about a line containing all points.
struct StraightnessZone3 {
  Line3 axis;              // zone axis; point_mm = foot of the data centroid; sign as FitLine3
  double diameter_mm = 0;  // the straightness value
  ZoneCertificate certificate;  // contacts all kUpper
  std::size_t n_points = 0;
  int iterations = 0;
};
// Errors: kTooFewPoints (< 3), kDegenerate (all points coincide, or the points do not spread along
// a line: extent along the axis <= the zone diameter), kNotConverged, kInvalidArgument.
Result<StraightnessZone3> MinimumZoneStraightness3(std::span<const Eigen::Vector3d> points_mm,
                                                   const ZoneOptions& options = {});

// ---- Circularity / roundness (ISO 12181 MZCI): minimum radial separation R - r of two concentric
// circles containing the points (NOT the minimum-area annulus of CGAL Min_annulus_d).
struct CircularityZone {
  Eigen::Vector2d center_mm = Eigen::Vector2d::Zero();
  double r_inner_mm = 0;
  double r_outer_mm = 0;
  double width_mm = 0;  // r_outer - r_inner, computed as (R^2 - r^2)/(R + r) from exact squares
  ZoneCertificate certificate;
  std::size_t n_points = 0;
  int iterations = 0;
};
// Errors: kTooFewPoints (< 4), kDegenerate (collinear points), kNotConverged, kInvalidArgument.
Result<CircularityZone> MinimumZoneCircularity(std::span<const Eigen::Vector2d> points_mm,
                                               const ZoneOptions& options = {});

// ---- Reference circles (ISO 12181 MCCI, MICI).
struct ReferenceCircle {
  Circle2 circle;
  double peak_to_valley_mm = 0;  // max - min distance of the points from circle.center_mm
  ZoneCertificate certificate;   // contacts (kUpper) are the points on the circle
  std::size_t n_points = 0;
};
// Smallest circle containing all points (CGAL Min_circle_2, exact). Global, exact.
// Errors: kTooFewPoints (< 2), kDegenerate (all points coincide), kInvalidArgument.
Result<ReferenceCircle> MinimumCircumscribedCircle(std::span<const Eigen::Vector2d> points_mm,
                                                   const ZoneOptions& options = {});
// Largest circle containing no point in its interior whose centre lies in the convex hull of the
// points (the "largest empty circle"; for a roundness profile, the inscribed circle). Global over
// that domain, exact (Delaunay with exact predicates, candidates compared in rationals).
// Errors: kTooFewPoints (< 3), kDegenerate (collinear points), kInvalidArgument.
Result<ReferenceCircle> MaximumInscribedCircle(std::span<const Eigen::Vector2d> points_mm,
                                               const ZoneOptions& options = {});

// ---- Cylindricity (ISO 12180 MZCY): minimum radial separation of two coaxial cylinders.
struct CylindricityZone {
  Line3 axis;  // point_mm = foot of the data centroid on the axis; sign as `start`'s axis
  double r_inner_mm = 0;
  double r_outer_mm = 0;
  double width_mm = 0;
  ZoneCertificate certificate;  // kLocal at best (see top of file)
  std::size_t n_points = 0;
  int iterations = 0;
};
// Starts from `start` if given (e.g. the least-squares cylinder), else from FitCylinder.
// Errors: kTooFewPoints (< 6), kDegenerate, kNotConverged, kInvalidArgument, and FitCylinder's.
Result<CylindricityZone> MinimumZoneCylindricity(std::span<const Eigen::Vector3d> points_mm,
                                                 const ZoneOptions& options = {},
                                                 std::optional<Cylinder> start = std::nullopt);

}  // namespace tpcal::fitting
