#include "gdt/synthetic.h"

#include <cmath>

#include "core/units.h"

namespace tpcal::gdt {
namespace {

constexpr std::size_t kFirstDataLine = 4;

void Push(PointSet* ps, const std::string& feature, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  const bool keep_normals = ps->has_normals() || ps->empty();
  const std::size_t line = ps->line.empty() ? kFirstDataLine : ps->line.back() + 1;
  ps->xyz_mm.push_back(p);
  if (keep_normals) ps->normal.push_back(n.normalized());
  ps->feature.push_back(ps->InternFeature(feature));
  ps->line.push_back(line);
}

}  // namespace

void InPlaneAxes(const Eigen::Vector3d& axis, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - axis * axis.x();
  if (x.norm() < 1e-3) x = Eigen::Vector3d::UnitY() - axis * axis.y();
  *u = x.normalized();
  *v = axis.cross(*u);
}

void AppendCircle(PointSet* ps, const std::string& feature, const SyntheticCircle& c) {
  Eigen::Vector3d u, v;
  InPlaneAxes(c.axis, &u, &v);
  for (int k = 0; k < c.n_points; ++k) {
    const double theta = c.start_angle_rad + 2.0 * kPi * k / c.n_points;
    const Eigen::Vector3d radial = u * std::cos(theta) + v * std::sin(theta);
    const double r = c.radius_mm + (c.dr_mm ? c.dr_mm(theta) : 0.0);
    Push(ps, feature, c.center_mm + radial * r, c.hole ? Eigen::Vector3d(-radial) : radial);
  }
}

void AppendPlaneRing(PointSet* ps, const std::string& feature, const SyntheticPlaneRing& r) {
  Eigen::Vector3d u, v;
  InPlaneAxes(r.normal, &u, &v);
  for (int k = 0; k < r.n_points; ++k) {
    const double theta = r.start_angle_rad + 2.0 * kPi * k / r.n_points;
    const Eigen::Vector3d p = r.center_mm + (u * std::cos(theta) + v * std::sin(theta)) * r.radius_mm +
                              r.normal * (r.dz_mm ? r.dz_mm(theta) : 0.0);
    Push(ps, feature, p, r.normal);
  }
}

PointSet Transformed(const PointSet& ps, const Rigid3& t) {
  PointSet out = ps;
  for (auto& p : out.xyz_mm) p = t * p;
  for (auto& n : out.normal) n = t.linear() * n;
  return out;
}

Rigid3 RandomPlacement(std::mt19937_64& rng, double max_translation_mm) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(-max_translation_mm, max_translation_mm);
  // A normalised 4D Gaussian is a uniform unit quaternion. Draws are sequenced explicitly
  // (argument evaluation order is unspecified in C++).
  double g[4];
  for (double& x : g) x = gauss(rng);
  Eigen::Quaterniond q(g[0], g[1], g[2], g[3]);
  q.normalize();
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) t(i) = uni(rng);
  return MakeRigid(q.toRotationMatrix(), t);
}

}  // namespace tpcal::gdt
