// A plan feature fitted to its points in the datum frame: the fitting/ result, the sense
// rules applied, and its form value under the feature's criterion (ls or mz).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "core/status.h"
#include "fitting/features.h"
#include "fitting/fit_result.h"
#include "gdt/form.h"
#include "gdt/form_zone.h"
#include "gdt/plan.h"

namespace tpcal::gdt {

// The centroid of a feature's points (kind point).
struct PointFeature {
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();
};

// Line2 and Circle2 fits live in the (u, v) coordinates of FittedFeature::projection
// (gdt/location.h InPlane); every other fit in datum-frame coordinates.
using FeatureFit = std::variant<fitting::FitResult<fitting::Line2>, fitting::FitResult<fitting::Line3>,
                                fitting::FitResult<fitting::Plane>, fitting::FitResult<fitting::Circle2>,
                                fitting::FitResult<fitting::Circle3>, fitting::FitResult<fitting::Cylinder>,
                                fitting::FitResult<fitting::Sphere>, fitting::FitResult<fitting::Cone>,
                                fitting::FitResult<PointFeature>>;

struct FittedFeature {
  std::string name;
  FeatureKind kind = FeatureKind::kPlane;
  Projection projection = Projection::kNone;  // Line2 / Circle2 fits: their plane
  double height_mm = 0;  // Line2 / Circle2 fits: mean coordinate of the points along the plane normal
  FeatureFit fit;        // in the datum frame (see above)
  FormCriterion criterion = FormCriterion::kLeastSquares;
  // Form value under `criterion` (mm): straightness (line2: parallel lines, line3: cylinder
  // diameter), flatness, circularity (radial), cylindricity / sphericity / cone form (LS
  // residual range). nullopt for points.
  std::optional<double> form_ls_mm;
  std::optional<MinimumZoneValue> form_mz;  // filled when criterion is mz (gdt/form_zone.h)
  std::vector<std::size_t> point_indices;  // into the PointSet; empty for pitch circles
  std::size_t first_line = 0;              // source line of the first point (0: unknown)
  std::vector<std::string> members;        // pitch circles: the member features
  std::vector<Eigen::Vector2d> member_centers_mm;  // pitch circles: member centres, (u, v) of `projection`

  template <typename F>
  const fitting::FitResult<F>* As() const { return std::get_if<fitting::FitResult<F>>(&fit); }
  // The form value under `criterion` (nullopt for points).
  std::optional<double> form_mm() const {
    if (criterion == FormCriterion::kMinimumZone) {
      return form_mz ? std::optional<double>(form_mz->width_mm) : std::nullopt;
    }
    return form_ls_mm;
  }
};

// Fits a point feature (any kind but pitch_circle) to `points_datum` (datum frame, mm).
// `indices` and `first_line` are recorded for reports and errors. Errors: the fitter's,
// with the feature named; kInternal if criterion mz is not available for this kind/build.
Result<FittedFeature> FitFeature(const FeatureSpec& spec, std::span<const Eigen::Vector3d> points_datum,
                                 std::vector<std::size_t> indices, std::size_t first_line,
                                 const fitting::FitOptions& options);

// Fits a pitch circle to the centres of already fitted member circles, in spec.projection.
Result<FittedFeature> FitPitchCircle(const FeatureSpec& spec, std::span<const FittedFeature* const> members,
                                     const fitting::FitOptions& options);

// Centre of a circle, pitch circle, sphere, point or cylinder (the axis point at the
// feature's point centroid), in the datum frame. Errors: kInvalidArgument for other kinds.
Result<Eigen::Vector3d> CenterOf(const FittedFeature& f);

// In-plane centre (u, v) of a centred feature in `plane`.
Result<Eigen::Vector2d> CenterInPlane(const FittedFeature& f, Projection plane);

// Oriented unit direction of a plane (normal), line3 (direction) or cylinder (axis), datum frame.
Result<Eigen::Vector3d> DirectionOf(const FittedFeature& f);

// Radius of a circle, pitch circle, cylinder or sphere (mm).
Result<double> RadiusOf(const FittedFeature& f);

// In-plane coordinates of `points_datum` for a circle feature and the circle in those
// coordinates: for Circle2 fits the projection plane; for Circle3 fits the circle's own plane
// with +u along datum X projected into it (datum Y if the axis is along X), +v = axis x u.
// This is the frame of the circularity profile's theta. Pitch circles return their member
// centres (points_datum unused).
Result<std::pair<std::vector<Eigen::Vector2d>, fitting::Circle2>> CircleCoordinates(
    const FittedFeature& f, std::span<const Eigen::Vector3d> points_datum);

}  // namespace tpcal::gdt
