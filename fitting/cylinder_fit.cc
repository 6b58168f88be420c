#include "fitting/cylinder_fit.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "fitting/internal/axis_fit.h"
#include "fitting/internal/orientation.h"

namespace tpcal::fitting {
namespace {

// Axes in the plane of the points, every 10 degrees, tried when the algebraic score's starts give
// no cylinder (no start, no convergence, or a radius beyond 1e6 x the data's extent). A shallow
// patch (a 20 degree arc 0.2 R long: 0.35 R by 0.2 R, sagitta 1.5 % of R) can have every minimum
// of the algebraic score off its axis, and from a wrong axis Levenberg-Marquardt runs off toward
// the plane (R -> infinity); a cylinder's axis lies close to the best-fit plane of such a patch.
std::vector<Eigen::Vector3d> InPlaneDirections(const internal::AxisFitSetup& setup) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : setup.sample_mm) mean += p;
  mean /= static_cast<double>(setup.sample_mm.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : setup.sample_mm) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const Eigen::Vector3d e1 = eig.eigenvectors().col(2), e2 = eig.eigenvectors().col(1);
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < 18; ++k) {
    const double a = k * (kPi / 18.0);
    out.push_back(std::cos(a) * e1 + std::sin(a) * e2);
  }
  return out;
}

}  // namespace

Result<FitResult<Cylinder>> FitCylinder(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options,
                                        std::optional<Eigen::Vector3d> axis_hint) {
  using internal::CylinderModel;
  const std::string what = "FitCylinder";
  auto setup = internal::SetUpAxisFit(points_mm, 5, options, what);
  if (!setup.ok()) return setup.status();
  auto dirs = internal::StartDirections(*setup, axis_hint, what, [](const internal::AxisDirectionScore& s,
                                                                   const Eigen::Vector3d& w) { return s.Cylinder(w); });
  if (!dirs.ok()) return dirs.status();
  std::vector<CylinderModel::State> starts;
  for (const auto& w : *dirs) {
    if (auto s = internal::ProjectedCircleStart(*setup, w)) starts.push_back(*s);
  }
  const bool no_start = starts.empty();
  using Run = Result<internal::LmRun<CylinderModel>>;
  auto usable = [&](const Run& r) { return r.ok() && r->state.radius > 0.0 && r->state.radius <= 1e6 * setup->extent; };
  Run run = no_start ? Run(Status(StatusCode::kDegenerate, "no start"))
                     : internal::BestOfStarts<CylinderModel>(points_mm, *setup, starts, options);
  if (!usable(run) && !axis_hint.has_value()) {
    std::vector<CylinderModel::State> more;
    for (const auto& w : InPlaneDirections(*setup))
      if (auto s = internal::ProjectedCircleStart(*setup, w)) more.push_back(*s);
    Run again = more.empty() ? Run(Status(StatusCode::kDegenerate, "no start"))
                             : internal::BestOfStarts<CylinderModel>(points_mm, *setup, more, options);
    if (usable(again) || (!run.ok() && again.ok())) run = std::move(again);
  }
  if (!run.ok() && no_start) {
    return Status(StatusCode::kDegenerate, what + ": no direction gives a circular cross-section (the points do "
                                                  "not lie on a cylinder: collinear or coplanar?)");
  }
  if (!run.ok()) return run.status().WithContext(what);
  const CylinderModel model(points_mm, setup->origin_mm, setup->scale_mm);
  const Eigen::Vector3d a = run->state.axis.dir();
  if (internal::OrientAlong(a, axis_hint).dot(a) < 0.0) {
    run->state.axis = internal::Reversed(run->state.axis);
    run->lin = model.Linearize(run->state, nullptr, nullptr);
  }
  if (!(run->state.radius > 0.0) || !(run->state.radius <= 1e6 * setup->extent)) {
    return Status(StatusCode::kDegenerate,
                  what + ": the least-squares cylinder has no positive radius below 1e6 x the extent of the data "
                         "(points nearly coplanar)");
  }
  auto summary = internal::Summarize(
      model, *run, {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad", "radius_mm"}, what, options);
  if (!summary.ok()) return summary.status();
  FitResult<Cylinder> r;
  r.feature = Cylinder{model.ToMm(run->state.axis.point), run->state.axis.dir(), run->state.radius * setup->scale_mm};
  r.n_points = points_mm.size();
  r.parameter_names = {"offset_u_mm", "offset_v_mm", "tilt_u_rad", "tilt_v_rad", "radius_mm"};
  r.local_axes = run->state.axis.frame;
  summary->MoveInto(r);
  return r;
}

}  // namespace tpcal::fitting
