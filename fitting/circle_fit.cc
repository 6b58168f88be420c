#include "fitting/circle_fit.h"

#include <sstream>
#include <string>
#include <vector>

#include "fitting/internal/hypersphere.h"
#include "fitting/plane_fit.h"

namespace tpcal::fitting {

Result<FitResult<Circle2>> FitCircle2(std::span<const Eigen::Vector2d> points_mm, const FitOptions& options) {
  auto sol = internal::FitHypersphere<2>(points_mm, options, "FitCircle2");
  if (!sol.ok()) return sol.status();
  FitResult<Circle2> r;
  r.feature = Circle2{sol->center_mm, sol->radius_mm};
  r.n_points = points_mm.size();
  r.parameter_names = {"center_x_mm", "center_y_mm", "radius_mm"};
  sol->summary.MoveInto(r);
  return r;
}

Result<FitResult<Circle3>> FitCircle3(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options,
                                      std::optional<Eigen::Vector3d> axis_hint) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (points_mm.size() < 3) {
    return Status(StatusCode::kTooFewPoints,
                  "FitCircle3 needs at least 3 points, got " + std::to_string(points_mm.size()));
  }
  FitOptions plane_options = options;
  plane_options.keep_residuals = false;
  plane_options.keep_jacobian = false;
  plane_options.compute_covariance = false;
  auto plane = FitPlane(points_mm, plane_options, axis_hint);
  if (!plane.ok()) return plane.status().WithContext("FitCircle3 (plane step)");
  const Eigen::Vector3d origin = plane->feature.point_mm;
  const Eigen::Vector3d u = plane->local_axes.col(0);
  const Eigen::Vector3d v = plane->local_axes.col(1);
  std::vector<Eigen::Vector2d> in_plane(points_mm.size());
  for (std::size_t i = 0; i < points_mm.size(); ++i) {
    const Eigen::Vector3d d = points_mm[i] - origin;
    in_plane[i] = Eigen::Vector2d(u.dot(d), v.dot(d));
  }
  auto sol = internal::FitHypersphere<2>(in_plane, options, "FitCircle3 (circle step)");
  if (!sol.ok()) return sol.status();
  FitResult<Circle3> r;
  r.feature = Circle3{origin + sol->center_mm.x() * u + sol->center_mm.y() * v, plane->feature.normal, sol->radius_mm};
  r.n_points = points_mm.size();
  r.local_axes = plane->local_axes;
  r.parameter_names = {"center_u_mm", "center_v_mm", "radius_mm"};
  sol->summary.MoveInto(r);
  std::ostringstream os;
  os << r.message << "; plane step: out-of-plane rms " << plane->stats.rms_mm << " mm";
  r.message = os.str();
  return r;
}

}  // namespace tpcal::fitting
