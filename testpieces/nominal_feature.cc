#include "testpieces/nominal_feature.h"

#include <cmath>
#include <limits>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

constexpr double kUnitTol = 1e-9;  // unit-vector and orthogonality checks (double precision)

double WrapTwoPi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a;
}

double Cross2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Signed distance of q inside a convex CCW polygon (positive inside): min over edges.
double InsideDistance(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& q) {
  double d = std::numeric_limits<double>::infinity();
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % n];
    const Eigen::Vector2d e = (b - a).normalized();
    d = std::min(d, Cross2d(e, q - a));
  }
  return d;
}

Status CheckConvexCcw(const std::vector<Eigen::Vector2d>& poly, const std::string& what) {
  if (poly.size() < 3) return {StatusCode::kInvalidArgument, what + ": a polygon needs at least 3 vertices"};
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e1 = poly[(i + 1) % n] - poly[i];
    const Eigen::Vector2d e2 = poly[(i + 2) % n] - poly[(i + 1) % n];
    if (Cross2d(e1, e2) <= 0) {
      return {StatusCode::kInvalidArgument, what + ": polygon is not convex and counter-clockwise at vertex " +
                                                std::to_string((i + 1) % n)};
    }
  }
  return Status::Ok();
}

}  // namespace

const char* SurfaceTypeName(SurfaceType t) {
  switch (t) {
    case SurfaceType::kPlane: return "plane";
    case SurfaceType::kCylinder: return "cylinder";
    case SurfaceType::kCone: return "cone";
  }
  return "?";
}

Status ValidateFeature(const NominalFeature& f) {
  const std::string what = "feature " + f.name;
  if (f.name.empty()) return {StatusCode::kInvalidArgument, "feature without a name"};
  if (std::abs(f.axis.norm() - 1.0) > kUnitTol || std::abs(f.ref_dir.norm() - 1.0) > kUnitTol) {
    return {StatusCode::kInvalidArgument, what + ": axis and ref_dir must be unit vectors"};
  }
  if (std::abs(f.axis.dot(f.ref_dir)) > kUnitTol) {
    return {StatusCode::kInvalidArgument, what + ": ref_dir must be perpendicular to the axis"};
  }
  switch (f.type) {
    case SurfaceType::kPlane:
      if (f.polygon_uv_mm.empty()) {
        if (!(f.r_max_mm > f.r_min_mm) || f.r_min_mm < 0) {
          return {StatusCode::kInvalidArgument, what + ": annulus needs 0 <= r_min < r_max"};
        }
      } else {
        TPCAL_RETURN_IF_ERROR(CheckConvexCcw(f.polygon_uv_mm, what));
        if (!f.hole_uv_mm.empty()) TPCAL_RETURN_IF_ERROR(CheckConvexCcw(f.hole_uv_mm, what + " hole"));
      }
      break;
    case SurfaceType::kCone:
      if (!(f.half_angle_rad > 0 && f.half_angle_rad < kPi / 2)) {
        return {StatusCode::kInvalidArgument, what + ": cone half angle must be in (0, 90) deg"};
      }
      [[fallthrough]];
    case SurfaceType::kCylinder:
      if (!(f.radius_mm > 0)) return {StatusCode::kInvalidArgument, what + ": radius must be > 0"};
      if (!(f.h_max_mm > f.h_min_mm)) return {StatusCode::kInvalidArgument, what + ": needs h_min < h_max"};
      if (f.type == SurfaceType::kCone && !(f.radius_mm - f.h_max_mm * std::tan(f.half_angle_rad) > 0)) {
        return {StatusCode::kInvalidArgument, what + ": cone apex inside the band"};
      }
      break;
  }
  if (!(f.level_max_mm >= f.level_min_mm)) {
    return {StatusCode::kInvalidArgument, what + ": probing band needs level_min <= level_max"};
  }
  return Status::Ok();
}

Eigen::Vector3d PointAt(const NominalFeature& f, const SurfaceCoords& c) {
  switch (f.type) {
    case SurfaceType::kPlane:
      return f.origin_mm + c.s1 * f.ref_dir + c.s2 * f.v_dir();
    case SurfaceType::kCylinder:
    case SurfaceType::kCone: {
      const double r = f.type == SurfaceType::kCylinder ? f.radius_mm
                                                        : f.radius_mm - c.s2 * std::tan(f.half_angle_rad);
      const Eigen::Vector3d er = std::cos(c.s1) * f.ref_dir + std::sin(c.s1) * f.v_dir();
      return f.origin_mm + c.s2 * f.axis + r * er;
    }
  }
  return f.origin_mm;
}

Eigen::Vector3d NormalAt(const NominalFeature& f, const SurfaceCoords& c) {
  switch (f.type) {
    case SurfaceType::kPlane:
      return f.axis;
    case SurfaceType::kCylinder: {
      const Eigen::Vector3d er = std::cos(c.s1) * f.ref_dir + std::sin(c.s1) * f.v_dir();
      return f.internal ? Eigen::Vector3d(-er) : er;
    }
    case SurfaceType::kCone: {
      const Eigen::Vector3d er = std::cos(c.s1) * f.ref_dir + std::sin(c.s1) * f.v_dir();
      // Outward normal of a cone narrowing toward +axis: radial tilted toward +axis.
      return std::cos(f.half_angle_rad) * er + std::sin(f.half_angle_rad) * f.axis;
    }
  }
  return f.axis;
}

bool InPlanePatch(const NominalFeature& f, const Eigen::Vector2d& uv, double margin_mm) {
  if (f.polygon_uv_mm.empty()) {
    const double r = uv.norm();
    return r >= f.r_min_mm + margin_mm && r <= f.r_max_mm - margin_mm;
  }
  if (InsideDistance(f.polygon_uv_mm, uv) < margin_mm) return false;
  if (!f.hole_uv_mm.empty() && InsideDistance(f.hole_uv_mm, uv) > -margin_mm) return false;
  return true;
}

Result<Projection> ProjectOnto(const NominalFeature& f, const Eigen::Vector3d& p) {
  Projection out;
  const Eigen::Vector3d d = p - f.origin_mm;
  const Eigen::Vector3d v = f.v_dir();
  switch (f.type) {
    case SurfaceType::kPlane: {
      out.coords = {d.dot(f.ref_dir), d.dot(v)};
      out.point_mm = PointAt(f, out.coords);
      out.normal = f.axis;
      out.signed_distance_mm = d.dot(f.axis);
      out.in_patch = InPlanePatch(f, {out.coords.s1, out.coords.s2});
      return out;
    }
    case SurfaceType::kCylinder:
    case SurfaceType::kCone: {
      const double h_point = d.dot(f.axis);
      const Eigen::Vector3d radial = d - h_point * f.axis;
      const double rho = radial.norm();
      if (rho < 1e-9) {
        return Status(StatusCode::kDegenerate, "feature " + f.name + ": point on the axis, azimuth undefined");
      }
      const double theta = WrapTwoPi(std::atan2(radial.dot(v), radial.dot(f.ref_dir)));
      double h = h_point;
      if (f.type == SurfaceType::kCone) {
        // Project along the cone normal in the (radial, axis) half plane: the generatrix through
        // (r0, 0) with direction (-sin a, cos a); foot parameter s.
        const double a = f.half_angle_rad;
        const Eigen::Vector2d q(rho - f.radius_mm, h_point);
        const Eigen::Vector2d g(-std::sin(a), std::cos(a));
        const double s = q.dot(g);
        h = s * std::cos(a);
      }
      out.coords = {theta, h};
      out.point_mm = PointAt(f, out.coords);
      out.normal = NormalAt(f, out.coords);
      out.signed_distance_mm = (p - out.point_mm).dot(out.normal);
      out.in_patch = h >= f.h_min_mm && h <= f.h_max_mm;
      return out;
    }
  }
  return Status(StatusCode::kInternal, "unknown surface type");
}

const NominalFeature* FindFeature(const std::vector<NominalFeature>& features, const std::string& name) {
  for (const auto& f : features) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

}  // namespace tpcal::testpieces
