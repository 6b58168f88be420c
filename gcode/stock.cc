#include "gcode/stock.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace tpcal::gcode {
namespace {

using testpieces::NominalFeature;
using testpieces::SurfaceType;

// Lower bound of the distance to a convex polygon (CCW): max over edges of the signed distance
// to the edge line (exact inside).
double PolygonDistance(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& q) {
  double d = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    const Eigen::Vector2d e = (b - a).normalized();
    const Eigen::Vector2d outward(e.y(), -e.x());
    d = std::max(d, (q - a).dot(outward));
  }
  return d;
}

StockPrimitive Cylinder(const std::string& name, double radius, double z0, double z1,
                        const Eigen::Vector2d& c = Eigen::Vector2d::Zero()) {
  StockPrimitive s;
  s.kind = StockPrimitive::Kind::kCylinder;
  s.name = name;
  s.center_xy_mm = c;
  s.radius_mm = radius;
  s.z_min_mm = z0;
  s.z_max_mm = z1;
  return s;
}

StockPrimitive Prism(const std::string& name, std::vector<Eigen::Vector2d> poly, double z0, double z1) {
  StockPrimitive s;
  s.kind = StockPrimitive::Kind::kPrism;
  s.name = name;
  s.polygon_xy_mm = std::move(poly);
  s.z_min_mm = z0;
  s.z_max_mm = z1;
  return s;
}

std::vector<Eigen::Vector2d> Square(double half) {
  return {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
}

// Convex polygon of a layer from its straight side faces (each face: origin at the middle of
// its bottom edge, ref_dir along the edge, polygon_uv from -half to +half).
std::vector<Eigen::Vector2d> LayerPolygon(const std::vector<const NominalFeature*>& faces) {
  std::vector<Eigen::Vector2d> pts;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const NominalFeature* f : faces) {
    const double half = f->polygon_uv_mm[1].x();
    const Eigen::Vector3d a = f->origin_mm - half * f->ref_dir;
    pts.emplace_back(a.x(), a.y());
    c += pts.back();
  }
  c /= static_cast<double>(pts.size());
  std::sort(pts.begin(), pts.end(), [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    return std::atan2(p.y() - c.y(), p.x() - c.x()) < std::atan2(q.y() - c.y(), q.x() - c.x());
  });
  return pts;
}

void Grow(StockEnvelope* env, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  env->min_mm = env->min_mm.cwiseMin(lo);
  env->max_mm = env->max_mm.cwiseMax(hi);
}

void Bounds(StockEnvelope* env) {
  const double inf = std::numeric_limits<double>::infinity();
  env->min_mm = Eigen::Vector3d::Constant(inf);
  env->max_mm = Eigen::Vector3d::Constant(-inf);
  for (const StockPrimitive& s : env->solids) {
    switch (s.kind) {
      case StockPrimitive::Kind::kPrism:
        for (const auto& v : s.polygon_xy_mm) Grow(env, {v.x(), v.y(), s.z_min_mm}, {v.x(), v.y(), s.z_max_mm});
        break;
      case StockPrimitive::Kind::kCylinder:
        Grow(env, {s.center_xy_mm.x() - s.radius_mm, s.center_xy_mm.y() - s.radius_mm, s.z_min_mm},
             {s.center_xy_mm.x() + s.radius_mm, s.center_xy_mm.y() + s.radius_mm, s.z_max_mm});
        break;
      case StockPrimitive::Kind::kFrustum: {
        // Bounding box of the two end circles.
        for (double h : {s.h_min_mm, s.h_max_mm}) {
          const double r = s.radius_mm - h * std::tan(s.half_angle_rad);
          const Eigen::Vector3d c = s.origin_mm + h * s.axis;
          Eigen::Vector3d ext;
          for (int i = 0; i < 3; ++i) ext[i] = r * std::sqrt(std::max(0.0, 1.0 - s.axis[i] * s.axis[i]));
          Grow(env, c - ext, c + ext);
        }
        break;
      }
    }
  }
}

Result<StockEnvelope> TurningStock(const testpieces::TestPiece& piece) {
  const auto& p = std::get<testpieces::TurningPieceParams>(piece.config.params);
  StockEnvelope env;
  const double doc = p.turning_depth_of_cut_mm;
  for (int i = 0; i < 6; ++i) {
    const double top = i == 0 ? p.top_z_mm() : p.steps[i - 1].shoulder_z_mm + doc;
    env.solids.push_back(Cylinder("raw section S" + std::to_string(i + 1) + " (r + depth of cut)",
                                  p.steps[i].radius_mm + doc, p.base_bottom_z_mm, top));
  }
  env.solids.push_back(Cylinder("base flange", p.base_radius_mm, p.base_bottom_z_mm, p.steps[5].shoulder_z_mm + doc));
  // Groove (walls with their finishing stock), holes and the bore.
  const double stock = p.groove_finish_stock_mm;
  StockPrimitive groove = Cylinder("groove", p.groove_outer_radius_mm - stock, p.groove_bottom_z_mm, p.top_z_mm() + 1.0);
  groove.inner_radius_mm = p.groove_inner_radius_mm + (p.groove_inner_wall_pass ? stock : 0.0);
  env.voids.push_back(groove);
  for (const NominalFeature& f : piece.features) {
    if (f.hole) env.voids.push_back(Cylinder("hole " + f.name, f.radius_mm, f.h_min_mm, f.h_max_mm + 1.0, f.origin_mm.head<2>()));
  }
  if (p.bore_radius_mm > 0) {
    env.voids.push_back(Cylinder("bore", p.bore_radius_mm, p.base_bottom_z_mm - 1.0, p.bore_top_z_mm));
  }
  Bounds(&env);
  return env;
}

Result<StockEnvelope> ContourStock(const testpieces::TestPiece& piece) {
  StockEnvelope env;
  const NominalFeature* floor = piece.Feature("FLOOR");
  if (!floor) return Status(StatusCode::kInvalidArgument, "M1 stock: no FLOOR feature");
  env.solids.push_back(Prism("base plate", floor->polygon_uv_mm, 0.0, floor->origin_mm.z()));
  std::map<std::pair<long long, long long>, std::vector<const NominalFeature*>> layers;
  for (const NominalFeature& f : piece.features) {
    if (f.type == SurfaceType::kPlane && f.pattern == testpieces::ProbePattern::kLines) {
      const double z0 = f.origin_mm.z(), z1 = z0 + f.polygon_uv_mm[2].y();
      layers[{std::llround(z0 * 1e6), std::llround(z1 * 1e6)}].push_back(&f);
    }
  }
  for (const auto& [z, faces] : layers) {
    env.solids.push_back(Prism("layer of " + faces.front()->name, LayerPolygon(faces), z.first * 1e-6, z.second * 1e-6));
  }
  for (const NominalFeature& f : piece.features) {
    if (f.type != SurfaceType::kCylinder) continue;
    if (f.internal) {
      env.voids.push_back(Cylinder(f.name, f.radius_mm, f.h_min_mm, f.h_max_mm + 1.0, f.origin_mm.head<2>()));
    } else {
      env.solids.push_back(Cylinder(f.name, f.radius_mm, f.h_min_mm, f.h_max_mm, f.origin_mm.head<2>()));
    }
  }
  Bounds(&env);
  return env;
}

Result<StockEnvelope> FaceMillingStock(const testpieces::TestPiece& piece) {
  StockEnvelope env;
  for (const NominalFeature& f : piece.features) {
    std::vector<Eigen::Vector2d> poly;
    for (const auto& uv : f.polygon_uv_mm) {
      const Eigen::Vector3d q = f.origin_mm + uv.x() * f.ref_dir + uv.y() * f.v_dir();
      poly.emplace_back(q.x(), q.y());
    }
    env.solids.push_back(Prism("block under " + f.name, poly, 0.0, f.origin_mm.z()));
  }
  Bounds(&env);
  return env;
}

Result<StockEnvelope> ConeStock(const testpieces::TestPiece& piece) {
  const auto& p = std::get<testpieces::ConeFrustumParams>(piece.config.params);
  StockEnvelope env;
  env.solids.push_back(Prism("base plate", Square(0.5 * p.base_size_mm), 0.0, p.base_thickness_mm));
  if (piece.features.empty()) return Status(StatusCode::kInvalidArgument, "cone stock: no cone feature");
  // The cone, and the second cone of the enriched piece (its first section CONE2_1).
  std::vector<const NominalFeature*> cones{&piece.features.front()};
  if (const NominalFeature* second = piece.Feature("CONE2_1")) cones.push_back(second);
  if (const NominalFeature* third = piece.Feature("CONE3_1")) cones.push_back(third);
  for (const NominalFeature* fp : cones) {
    const NominalFeature& f = *fp;
    StockPrimitive cone;
    cone.kind = StockPrimitive::Kind::kFrustum;
    cone.name = fp == cones.front() ? "cone frustum" : fp == cones[1] ? "second cone frustum" : "third cone frustum";
    cone.origin_mm = f.origin_mm;
    cone.axis = f.axis;
    cone.radius_mm = f.radius_mm;
    cone.half_angle_rad = f.half_angle_rad;
    // The tilted cone starts below the base top on one side: extend it into the plate.
    cone.h_min_mm = -f.radius_mm * std::tan(std::acos(std::clamp(f.axis.z(), -1.0, 1.0))) - 1.0;
    cone.h_max_mm = p.height_mm;
    env.solids.push_back(cone);
  }
  Bounds(&env);
  return env;
}

}  // namespace

double StockPrimitive::SignedDistance(const Eigen::Vector3d& p) const {
  switch (kind) {
    case Kind::kPrism:
      return std::max({PolygonDistance(polygon_xy_mm, p.head<2>()), z_min_mm - p.z(), p.z() - z_max_mm});
    case Kind::kCylinder: {
      const double rho = (p.head<2>() - center_xy_mm).norm();
      const double outer = std::max({rho - radius_mm, z_min_mm - p.z(), p.z() - z_max_mm});
      return inner_radius_mm > 0 ? std::max(outer, inner_radius_mm - rho) : outer;
    }
    case Kind::kFrustum: {
      const Eigen::Vector3d d = p - origin_mm;
      const double h = d.dot(axis);
      const double rho = (d - h * axis).norm();
      const double t = std::tan(half_angle_rad);
      // Trapezoid in (rho, h): rho <= r0 - h t, h in [h_min, h_max].
      const double side = (rho - (radius_mm - h * t)) * std::cos(half_angle_rad);
      return std::max({side, h_min_mm - h, h - h_max_mm});
    }
  }
  return 0.0;
}

double StockEnvelope::SignedDistance(const Eigen::Vector3d& p, std::string* nearest) const {
  double d = std::numeric_limits<double>::infinity();
  const StockPrimitive* best = nullptr;
  for (const StockPrimitive& s : solids) {
    const double di = s.SignedDistance(p);
    if (di < d) {
      d = di;
      best = &s;
    }
  }
  for (const StockPrimitive& v : voids) {
    const double dv = -v.SignedDistance(p);
    if (dv > d) {
      d = dv;
      best = &v;
    }
  }
  if (nearest) *nearest = best ? best->name : "";
  return d;
}

Result<StockEnvelope> StockOf(const testpieces::TestPiece& piece) {
  switch (piece.kind()) {
    case testpieces::PieceKind::kTurning: return TurningStock(piece);
    case testpieces::PieceKind::kContourM1: return ContourStock(piece);
    case testpieces::PieceKind::kFaceMillingM2: return FaceMillingStock(piece);
    case testpieces::PieceKind::kConeFrustum: return ConeStock(piece);
  }
  return Status(StatusCode::kInternal, "unknown piece kind");
}

}  // namespace tpcal::gcode
