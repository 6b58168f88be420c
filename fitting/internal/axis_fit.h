// Internal to tpcal::fitting: least-squares cylinder and cone, shared by cylinder_fit.cc and
// cone_fit.cc.
//
// Local minimal parametrisation. The state holds an axis frame (u, v, a) and a point on the
// axis, kept at the foot of the data centroid; a Levenberg-Marquardt step is (offset_u,
// offset_v, tilt_u, tilt_v, radius[, half_angle]): the point moves in the (u, v) plane, the
// direction tilts toward u and v about that point, then the point is re-footed on the new
// axis. The Jacobian is taken at step zero, so the covariance is in the frame of the result.
//
// Start without a hint (the hard part on short arcs): the surface's algebraic equation is
// linear in its coefficients once the axis direction W is fixed. For a cylinder,
// |P X|^2 = 2 C.(P X) + R^2 - |C|^2 with P = I - W W^T; for a cone the right side also has
// terms in w = W.X and w^2. So the algebraic residual of the best surface about W, E(W), is a
// small quadratic-form computation from one 10 x 10 matrix of moments up to order four (of a
// strided sample), and W can be searched exhaustively: E is scored on ~2000 directions of a
// Fibonacci hemisphere plus the data's three principal axes, the best distinct minima are
// polished by a pattern search, and each seeds a Levenberg-Marquardt run on the sample; the
// lowest geometric cost wins and is refined on all points. This does not rely on the
// principal axes, which on a 20 deg arc of a long cylinder put the axis in the middle
// eigenvector and on a short one in the largest: the direction of least curvature of the
// patch is what E finds.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/frames.h"
#include "core/status.h"
#include "core/units.h"
#include "fitting/fit_result.h"
#include "fitting/internal/accurate_sum.h"
#include "fitting/internal/hypersphere.h"
#include "fitting/internal/lm.h"

namespace tpcal::fitting::internal {

// An axis in scaled coordinates: frame columns (u, v, a), `point` on the axis.
struct Axis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  Eigen::Vector3d dir() const { return frame.col(2); }
};

// Axis through `through` with direction `dir`, its point the foot of the origin (0).
inline Axis MakeAxis(const Eigen::Vector3d& through, const Eigen::Vector3d& dir) {
  Axis ax;
  const Eigen::Vector3d a = dir.normalized();
  const Eigen::Vector3d u = AnyPerpendicular(a);
  ax.frame.col(0) = u;
  ax.frame.col(1) = a.cross(u);
  ax.frame.col(2) = a;
  ax.point = through - a.dot(through) * a;
  return ax;
}

// The same axis with the opposite direction; (u, v, a) stays right-handed.
inline Axis Reversed(const Axis& ax) {
  Axis r = ax;
  r.frame.col(1) = -ax.frame.col(1);
  r.frame.col(2) = -ax.frame.col(2);
  return r;
}

// Moves the point by (du, dv), tilts the direction toward (u, v) by (tu, tv) about it, and
// re-foots the point at the origin's foot; *shift = how far the point moved along the new axis.
inline Axis MoveAxis(const Axis& ax, double du, double dv, double tu, double tv, double* shift) {
  const Eigen::Vector3d u = ax.frame.col(0), v = ax.frame.col(1), a = ax.frame.col(2);
  const Eigen::Vector3d p = ax.point + du * u + dv * v;
  const Eigen::Vector3d a2 = (a + tu * u + tv * v).normalized();
  const Eigen::Matrix3d rot = Eigen::Quaterniond::FromTwoVectors(a, a2).toRotationMatrix();
  Eigen::Vector3d u2 = rot * u;
  u2 = (u2 - a2.dot(u2) * a2).normalized();
  Axis out;
  out.frame.col(0) = u2;
  out.frame.col(1) = a2.cross(u2);
  out.frame.col(2) = a2;
  *shift = -a2.dot(p);
  out.point = p + *shift * a2;
  return out;
}

// Shared data of both models: points, centring and scaling.
class AxisModelBase {
 public:
  AxisModelBase(std::span<const Eigen::Vector3d> points_mm, const Eigen::Vector3d& origin_mm, double scale_mm)
      : points_(points_mm), origin_(origin_mm), scale_(scale_mm), inv_scale_(1.0 / scale_mm) {}
  std::size_t num_residuals() const { return points_.size(); }
  double scale_mm() const { return scale_; }
  Eigen::Vector3d ToMm(const Eigen::Vector3d& q) const { return origin_ + q * scale_; }

 protected:
  // Local coordinates (along u, v, a) of point i relative to the axis point.
  Eigen::Vector3d Local(const Axis& ax, std::size_t i) const {
    return ax.frame.transpose() * ((points_[i] - origin_) * inv_scale_ - ax.point);
  }
  std::span<const Eigen::Vector3d> points_;
  Eigen::Vector3d origin_;
  double scale_;
  double inv_scale_;
};

class CylinderModel : public AxisModelBase {
 public:
  static constexpr int kParams = 5;  // offset_u, offset_v, tilt_u, tilt_v, radius
  using PVec = Eigen::Matrix<double, kParams, 1>;
  struct State {
    Axis axis;
    double radius;
  };
  using AxisModelBase::AxisModelBase;
  std::array<bool, kParams> param_is_length() const { return {true, true, false, false, true}; }

  Linearization<kParams> Linearize(const State& s, double* residuals_mm, Eigen::MatrixXd* jacobian) const {
    return LinearizeRows<kParams>(
        points_.size(),
        [&](std::size_t i, std::array<double, kParams>& j, double& r) {
          const Eigen::Vector3d l = Local(s.axis, i);
          const double rho = std::hypot(l.x(), l.y());
          r = rho - s.radius;
          const double cu = rho > 0.0 ? l.x() / rho : 0.0, cv = rho > 0.0 ? l.y() / rho : 0.0;
          j = {-cu, -cv, -l.z() * cu, -l.z() * cv, -1.0};
        },
        scale_, residuals_mm, jacobian, JacobianMmScale(*this));
  }

  State Retract(const State& s, const PVec& d) const {
    double shift;
    return {MoveAxis(s.axis, d[0], d[1], d[2], d[3], &shift), s.radius + d[4]};
  }
};

// Signed distance to the cone (rho - R) cos(psi) - w sin(psi) in the half-plane (w, rho)
// of each point: w along the axis from the axis point, R the radius there.
class ConeModel : public AxisModelBase {
 public:
  static constexpr int kParams = 6;  // offset_u, offset_v, tilt_u, tilt_v, radius, half_angle
  using PVec = Eigen::Matrix<double, kParams, 1>;
  struct State {
    Axis axis;
    double radius;      // at axis.point
    double half_angle;  // rad; may be negative during the fit (cone widening along -a)
  };
  using AxisModelBase::AxisModelBase;
  std::array<bool, kParams> param_is_length() const { return {true, true, false, false, true, false}; }

  Linearization<kParams> Linearize(const State& s, double* residuals_mm, Eigen::MatrixXd* jacobian) const {
    const double c = std::cos(s.half_angle), sn = std::sin(s.half_angle);
    return LinearizeRows<kParams>(
        points_.size(),
        [&](std::size_t i, std::array<double, kParams>& j, double& r) {
          const Eigen::Vector3d l = Local(s.axis, i);
          const double rho = std::hypot(l.x(), l.y());
          r = (rho - s.radius) * c - l.z() * sn;
          // d rho / d offset = -l_uv / rho; d rho / d tilt = -w l_uv / rho; d w / d tilt = l_uv.
          const double cu = rho > 0.0 ? l.x() / rho : 0.0, cv = rho > 0.0 ? l.y() / rho : 0.0;
          j = {-c * cu, -c * cv, -c * l.z() * cu - sn * l.x(), -c * l.z() * cv - sn * l.y(), -c,
               -(rho - s.radius) * sn - l.z() * c};
        },
        scale_, residuals_mm, jacobian, JacobianMmScale(*this));
  }

  State Retract(const State& s, const PVec& d) const {
    double shift;
    State out;
    out.axis = MoveAxis(s.axis, d[0], d[1], d[2], d[3], &shift);
    out.half_angle = s.half_angle + d[5];
    out.radius = s.radius + d[4] + shift * std::tan(out.half_angle);
    return out;
  }
};

// Moments of z = (1, x, y, z, xx, yy, zz, xy, xz, yz) of scaled points, and the algebraic
// residual E(W) of the best cylinder / cone about direction W (see the file comment).
class AxisDirectionScore {
 public:
  using ZVec = Eigen::Matrix<double, 10, 1>;
  explicit AxisDirectionScore(const Eigen::Matrix<double, 10, 10>& moments) : g_(moments) {}

  // E(W) and the regression coefficients (1, U.X, V.X) for the cylinder; (1, X, w^2) for the cone.
  double Cylinder(const Eigen::Vector3d& w, Eigen::VectorXd* beta = nullptr) const {
    const Eigen::Vector3d u = AnyPerpendicular(w), v = w.cross(u);
    Eigen::Matrix<double, 10, 3> r = Eigen::Matrix<double, 10, 3>::Zero();
    r(0, 0) = 1.0;
    r.block<3, 1>(1, 1) = u;
    r.block<3, 1>(1, 2) = v;
    return Residual(r, Target(w), beta);
  }
  double Cone(const Eigen::Vector3d& w, Eigen::VectorXd* beta = nullptr) const {
    Eigen::Matrix<double, 10, 5> r = Eigen::Matrix<double, 10, 5>::Zero();
    r(0, 0) = 1.0;
    r.block<3, 3>(1, 1).setIdentity();
    r.block<6, 1>(4, 4) << w.x() * w.x(), w.y() * w.y(), w.z() * w.z(), 2 * w.x() * w.y(), 2 * w.x() * w.z(),
        2 * w.y() * w.z();
    return Residual(r, Target(w), beta);
  }
  Eigen::Matrix3d Scatter() const {
    const Eigen::Vector3d m = g_.block<3, 1>(1, 0);
    return g_.block<3, 3>(1, 1) - m * m.transpose();
  }

 private:
  // |P X|^2 = |X|^2 - (W.X)^2 in the quadratic monomials.
  static ZVec Target(const Eigen::Vector3d& w) {
    ZVec t = ZVec::Zero();
    t.segment<6>(4) << 1 - w.x() * w.x(), 1 - w.y() * w.y(), 1 - w.z() * w.z(), -2 * w.x() * w.y(),
        -2 * w.x() * w.z(), -2 * w.y() * w.z();
    return t;
  }
  template <int K>
  double Residual(const Eigen::Matrix<double, 10, K>& r, const ZVec& t, Eigen::VectorXd* beta) const {
    const Eigen::Matrix<double, K, K> a = r.transpose() * g_ * r;
    const Eigen::Matrix<double, K, 1> b = r.transpose() * g_ * t;
    const Eigen::Matrix<double, K, 1> x = a.ldlt().solve(b);
    if (beta != nullptr) *beta = x;
    return std::max(0.0, t.dot(g_ * t) - b.dot(x));
  }
  Eigen::Matrix<double, 10, 10> g_;
};

// Moments for AxisDirectionScore over a strided sample of the scaled points.
template <typename ToScaled>
Eigen::Matrix<double, 10, 10> AxisMoments(std::size_t m, ToScaled&& scaled_point) {
  constexpr std::size_t kSums = 55;
  const auto s = BlockSums<kSums>(m, [&](std::size_t k) {
    const Eigen::Vector3d q = scaled_point(k);
    const std::array<double, 10> z = {1.0,           q.x(),         q.y(),         q.z(),         q.x() * q.x(),
                                      q.y() * q.y(), q.z() * q.z(), q.x() * q.y(), q.x() * q.z(), q.y() * q.z()};
    std::array<double, kSums> acc;
    std::size_t t = 0;
    for (int r = 0; r < 10; ++r) {
      for (int c = r; c < 10; ++c) acc[t++] = z[r] * z[c];
    }
    return acc;
  });
  Eigen::Matrix<double, 10, 10> g;
  std::size_t t = 0;
  for (int r = 0; r < 10; ++r) {
    for (int c = r; c < 10; ++c, ++t) g(r, c) = g(c, r) = s[t] / static_cast<double>(m);
  }
  return g;
}

// Up to `count` directions of low score, at least 10 deg apart, each polished by a
// pattern search down to 1e-6 rad (at most 300 moves). Candidates: a Fibonacci hemisphere and the principal axes.
template <typename Score>
std::vector<Eigen::Vector3d> BestDirections(Score&& score, const Eigen::Matrix3d& scatter, int count) {
  constexpr int kGrid = 2000;
  std::vector<std::pair<double, Eigen::Vector3d>> cand;
  cand.reserve(kGrid + 3);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < kGrid; ++i) {
    const double z = 1.0 - (i + 0.5) / kGrid;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d w(r * std::cos(golden * i), r * std::sin(golden * i), z);
    cand.emplace_back(score(w), w);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter);
  for (int k = 0; k < 3; ++k) cand.emplace_back(score(es.eigenvectors().col(k)), es.eigenvectors().col(k));
  std::sort(cand.begin(), cand.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> picked;
  const double min_sep = std::cos(kPi / 18.0);
  for (const auto& [e, w] : cand) {
    if (static_cast<int>(picked.size()) >= count) break;
    bool distinct = true;
    for (const auto& p : picked) distinct = distinct && std::abs(p.dot(w)) < min_sep;
    if (!distinct) continue;
    // Pattern search on the sphere around w.
    Eigen::Vector3d best = w;
    double best_e = e;
    // At most kMaxMoves moves: the score of a non-cylindrical set (e.g. a plane) can
    // decrease without bound toward a degenerate direction.
    constexpr int kMaxMoves = 300;
    int moves = 0;
    for (double step = 0.03; step > 1e-6 && moves < kMaxMoves; ++moves) {
      const Eigen::Vector3d t1 = AnyPerpendicular(best), t2 = best.cross(t1);
      bool improved = false;
      for (const Eigen::Vector3d& d : {t1, Eigen::Vector3d(-t1), t2, Eigen::Vector3d(-t2)}) {
        const Eigen::Vector3d trial = (best + step * d).normalized();
        const double te = score(trial);
        if (te < best_e) {
          best_e = te;
          best = trial;
          improved = true;
          break;
        }
      }
      if (!improved) step *= 0.5;
    }
    picked.push_back(best);
  }
  return picked;
}

// Centre (origin, mm) and power-of-two scale of the points; the strided sample's indices.
struct AxisFitSetup {
  Eigen::Vector3d origin_mm;
  double scale_mm = 1.0;
  std::size_t stride = 1;
  std::vector<Eigen::Vector3d> sample_mm;  // every stride-th point
  double extent = 0.0;                     // RMS distance of the points from the origin, scaled
};

inline Result<AxisFitSetup> SetUpAxisFit(std::span<const Eigen::Vector3d> points_mm, std::size_t min_points,
                                         const FitOptions& options, const std::string& what) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < min_points) {
    return Status(StatusCode::kTooFewPoints,
                  what + " needs at least " + std::to_string(min_points) + " points, got " + std::to_string(n));
  }
  AxisFitSetup s;
  const Eigen::Vector3d shift = points_mm[0];
  const auto sum = BlockSums<3>(n, [&](std::size_t i) {
    const Eigen::Vector3d d = points_mm[i] - shift;
    return std::array<double, 3>{d.x(), d.y(), d.z()};
  });
  s.origin_mm = shift + Eigen::Vector3d(sum[0], sum[1], sum[2]) / static_cast<double>(n);
  if (!s.origin_mm.allFinite()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!points_mm[i].allFinite()) {
        return Status(StatusCode::kInvalidArgument, what + ": point " + std::to_string(i) + " is not finite");
      }
    }
  }
  const auto ss = BlockSums<1>(n, [&](std::size_t i) {
    return std::array<double, 1>{(points_mm[i] - s.origin_mm).squaredNorm()};
  });
  const double rms = std::sqrt(ss[0] / static_cast<double>(n));
  if (!(rms > 0.0) || !std::isfinite(rms)) return Status(StatusCode::kDegenerate, what + ": all points coincide");
  s.scale_mm = PowerOfTwoNear(rms);
  s.stride = std::max<std::size_t>(1, n / kStartSample);
  for (std::size_t i = 0; i < n; i += s.stride) s.sample_mm.push_back(points_mm[i]);
  s.extent = rms / s.scale_mm;
  return s;
}

// Runs LM from each start on the sample, then from the best (lowest cost) on all points.
// Returns the run on all points, or the first error if every start fails.
template <typename Model>
Result<LmRun<Model>> BestOfStarts(std::span<const Eigen::Vector3d> points_mm, const AxisFitSetup& setup,
                                  const std::vector<typename Model::State>& starts, const FitOptions& options) {
  if (starts.empty()) return Status(StatusCode::kDegenerate, "no start found");
  const bool sampled = setup.stride > 1;
  const Model sample_model(setup.sample_mm, setup.origin_mm, setup.scale_mm);
  FitOptions sample_options = options;
  sample_options.keep_residuals = !sampled && options.keep_residuals;
  std::optional<LmRun<Model>> best;
  Status first_error;
  for (const auto& start : starts) {
    auto run = RunLm(sample_model, start, sample_options);
    if (!run.ok()) {
      if (first_error.ok()) first_error = run.status();
      continue;
    }
    if (!best || run->lin.cost < best->lin.cost) best = std::move(*run);
  }
  if (!best) return first_error;
  if (!sampled) return std::move(*best);
  const Model model(points_mm, setup.origin_mm, setup.scale_mm);
  return RunLm(model, best->state, options);
}

// Directions to start from: the hint, else the best minima of the algebraic score.
template <typename ScoreFn>
Result<std::vector<Eigen::Vector3d>> StartDirections(const AxisFitSetup& setup,
                                                     const std::optional<Eigen::Vector3d>& axis_hint,
                                                     const std::string& what, ScoreFn&& score_of) {
  if (axis_hint.has_value()) {
    if (!(axis_hint->allFinite() && axis_hint->norm() > 0.0)) {
      return Status(StatusCode::kInvalidArgument, what + ": axis_hint must be a finite non-zero vector");
    }
    return std::vector<Eigen::Vector3d>{axis_hint->normalized()};
  }
  const Eigen::Matrix<double, 10, 10> g = AxisMoments(setup.sample_mm.size(), [&](std::size_t k) -> Eigen::Vector3d {
    return (setup.sample_mm[k] - setup.origin_mm) / setup.scale_mm;
  });
  const AxisDirectionScore score(g);
  return BestDirections([&](const Eigen::Vector3d& w) { return score_of(score, w); }, score.Scatter(), 3);
}

// LS circle of the (scaled) sample projected along w: a cylinder start, or nullopt.
inline std::optional<CylinderModel::State> ProjectedCircleStart(const AxisFitSetup& setup, const Eigen::Vector3d& w) {
  const Eigen::Vector3d u = AnyPerpendicular(w), v = w.cross(u);
  std::vector<Eigen::Vector2d> proj(setup.sample_mm.size());
  for (std::size_t k = 0; k < proj.size(); ++k) {
    const Eigen::Vector3d q = (setup.sample_mm[k] - setup.origin_mm) / setup.scale_mm;
    proj[k] = Eigen::Vector2d(u.dot(q), v.dot(q));
  }
  FitOptions quiet;
  quiet.keep_residuals = false;
  quiet.compute_covariance = false;
  auto circle = FitHypersphere<2>(proj, quiet, "start");
  if (!circle.ok()) return std::nullopt;
  const Eigen::Vector3d c = circle->center_mm.x() * u + circle->center_mm.y() * v;
  return CylinderModel::State{MakeAxis(c, w), circle->radius_mm};
}

}  // namespace tpcal::fitting::internal
