// FitCone, declared in fitting/cylinder_fit.h (the axis-based surfaces share that header).
#include <cmath>
#include <string>
#include <vector>

#include "core/units.h"
#include "fitting/cylinder_fit.h"
#include "fitting/internal/axis_fit.h"

namespace tpcal::fitting {

Result<FitResult<Cone>> FitCone(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options,
                                std::optional<Eigen::Vector3d> axis_hint) {
  using internal::ConeModel;
  const std::string what = "FitCone";
  auto setup = internal::SetUpAxisFit(points_mm, 6, options, what);
  if (!setup.ok()) return setup.status();
  auto dirs = internal::StartDirections(*setup, axis_hint, what, [](const internal::AxisDirectionScore& s,
                                                                   const Eigen::Vector3d& w) { return s.Cone(w); });
  if (!dirs.ok()) return dirs.status();
  // Starts from the algebraic cone about each direction: with the regression
  // |P X|^2 = b0 + bX.X + bw w^2, the axis passes through C = (bX - (bX.W) W) / 2, the
  // radius there is R = sqrt(b0 + |C|^2) and tan(half angle) = (bX.W) / (2 R). If that
  // has no real radius, the projected LS circle with half angle 0.
  const internal::AxisDirectionScore score(internal::AxisMoments(
      setup->sample_mm.size(),
      [&](std::size_t k) -> Eigen::Vector3d { return (setup->sample_mm[k] - setup->origin_mm) / setup->scale_mm; }));
  std::vector<ConeModel::State> starts;
  for (const auto& w : *dirs) {
    Eigen::VectorXd beta;
    score.Cone(w, &beta);
    const Eigen::Vector3d bx = beta.segment<3>(1);
    const Eigen::Vector3d c = 0.5 * (bx - bx.dot(w) * w);
    const double r2 = beta[0] + c.squaredNorm();
    if (r2 > 0.0 && std::isfinite(r2)) {
      const double r = std::sqrt(r2);
      starts.push_back({internal::MakeAxis(c, w), r, std::atan(bx.dot(w) / (2.0 * r))});
    } else if (auto s = internal::ProjectedCircleStart(*setup, w)) {
      starts.push_back({s->axis, s->radius, 0.0});
    }
  }
  if (starts.empty()) {
    return Status(StatusCode::kDegenerate, what + ": no direction gives a circular cross-section (the points do "
                                                  "not lie on a cone: collinear or coplanar?)");
  }
  auto run = internal::BestOfStarts<ConeModel>(points_mm, *setup, starts, options);
  if (!run.ok()) return run.status().WithContext(what);
  const ConeModel model(points_mm, setup->origin_mm, setup->scale_mm);
  // The axis points toward the wider end: a negative half angle means the cone widens along -a.
  if (run->state.half_angle < 0.0) {
    run->state.axis = internal::Reversed(run->state.axis);
    run->state.half_angle = -run->state.half_angle;
    run->lin = model.Linearize(run->state, nullptr, nullptr);
  }
  const double half_angle = run->state.half_angle;
  if (!(half_angle > 0.0)) {
    return Status(StatusCode::kDegenerate, what + ": the least-squares half angle is 0 (the points lie on a "
                                                  "cylinder: use FitCylinder)");
  }
  if (!(half_angle < kPi / 2 - 1e-6)) {
    return Status(StatusCode::kDegenerate, what + ": the least-squares half angle is 90 deg (the points lie on a plane)");
  }
  if (!(run->state.radius > 0.0) || !(run->state.radius <= 1e6 * setup->extent)) {
    return Status(StatusCode::kDegenerate, what + ": the cone's radius at the data centroid is not positive (points "
                                                  "on both sides of the apex?) or beyond 1e6 x the extent of the data");
  }
  const std::vector<std::string> names = {"offset_u_mm", "offset_v_mm", "tilt_u_rad",
                                          "tilt_v_rad",  "radius_mm",   "half_angle_rad"};
  auto summary = internal::Summarize(model, *run, names, what, options);
  if (!summary.ok()) return summary.status();
  FitResult<Cone> r;
  r.feature = Cone{model.ToMm(run->state.axis.point), run->state.axis.dir(), half_angle,
                   run->state.radius * setup->scale_mm};
  r.n_points = points_mm.size();
  r.parameter_names = names;
  r.local_axes = run->state.axis.frame;
  summary->MoveInto(r);
  return r;
}

}  // namespace tpcal::fitting
