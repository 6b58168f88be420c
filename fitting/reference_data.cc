#include "fitting/reference_data.h"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cmath>
#include <string>

#include "core/frames.h"

namespace tpcal::fitting {
namespace {

// Foot points on the feature, their unit normals (direction of a positive residual) and the
// Jacobian columns of the size parameters (radius, half angle), if any.
struct Feet {
  std::vector<Eigen::Vector3d> foot;
  std::vector<Eigen::Vector3d> normal;
  Eigen::MatrixXd size_columns;  // n x s
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // reference point of the rigid rotations
};

// J = [-n_i, -(f_i - o) x n_i, size columns]: rigid motions of the feature and its sizes.
Eigen::MatrixXd RigidAndSizeJacobian(const Feet& f) {
  const Eigen::Index n = static_cast<Eigen::Index>(f.foot.size());
  const Eigen::Index s = f.size_columns.cols();
  Eigen::MatrixXd j(n, 6 + s);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d& ni = f.normal[static_cast<std::size_t>(i)];
    j.row(i).head<3>() = -ni.transpose();
    j.row(i).segment<3>(3) = -(f.foot[static_cast<std::size_t>(i)] - f.origin).cross(ni).transpose();
  }
  if (s > 0) j.rightCols(s) = f.size_columns;
  return j;
}

// Points f_i + e_i n_i with certified deviations e.
std::vector<Eigen::Vector3d> Displace(const Feet& f, const Eigen::VectorXd& e) {
  std::vector<Eigen::Vector3d> p(f.foot.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = f.foot[i] + e[static_cast<Eigen::Index>(i)] * f.normal[i];
  return p;
}

std::vector<double> ToStd(const Eigen::VectorXd& e) { return {e.data(), e.data() + e.size()}; }

// Stratified position in [0, 1): one uniform draw inside slot k of n.
double Slot(std::size_t k, std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return (static_cast<double>(k) + u(rng)) / static_cast<double>(n);
}

double Uniform(double lo, double hi, std::mt19937_64& rng) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

Status NeedPoints(const ReferenceOptions& o, std::size_t min_points, const char* what) {
  TPCAL_RETURN_IF_ERROR(o.Validate());
  if (o.n_points < min_points) {
    return Status(StatusCode::kTooFewPoints, std::string(what) + " needs at least " + std::to_string(min_points) +
                                                 " points, got " + std::to_string(o.n_points));
  }
  return Status::Ok();
}

// Unit vectors (u, v) normal to unit a, with (u, v, a) right-handed; u = AnyPerpendicular(a).
void Perpendiculars(const Eigen::Vector3d& a, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  *u = AnyPerpendicular(a);
  *v = a.cross(*u);
}

Eigen::Vector3d Lift(const Eigen::Vector2d& p) { return {p.x(), p.y(), 0.0}; }

}  // namespace

Status ReferenceOptions::Validate() const {
  auto bad = [](const std::string& m) { return Status(StatusCode::kInvalidArgument, "ReferenceOptions." + m); };
  if (!(std::isfinite(deviation_rms_mm) && deviation_rms_mm >= 0.0)) return bad("deviation_rms_mm must be >= 0");
  if (!(std::isfinite(arc_rad) && arc_rad > 0.0 && arc_rad <= 2.0 * kPi)) return bad("arc_rad must be in (0, 2 pi]");
  if (!std::isfinite(arc_start_rad)) return bad("arc_start_rad must be finite");
  if (!(std::isfinite(length_mm) && length_mm > 0.0)) return bad("length_mm must be > 0");
  if (!(std::isfinite(width_mm) && width_mm > 0.0)) return bad("width_mm must be > 0");
  if (!(cap_axis.allFinite() && cap_axis.norm() > 0.0)) return bad("cap_axis must be a non-zero vector");
  return Status::Ok();
}

Eigen::VectorXd NullSpaceDeviations(const Eigen::MatrixXd& j, double rms_mm, std::mt19937_64& rng) {
  const Eigen::Index n = j.rows();
  Eigen::VectorXd e(n);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (Eigen::Index i = 0; i < n; ++i) e[i] = gauss(rng);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(j);
  const Eigen::Index rank = qr.rank();
  if (rank >= n || rms_mm == 0.0) return Eigen::VectorXd::Zero(n);
  // e - Q Q^T e: zero the components along the first `rank` Householder columns.
  Eigen::VectorXd y = qr.householderQ().transpose() * e;
  y.head(rank).setZero();
  e = qr.householderQ() * y;
  const double rms = std::sqrt(e.squaredNorm() / static_cast<double>(n));
  return e * (rms_mm / rms);
}

Result<ReferenceSet<Line2, Eigen::Vector2d>> MakeReferenceLine2(const Line2& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 2, "MakeReferenceLine2"));
  const Eigen::Vector2d left(-truth.direction.y(), truth.direction.x());
  Feet f;
  f.origin = Lift(truth.point_mm);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double s = o.length_mm * (Slot(k, o.n_points, rng) - 0.5);
    f.foot.push_back(Lift(truth.point_mm + s * truth.direction));
    f.normal.push_back(Lift(left));
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  ReferenceSet<Line2, Eigen::Vector2d> r{truth, {}, ToStd(e)};
  for (const auto& p : Displace(f, e)) r.points_mm.push_back(p.head<2>());
  return r;
}

Result<ReferenceSet<Line3, Eigen::Vector3d>> MakeReferenceLine3(const Line3& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 2, "MakeReferenceLine3"));
  Eigen::Vector3d u, v;
  Perpendiculars(truth.direction, &u, &v);
  // Two residual components per point, along u and v.
  const Eigen::Index n = static_cast<Eigen::Index>(o.n_points);
  Eigen::MatrixXd j(2 * n, 6);
  std::vector<Eigen::Vector3d> foot(o.n_points);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = o.length_mm * (Slot(static_cast<std::size_t>(i), o.n_points, rng) - 0.5);
    foot[static_cast<std::size_t>(i)] = truth.point_mm + s * truth.direction;
    const Eigen::Vector3d a = s * truth.direction;  // foot - origin
    j.row(2 * i) << -u.transpose(), -a.cross(u).transpose();
    j.row(2 * i + 1) << -v.transpose(), -a.cross(v).transpose();
  }
  const Eigen::VectorXd e = NullSpaceDeviations(j, o.deviation_rms_mm / std::sqrt(2.0), rng);  // per component
  ReferenceSet<Line3, Eigen::Vector3d> r{truth, {}, {}};
  for (Eigen::Index i = 0; i < n; ++i) {
    r.points_mm.push_back(foot[static_cast<std::size_t>(i)] + e[2 * i] * u + e[2 * i + 1] * v);
    r.residuals_mm.push_back(std::hypot(e[2 * i], e[2 * i + 1]));
  }
  return r;
}

Result<ReferenceSet<Plane, Eigen::Vector3d>> MakeReferencePlane(const Plane& truth, const ReferenceOptions& o,
                                                                std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 3, "MakeReferencePlane"));
  Eigen::Vector3d u, v;
  Perpendiculars(truth.normal, &u, &v);
  Feet f;
  f.origin = truth.point_mm;
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double a = o.length_mm * (Slot(k, o.n_points, rng) - 0.5);
    const double b = Uniform(-0.5, 0.5, rng) * o.width_mm;
    f.foot.push_back(truth.point_mm + a * u + b * v);
    f.normal.push_back(truth.normal);
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  return ReferenceSet<Plane, Eigen::Vector3d>{truth, Displace(f, e), ToStd(e)};
}

Result<ReferenceSet<Circle2, Eigen::Vector2d>> MakeReferenceCircle2(const Circle2& truth, const ReferenceOptions& o,
                                                                    std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 3, "MakeReferenceCircle2"));
  Feet f;
  f.origin = Lift(truth.center_mm);
  f.size_columns = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(o.n_points), 1, -1.0);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double t = o.arc_start_rad + o.arc_rad * Slot(k, o.n_points, rng);
    const Eigen::Vector3d radial(std::cos(t), std::sin(t), 0.0);
    f.foot.push_back(f.origin + truth.radius_mm * radial);
    f.normal.push_back(radial);
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  ReferenceSet<Circle2, Eigen::Vector2d> r{truth, {}, ToStd(e)};
  for (const auto& p : Displace(f, e)) r.points_mm.push_back(p.head<2>());
  return r;
}

Result<ReferenceSet<Circle3, Eigen::Vector3d>> MakeReferenceCircle3(const Circle3& truth, const ReferenceOptions& o,
                                                                    std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 3, "MakeReferenceCircle3"));
  Eigen::Vector3d u, v;
  Perpendiculars(truth.axis, &u, &v);
  Feet circle;
  circle.origin = truth.center_mm;
  circle.size_columns = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(o.n_points), 1, -1.0);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double t = o.arc_start_rad + o.arc_rad * Slot(k, o.n_points, rng);
    const Eigen::Vector3d radial = std::cos(t) * u + std::sin(t) * v;
    circle.foot.push_back(truth.center_mm + truth.radius_mm * radial);
    circle.normal.push_back(radial);
  }
  // In-plane radial deviations first; the plane's Jacobian then at the displaced points
  // (their in-plane positions are what the plane fit sees).
  const Eigen::VectorXd e_radial = NullSpaceDeviations(RigidAndSizeJacobian(circle), o.deviation_rms_mm, rng);
  Feet plane;
  plane.origin = truth.center_mm;
  plane.foot = Displace(circle, e_radial);
  plane.normal.assign(o.n_points, truth.axis);
  const Eigen::VectorXd e_axial = NullSpaceDeviations(RigidAndSizeJacobian(plane), o.deviation_rms_mm, rng);
  return ReferenceSet<Circle3, Eigen::Vector3d>{truth, Displace(plane, e_axial), ToStd(e_radial)};
}

Result<ReferenceSet<Sphere, Eigen::Vector3d>> MakeReferenceSphere(const Sphere& truth, const ReferenceOptions& o,
                                                                  std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 4, "MakeReferenceSphere"));
  if (o.arc_rad > kPi) {
    return Status(StatusCode::kInvalidArgument, "MakeReferenceSphere: arc_rad (cap half angle) must be <= pi");
  }
  const Eigen::Vector3d c = o.cap_axis.normalized();
  Eigen::Vector3d u, v;
  Perpendiculars(c, &u, &v);
  Feet f;
  f.origin = truth.center_mm;
  f.size_columns = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(o.n_points), 1, -1.0);
  const double cos_cap = std::cos(o.arc_rad);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    // Uniform on the cap: cos(polar angle) uniform in [cos(cap), 1].
    const double cz = 1.0 - (1.0 - cos_cap) * Slot(k, o.n_points, rng);
    const double sz = std::sqrt(std::max(0.0, 1.0 - cz * cz));
    const double phi = Uniform(0.0, 2.0 * kPi, rng);
    const Eigen::Vector3d n = sz * std::cos(phi) * u + sz * std::sin(phi) * v + cz * c;
    f.foot.push_back(truth.center_mm + truth.radius_mm * n);
    f.normal.push_back(n);
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  return ReferenceSet<Sphere, Eigen::Vector3d>{truth, Displace(f, e), ToStd(e)};
}

Result<ReferenceSet<Cylinder, Eigen::Vector3d>> MakeReferenceCylinder(const Cylinder& truth,
                                                                      const ReferenceOptions& o,
                                                                      std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 5, "MakeReferenceCylinder"));
  Eigen::Vector3d u, v;
  Perpendiculars(truth.axis, &u, &v);
  Feet f;
  f.origin = truth.point_mm;
  f.size_columns = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(o.n_points), 1, -1.0);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double t = o.arc_start_rad + o.arc_rad * Slot(k, o.n_points, rng);
    const double w = Uniform(-0.5, 0.5, rng) * o.length_mm;
    const Eigen::Vector3d radial = std::cos(t) * u + std::sin(t) * v;
    f.foot.push_back(truth.point_mm + w * truth.axis + truth.radius_mm * radial);
    f.normal.push_back(radial);
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  return ReferenceSet<Cylinder, Eigen::Vector3d>{truth, Displace(f, e), ToStd(e)};
}

Result<ReferenceSet<Cone, Eigen::Vector3d>> MakeReferenceCone(const Cone& truth, const ReferenceOptions& o,
                                                              std::mt19937_64& rng) {
  TPCAL_RETURN_IF_ERROR(NeedPoints(o, 6, "MakeReferenceCone"));
  const double tan_a = std::tan(truth.half_angle_rad);
  if (!(truth.radius_mm - 0.5 * o.length_mm * tan_a > 0.0)) {
    return Status(StatusCode::kInvalidArgument, "MakeReferenceCone: the apex lies inside length_mm");
  }
  Eigen::Vector3d u, v;
  Perpendiculars(truth.axis, &u, &v);
  const double ca = std::cos(truth.half_angle_rad), sa = std::sin(truth.half_angle_rad);
  Feet f;
  f.origin = truth.point_mm;
  f.size_columns.resize(static_cast<Eigen::Index>(o.n_points), 2);
  for (std::size_t k = 0; k < o.n_points; ++k) {
    const double t = o.arc_start_rad + o.arc_rad * Slot(k, o.n_points, rng);
    const double w = Uniform(-0.5, 0.5, rng) * o.length_mm;
    const Eigen::Vector3d radial = std::cos(t) * u + std::sin(t) * v;
    f.foot.push_back(truth.point_mm + w * truth.axis + (truth.radius_mm + w * tan_a) * radial);
    f.normal.push_back(ca * radial - sa * truth.axis);
    // Signed distance (rho - R) cos a - w sin a: d/dR = -cos a; d/da at a foot point = -w / cos a.
    f.size_columns.row(static_cast<Eigen::Index>(k)) << -ca, -w / ca;
  }
  const Eigen::VectorXd e = NullSpaceDeviations(RigidAndSizeJacobian(f), o.deviation_rms_mm, rng);
  return ReferenceSet<Cone, Eigen::Vector3d>{truth, Displace(f, e), ToStd(e)};
}

}  // namespace tpcal::fitting
