#include "gdt/fitted_feature.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "fitting/circle_fit.h"
#include "fitting/cylinder_fit.h"
#include "fitting/line_fit.h"
#include "fitting/plane_fit.h"
#include "fitting/sphere_fit.h"
#include "gdt/form_zone.h"
#include "gdt/location.h"
#include "gdt/orientation.h"

namespace tpcal::gdt {
namespace {

std::string Describe(const FeatureSpec& spec, std::size_t n) {
  return "feature '" + spec.name + "' (" + FeatureKindName(spec.kind) + ", " + std::to_string(n) + " points)";
}

// Sense for a direction-like fit result: the plan's nominal direction, else the datum axis of
// the fitted direction's largest component (positive).
Eigen::Vector3d SenseFor(const FeatureSpec& spec, const Eigen::Vector3d& fitted) {
  if (spec.nominal_direction) return *spec.nominal_direction;
  return Eigen::Vector3d::Unit(DominantAxis(fitted));
}

// Fits with `fit(hint)`; if the direction `dir_of(result)` disagrees with the sense rule,
// refits with the sense as hint, so the fitter's own sign rule (and its covariance frame)
// stays consistent with the reported direction.
template <typename F, typename Fit, typename DirOf>
Result<fitting::FitResult<F>> FitOriented(const FeatureSpec& spec, Fit&& fit, DirOf&& dir_of) {
  if (spec.nominal_direction) return fit(std::optional<Eigen::Vector3d>(*spec.nominal_direction));
  auto r = fit(std::optional<Eigen::Vector3d>());
  if (!r.ok()) return r;
  const Eigen::Vector3d d = dir_of(r->feature);
  const Eigen::Vector3d sense = SenseFor(spec, d);
  if (d.dot(sense) >= 0) return r;
  return fit(std::optional<Eigen::Vector3d>(sense));
}

std::vector<Eigen::Vector2d> Project(std::span<const Eigen::Vector3d> points, Projection plane, double* mean_height) {
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(points.size());
  double h = 0.0;
  for (const auto& p : points) {
    uv.push_back(InPlane(p, plane));
    h += AlongNormal(p, plane);
  }
  *mean_height = points.empty() ? 0.0 : h / static_cast<double>(points.size());
  return uv;
}

Eigen::Vector2d ProjectDirection(const Eigen::Vector3d& d, Projection plane) { return InPlane(d, plane); }

Status MzUnsupported(const FeatureSpec& spec) {
  return Status(StatusCode::kInvalidArgument, std::string("form_criterion mz is not defined for a ") +
                                                  FeatureKindName(spec.kind) + " (feature '" + spec.name + "')");
}

// Fills form_mz when the criterion asks for it.
Status FillMinimumZone(const FeatureSpec& spec, FittedFeature* f, std::span<const Eigen::Vector3d> points_datum,
                       std::span<const Eigen::Vector2d> points_uv) {
  if (spec.form_criterion != FormCriterion::kMinimumZone) return Status::Ok();
  Result<MinimumZoneValue> mz = Status(StatusCode::kInternal, "unset");
  switch (spec.kind) {
    case FeatureKind::kPlane: mz = MinimumZoneFlatness(points_datum); break;
    case FeatureKind::kLine2: mz = MinimumZoneStraightness2(points_uv); break;
    case FeatureKind::kLine3: mz = MinimumZoneStraightness3(points_datum); break;
    case FeatureKind::kCircle:
    case FeatureKind::kPitchCircle: mz = MinimumZoneCircularity(points_uv); break;
    case FeatureKind::kCylinder: {
      const auto* c = f->As<fitting::Cylinder>();
      mz = MinimumZoneCylindricity(points_datum, c ? std::optional<fitting::Cylinder>(c->feature) : std::nullopt);
      break;
    }
    default: return MzUnsupported(spec);
  }
  if (!mz.ok()) return mz.status().WithContext("feature '" + spec.name + "' minimum zone");
  f->form_mz = *mz;
  return Status::Ok();
}

}  // namespace

Result<std::pair<std::vector<Eigen::Vector2d>, fitting::Circle2>> CircleCoordinates(
    const FittedFeature& f, std::span<const Eigen::Vector3d> points_datum) {
  if (const auto* c2 = f.As<fitting::Circle2>()) {
    if (f.kind == FeatureKind::kPitchCircle) return std::make_pair(f.member_centers_mm, c2->feature);
    std::vector<Eigen::Vector2d> uv;
    uv.reserve(points_datum.size());
    for (const auto& p : points_datum) uv.push_back(InPlane(p, f.projection));
    return std::make_pair(std::move(uv), c2->feature);
  }
  if (const auto* c3 = f.As<fitting::Circle3>()) {
    const Eigen::Vector3d a = c3->feature.axis;
    Eigen::Vector3d u = Eigen::Vector3d::UnitX() - a * a.x();
    if (u.norm() < 1e-3) u = Eigen::Vector3d::UnitY() - a * a.y();
    u.normalize();
    const Eigen::Vector3d v = a.cross(u);
    std::vector<Eigen::Vector2d> uv;
    uv.reserve(points_datum.size());
    for (const auto& p : points_datum) {
      const Eigen::Vector3d d = p - c3->feature.center_mm;
      uv.emplace_back(u.dot(d), v.dot(d));
    }
    return std::make_pair(std::move(uv), fitting::Circle2{Eigen::Vector2d::Zero(), c3->feature.radius_mm});
  }
  return Status(StatusCode::kInvalidArgument, "feature '" + f.name + "' is not a circle");
}

Result<FittedFeature> FitFeature(const FeatureSpec& spec, std::span<const Eigen::Vector3d> pts,
                                 std::vector<std::size_t> indices, std::size_t first_line,
                                 const fitting::FitOptions& options) {
  FittedFeature f;
  f.name = spec.name;
  f.kind = spec.kind;
  f.projection = spec.projection;
  f.criterion = spec.form_criterion;
  f.point_indices = std::move(indices);
  f.first_line = first_line;
  const std::string what = Describe(spec, pts.size());
  if (pts.size() < MinPoints(spec.kind))
    return Status(StatusCode::kTooFewPoints, what + ": a " + FeatureKindName(spec.kind) + " fit needs at least " +
                                                 std::to_string(MinPoints(spec.kind)) + " points");
  auto fail = [&](const Status& s) { return s.WithContext(what); };
  std::vector<Eigen::Vector2d> uv;  // in-plane coordinates for 2D fits and circle profiles

  switch (spec.kind) {
    case FeatureKind::kLine2: {
      uv = Project(pts, spec.projection, &f.height_mm);
      auto r = fitting::FitLine2(uv, options);
      if (!r.ok()) return fail(r.status());
      if (spec.nominal_direction) {
        const Eigen::Vector2d s = ProjectDirection(*spec.nominal_direction, spec.projection);
        if (r->feature.direction.dot(s) < 0) {
          r->feature.direction = -r->feature.direction;
          for (double& res : r->residuals_mm) res = -res;  // left of the direction flips side
          r->message += (r->message.empty() ? "" : "; ") + std::string("direction flipped to nominal_direction");
        }
      }
      f.form_ls_mm = LsStraightness2(uv, r->feature);
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kLine3: {
      auto r = fitting::FitLine3(pts, options);
      if (!r.ok()) return fail(r.status());
      if (spec.nominal_direction && r->feature.direction.dot(*spec.nominal_direction) < 0) {
        r->feature.direction = -r->feature.direction;
        r->message += (r->message.empty() ? "" : "; ") + std::string("direction flipped to nominal_direction");
      }
      f.form_ls_mm = LsStraightness3(pts, r->feature);
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kPlane: {
      auto r = FitOriented<fitting::Plane>(
          spec, [&](std::optional<Eigen::Vector3d> hint) { return fitting::FitPlane(pts, options, hint); },
          [](const fitting::Plane& p) { return p.normal; });
      if (!r.ok()) return fail(r.status());
      f.form_ls_mm = LsFlatness(pts, r->feature);
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kCircle: {
      if (spec.projection != Projection::kNone) {
        uv = Project(pts, spec.projection, &f.height_mm);
        auto r = fitting::FitCircle2(uv, options);
        if (!r.ok()) return fail(r.status());
        f.form_ls_mm = ProfileRange(CircularityProfile(uv, r->feature));
        f.fit = std::move(*r);
      } else {
        auto r = FitOriented<fitting::Circle3>(
            spec, [&](std::optional<Eigen::Vector3d> hint) { return fitting::FitCircle3(pts, options, hint); },
            [](const fitting::Circle3& c) { return c.axis; });
        if (!r.ok()) return fail(r.status());
        f.fit = std::move(*r);
        auto coords = CircleCoordinates(f, pts);
        if (!coords.ok()) return fail(coords.status());
        uv = std::move(coords->first);
        f.form_ls_mm = ProfileRange(CircularityProfile(uv, coords->second));
      }
      break;
    }
    case FeatureKind::kCylinder: {
      auto r = FitOriented<fitting::Cylinder>(
          spec, [&](std::optional<Eigen::Vector3d> hint) { return fitting::FitCylinder(pts, options, hint); },
          [](const fitting::Cylinder& c) { return c.axis; });
      if (!r.ok()) return fail(r.status());
      f.form_ls_mm = r->stats.form_mm;
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kCone: {
      auto r = fitting::FitCone(pts, options);
      if (!r.ok()) return fail(r.status());
      f.form_ls_mm = r->stats.form_mm;
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kSphere: {
      auto r = fitting::FitSphere(pts, options);
      if (!r.ok()) return fail(r.status());
      f.form_ls_mm = r->stats.form_mm;
      f.fit = std::move(*r);
      break;
    }
    case FeatureKind::kPoint: {
      fitting::FitResult<PointFeature> r;
      for (const auto& p : pts) r.feature.point_mm += p;
      r.feature.point_mm /= static_cast<double>(pts.size());
      r.n_points = pts.size();
      double sum2 = 0.0;
      for (const auto& p : pts) {
        const double d = (p - r.feature.point_mm).norm();
        r.residuals_mm.push_back(d);
        sum2 += d * d;
        r.stats.max_mm = std::max(r.stats.max_mm, d);
      }
      r.stats.rms_mm = std::sqrt(sum2 / static_cast<double>(pts.size()));
      r.message = "centroid of the points; residuals are distances from it";
      f.fit = std::move(r);
      break;
    }
    case FeatureKind::kPitchCircle:
      return Status(StatusCode::kInvalidArgument, what + ": a pitch circle is fitted from its members");
  }
  TPCAL_RETURN_IF_ERROR(FillMinimumZone(spec, &f, pts, uv));
  return f;
}

Result<FittedFeature> FitPitchCircle(const FeatureSpec& spec, std::span<const FittedFeature* const> members,
                                     const fitting::FitOptions& options) {
  FittedFeature f;
  f.name = spec.name;
  f.kind = spec.kind;
  f.projection = spec.projection;
  f.criterion = spec.form_criterion;
  const std::string what = "pitch circle '" + spec.name + "' (" + std::to_string(members.size()) + " members)";
  double h = 0.0;
  for (const FittedFeature* m : members) {
    auto c = CenterOf(*m);
    if (!c.ok()) return c.status().WithContext(what);
    f.members.push_back(m->name);
    f.member_centers_mm.push_back(InPlane(*c, spec.projection));
    h += AlongNormal(*c, spec.projection);
    if (f.first_line == 0 || (m->first_line != 0 && m->first_line < f.first_line)) f.first_line = m->first_line;
  }
  if (members.size() < MinPoints(FeatureKind::kPitchCircle))
    return Status(StatusCode::kTooFewPoints, what + ": a pitch circle needs at least 3 members");
  f.height_mm = h / static_cast<double>(members.size());
  auto r = fitting::FitCircle2(f.member_centers_mm, options);
  if (!r.ok()) return r.status().WithContext(what);
  f.form_ls_mm = ProfileRange(CircularityProfile(f.member_centers_mm, r->feature));
  f.fit = std::move(*r);
  TPCAL_RETURN_IF_ERROR(FillMinimumZone(spec, &f, {}, f.member_centers_mm));
  return f;
}

Result<Eigen::Vector3d> CenterOf(const FittedFeature& f) {
  if (const auto* c2 = f.As<fitting::Circle2>()) return FromPlane(c2->feature.center_mm, f.height_mm, f.projection);
  if (const auto* c3 = f.As<fitting::Circle3>()) return c3->feature.center_mm;
  if (const auto* s = f.As<fitting::Sphere>()) return s->feature.center_mm;
  if (const auto* p = f.As<PointFeature>()) return p->feature.point_mm;
  if (const auto* c = f.As<fitting::Cylinder>()) return c->feature.point_mm;
  return Status(StatusCode::kInvalidArgument,
                "feature '" + f.name + "' (" + FeatureKindName(f.kind) + ") has no centre point");
}

Result<Eigen::Vector2d> CenterInPlane(const FittedFeature& f, Projection plane) {
  if (const auto* c2 = f.As<fitting::Circle2>()) {
    if (f.projection == plane) return c2->feature.center_mm;
  }
  auto c = CenterOf(f);
  if (!c.ok()) return c.status();
  return InPlane(*c, plane);
}

Result<Eigen::Vector3d> DirectionOf(const FittedFeature& f) {
  if (const auto* p = f.As<fitting::Plane>()) return p->feature.normal;
  if (const auto* l = f.As<fitting::Line3>()) return l->feature.direction;
  if (const auto* c = f.As<fitting::Cylinder>()) return c->feature.axis;
  return Status(StatusCode::kInvalidArgument,
                "feature '" + f.name + "' (" + FeatureKindName(f.kind) + ") has no direction");
}

Result<double> RadiusOf(const FittedFeature& f) {
  if (const auto* c2 = f.As<fitting::Circle2>()) return c2->feature.radius_mm;
  if (const auto* c3 = f.As<fitting::Circle3>()) return c3->feature.radius_mm;
  if (const auto* s = f.As<fitting::Sphere>()) return s->feature.radius_mm;
  if (const auto* c = f.As<fitting::Cylinder>()) return c->feature.radius_mm;
  return Status(StatusCode::kInvalidArgument, "feature '" + f.name + "' (" + FeatureKindName(f.kind) +
                                                  ") has no radius");
}

}  // namespace tpcal::gdt
