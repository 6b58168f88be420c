#include "fitting/sphere_fit.h"

#include "fitting/internal/hypersphere.h"

namespace tpcal::fitting {

Result<FitResult<Sphere>> FitSphere(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options) {
  auto sol = internal::FitHypersphere<3>(points_mm, options, "FitSphere");
  if (!sol.ok()) return sol.status();
  FitResult<Sphere> r;
  r.feature = Sphere{sol->center_mm, sol->radius_mm};
  r.n_points = points_mm.size();
  r.parameter_names = {"center_x_mm", "center_y_mm", "center_z_mm", "radius_mm"};
  sol->summary.MoveInto(r);
  return r;
}

}  // namespace tpcal::fitting
