// Internal to fitting/: exact geometry behind the minimum-zone evaluations (2D in
// minimum_zone_exact2.cc, the only fitting/ translation unit with CGAL 2D kernels). Input
// coordinates are taken as exact binary numbers; decisions below are exact unless said otherwise.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fitting/minimum_zone.h"

namespace tpcal::fitting::internal {

// Index of the first non-finite coordinate, or -1.
long FirstNonFinite(std::span<const Eigen::Vector2d> points_mm);
long FirstNonFinite(std::span<const Eigen::Vector3d> points_mm);

// True if all points lie exactly on one line (or coincide).
bool AllCollinear2(std::span<const Eigen::Vector2d> points_mm);

// Extreme points of the convex hull in counter-clockwise order (points on edges excluded).
std::vector<std::size_t> ConvexHull2(std::span<const Eigen::Vector2d> points_mm);

// Minimum-width strip (exact rotating calipers over the exact hull; widths compared as rationals).
struct Strip2 {
  bool ok = false;
  std::string message;
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // unit (rounded), points from lower to upper line
  double lower_offset_mm = 0;  // normal . x on the lower line (rounded)
  double width_mm = 0;         // sqrt of the exact squared width, rounded
  std::vector<ZoneContact> contacts;  // points exactly on either line; kUpper = the +normal line
};
Strip2 MinimumWidthStrip2(std::span<const Eigen::Vector2d> points_mm);

// A rigorous lower bound of the minimum width of the points (floating point, outward rounding
// margin): used by the circularity exclusion search.
double MinimumWidthLowerBound2(std::span<const Eigen::Vector2d> points_mm);

// The annulus whose centre is equidistant from outer points a1, a2 and from inner points b1, b2,
// computed and checked in rational arithmetic.
struct ExactAnnulus {
  bool ok = false;            // centre defined (bisectors not parallel) and r < R
  bool contains_all = false;  // every point has r <= |p - c| <= R (exact)
  bool alternating = false;   // a1, b1, a2, b2 alternate strictly in angle about c (exact):
                              // the first-order optimality condition of R - r
  Eigen::Vector2d center_mm = Eigen::Vector2d::Zero();  // rounded
  double r_inner_mm = 0, r_outer_mm = 0, width_mm = 0;  // rounded; width from exact R^2 - r^2
  std::vector<ZoneContact> contacts;                    // every point exactly on either circle
  std::size_t first_violation = 0;                      // a point outside, if !contains_all
};
ExactAnnulus ExactAnnulus22(std::span<const Eigen::Vector2d> points_mm, std::size_t a1, std::size_t a2,
                            std::size_t b1, std::size_t b2);

// Minimum circumscribed circle (CGAL Min_circle_2 with an exact kernel).
struct ExactCircle {
  bool ok = false;
  std::string message;
  Eigen::Vector2d center_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0;
  std::vector<ZoneContact> contacts;  // points exactly on the circle
};
ExactCircle MinCircumscribedCircle2(std::span<const Eigen::Vector2d> points_mm);

// Largest empty circle with centre in the convex hull (Delaunay with exact predicates; candidates
// are Voronoi vertices and Voronoi-edge crossings of hull edges; ties resolved in rationals).
ExactCircle MaxInscribedCircle2(std::span<const Eigen::Vector2d> points_mm);

// Reference: CGAL Width_3 on ALL points (exact, slow: its own exact hull and antipodal search).
// Returns the exact minimum width, rounded; kTooFewPoints / kDegenerate as MinimumZoneFlatness.
// Used by tests and by tests/bench/zone_bench.cc as the baseline; implemented in flatness_zone.cc.
Result<double> FlatnessWidth3AllPoints(std::span<const Eigen::Vector3d> points_mm);

// MinimumZoneFlatness with the subset size beyond which the exact convex hull replaces the
// extreme subset (public default 400; tests pass 0 to exercise the hull path).
Result<FlatnessZone> MinimumZoneFlatnessWithSubsetLimit(std::span<const Eigen::Vector3d> points_mm,
                                                        const ZoneOptions& options,
                                                        std::optional<Eigen::Vector3d> normal_hint,
                                                        std::size_t max_subset);

}  // namespace tpcal::fitting::internal
