// Internal to tpcal::fitting: least-squares circle (D = 2) and sphere (D = 3), shared by
// FitCircle2, FitCircle3 and FitSphere.
//
// 1. Centre and scale: origin = centroid of a strided sample (at most kStartSample points),
//    scale = a power of two near their RMS distance (exact scaling), q = (p - origin)/scale.
// 2. Algebraic start: the Hyper fit (Al-Sharadqah & Chernov 2009; its constraint matrix is
//    2 Taubin - Pratt, used here in D dimensions), an eigenproblem of (D+2)x(D+2) moment
//    matrices accumulated in one pass.
// 3. Levenberg-Marquardt on all points, residual |q - c| - R, parameters (c, R).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/status.h"
#include "fitting/fit_result.h"
#include "fitting/internal/accurate_sum.h"
#include "fitting/internal/lm.h"

namespace tpcal::fitting::internal {

inline constexpr std::size_t kStartSample = 16384;

template <int D>
class HypersphereModel {
 public:
  static constexpr int kParams = D + 1;
  using Vec = Eigen::Matrix<double, D, 1>;
  using PVec = Eigen::Matrix<double, kParams, 1>;
  struct State {
    Vec center;     // scaled coordinates
    double radius;  // scaled units
  };

  HypersphereModel(std::span<const Vec> points_mm, const Vec& origin_mm, double scale_mm)
      : points_(points_mm), origin_(origin_mm), scale_(scale_mm), inv_scale_(1.0 / scale_mm) {}

  std::size_t num_residuals() const { return points_.size(); }
  double scale_mm() const { return scale_; }
  std::array<bool, kParams> param_is_length() const {
    std::array<bool, kParams> a;
    a.fill(true);
    return a;
  }
  Vec ToScaled(const Vec& p_mm) const { return (p_mm - origin_) * inv_scale_; }
  Vec ToMm(const Vec& q) const { return origin_ + q * scale_; }

  Linearization<kParams> Linearize(const State& s, double* residuals_mm, Eigen::MatrixXd* jacobian) const {
    const Vec c = s.center;
    const double radius = s.radius;
    return LinearizeRows<kParams>(
        points_.size(),
        [&](std::size_t i, std::array<double, kParams>& j, double& r) {
          const Vec d = (points_[i] - origin_) * inv_scale_ - c;
          const double rho = d.norm();
          r = rho - radius;
          // d r / d c = -(q - c)/|q - c|; at the centre itself any unit vector is a
          // subgradient, zero keeps the sums finite.
          const double minus_inv = rho > 0.0 ? -1.0 / rho : 0.0;
          for (int t = 0; t < D; ++t) j[static_cast<std::size_t>(t)] = d[t] * minus_inv;
          j[D] = -1.0;
        },
        scale_, residuals_mm, jacobian, PVec::Ones());
  }

  State Retract(const State& s, const PVec& delta) const {
    return {s.center + delta.template head<D>(), s.radius + delta[D]};
  }

 private:
  std::span<const Vec> points_;
  Vec origin_;
  double scale_;
  double inv_scale_;
};

template <int D>
struct HypersphereSolution {
  Eigen::Matrix<double, D, 1> center_mm;
  double radius_mm = 0.0;
  FitSummary summary;
};

// What a D-sphere is called in messages.
inline const char* HypersphereName(int d) { return d == 2 ? "circle" : "sphere"; }

// Hyper algebraic fit on q_i = (p_i - origin)/scale for i = 0, stride, 2 stride, ...
// Returns the start in scaled coordinates, or kDegenerate.
template <int D>
Result<typename HypersphereModel<D>::State> HyperStart(const HypersphereModel<D>& model,
                                                       std::span<const Eigen::Matrix<double, D, 1>> points_mm,
                                                       std::size_t stride, double* extent) {
  using Vec = Eigen::Matrix<double, D, 1>;
  constexpr int K = D + 2;  // z = (|q|^2, q, 1)
  using KMat = Eigen::Matrix<double, K, K>;
  using KVec = Eigen::Matrix<double, K, 1>;
  constexpr std::size_t kSums = K * (K + 1) / 2;
  const std::size_t m = (points_mm.size() + stride - 1) / stride;
  const auto sums = BlockSums<kSums>(m, [&](std::size_t k) {
    const Vec q = model.ToScaled(points_mm[k * stride]);
    // Scalars, not an Eigen vector: its packet store and the scalar reloads stall.
    std::array<double, K> z;
    z[0] = q.squaredNorm();
    for (int t = 0; t < D; ++t) z[static_cast<std::size_t>(t + 1)] = q[t];
    z[K - 1] = 1.0;
    std::array<double, kSums> a;
    std::size_t t = 0;
    for (int r = 0; r < K; ++r) {
      for (int c = r; c < K; ++c) a[t++] = z[r] * z[c];
    }
    return a;
  });
  KMat mom;
  {
    std::size_t t = 0;
    for (int r = 0; r < K; ++r) {
      for (int c = r; c < K; ++c, ++t) mom(r, c) = mom(c, r) = sums[t] / static_cast<double>(m);
    }
  }
  const char* name = HypersphereName(D);
  // Scatter of the sample: collinear (circle) / coplanar (sphere) points define no D-sphere.
  const Vec mean_q = mom.template block<D, 1>(1, K - 1);
  const Eigen::Matrix<double, D, D> scatter =
      mom.template block<D, D>(1, 1) - mean_q * mean_q.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> scatter_es(scatter, Eigen::EigenvaluesOnly);
  if (!(scatter_es.eigenvalues()[0] > 1e-20 * scatter_es.eigenvalues()[D - 1])) {
    std::ostringstream os;
    os << "points are " << (D == 2 ? "collinear" : "coplanar") << " (relative spread "
       << std::sqrt(std::max(0.0, scatter_es.eigenvalues()[0] / scatter_es.eigenvalues()[D - 1]))
       << " normal to their " << (D == 2 ? "line" : "plane") << "): no finite " << name;
    return Status(StatusCode::kDegenerate, os.str());
  }
  // Hyper constraint N (2 Taubin - Pratt) for the algebraic sphere a|q|^2 + b.q + c = 0.
  KMat nmat = KMat::Zero();
  nmat(0, 0) = 8.0 * mom(0, K - 1);
  for (int k = 1; k <= D; ++k) {
    nmat(0, k) = nmat(k, 0) = 4.0 * mom(k, K - 1);
    nmat(k, k) = 1.0;
  }
  nmat(0, K - 1) = nmat(K - 1, 0) = 2.0;
  // Smallest non-negative eta of M A = eta N A. With M = Y Y (Y its symmetric square
  // root) this is the symmetric problem (Y N^-1 Y) A* = eta A*, A = Y^-1 A*.
  Eigen::SelfAdjointEigenSolver<KMat> mes(mom);
  const KVec dm = mes.eigenvalues();
  KVec a;
  if (dm[0] <= 1e-13 * dm[K - 1]) {
    a = mes.eigenvectors().col(0);  // the data fit a D-sphere exactly (within rounding)
  } else {
    const KMat y = mes.eigenvectors() * dm.cwiseSqrt().asDiagonal() * mes.eigenvectors().transpose();
    const KMat y_inv = mes.eigenvectors() * dm.cwiseSqrt().cwiseInverse().asDiagonal() * mes.eigenvectors().transpose();
    const KMat kmat = y * nmat.inverse() * y;
    Eigen::SelfAdjointEigenSolver<KMat> kes(0.5 * (kmat + kmat.transpose()));
    int best = -1;
    for (int k = 0; k < K; ++k) {
      if (kes.eigenvalues()[k] > 0.0) {
        best = k;
        break;
      }
    }
    if (best < 0) return Status(StatusCode::kDegenerate, std::string("no algebraic ") + name + " fits the points");
    a = y_inv * kes.eigenvectors().col(best);
  }
  const double a0 = a[0];
  const Vec b = a.template segment<D>(1);
  const double c = a[K - 1];
  // Radius beyond 1e6 x the extent of the data (its RMS distance from the centroid): the
  // points are a straight line / flat patch to working precision.
  const Vec mean = mom.template block<D, 1>(1, K - 1);
  *extent = std::sqrt(std::max(0.0, mom(0, K - 1) - mean.squaredNorm()));
  const double b_norm = b.norm();
  if (!(std::abs(a0) * 2e6 * *extent > b_norm)) {
    std::ostringstream os;
    os << "points are nearly " << (D == 2 ? "collinear" : "coplanar") << ": the best " << name
       << " has a radius beyond 1e6 x the extent of the data";
    return Status(StatusCode::kDegenerate, os.str());
  }
  typename HypersphereModel<D>::State s;
  s.center = -b / (2.0 * a0);
  const double r2 = s.center.squaredNorm() - c / a0;
  if (!(r2 > 0.0)) return Status(StatusCode::kDegenerate, std::string("no real ") + name + " fits the points");
  s.radius = std::sqrt(r2);
  return s;
}

// The whole least-squares D-sphere fit. `what` names the caller in messages ("FitCircle2").
template <int D>
Result<HypersphereSolution<D>> FitHypersphere(std::span<const Eigen::Matrix<double, D, 1>> points_mm,
                                              const FitOptions& options, const std::string& what) {
  using Vec = Eigen::Matrix<double, D, 1>;
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < static_cast<std::size_t>(D + 1)) {
    return Status(StatusCode::kTooFewPoints,
                  what + " needs at least " + std::to_string(D + 1) + " points, got " + std::to_string(n));
  }
  // Origin and scale from a strided sample (every point if it is degenerate); the Hyper
  // start from all points (one pass of moments, no square roots): from it Gauss-Newton
  // needs about two passes, against three from a start on the sample.
  std::optional<HypersphereModel<D>> model;
  for (std::size_t stride = std::max<std::size_t>(1, n / kStartSample);; stride = 1) {
    const std::size_t m = (n + stride - 1) / stride;
    const auto sum = BlockSums<D>(m, [&](std::size_t k) {
      std::array<double, D> a;
      for (int t = 0; t < D; ++t) a[t] = points_mm[k * stride][t];
      return a;
    });
    Vec origin;
    for (int t = 0; t < D; ++t) origin[t] = sum[t] / static_cast<double>(m);
    if (!origin.allFinite()) {
      for (std::size_t i = 0; i < n; ++i) {
        if (!points_mm[i].allFinite()) {
          return Status(StatusCode::kInvalidArgument, what + ": point " + std::to_string(i) + " is not finite");
        }
      }
    }
    const auto ss = BlockSums<1>(m, [&](std::size_t k) {
      return std::array<double, 1>{(points_mm[k * stride] - origin).squaredNorm()};
    });
    const double rms = std::sqrt(ss[0] / static_cast<double>(m));
    if (rms > 0.0 && std::isfinite(rms)) {
      model.emplace(points_mm, origin, PowerOfTwoNear(rms));
      break;
    }
    if (stride == 1) return Status(StatusCode::kDegenerate, what + ": all points coincide");
  }
  double extent = 0.0;  // RMS distance of the points from their centroid, scaled units
  auto start = HyperStart<D>(*model, points_mm, 1, &extent);
  if (!start.ok()) return start.status().WithContext(what);
  auto run = RunLm(*model, *start, options);
  if (!run.ok()) return run.status().WithContext(what);
  std::vector<std::string> names;
  if (D == 2) {
    names = {"center_x_mm", "center_y_mm", "radius_mm"};
  } else {
    names = {"center_x_mm", "center_y_mm", "center_z_mm", "radius_mm"};
  }
  auto summary = Summarize(*model, *run, names, what, options);
  if (!summary.ok()) return summary.status();
  HypersphereSolution<D> sol;
  sol.center_mm = model->ToMm(run->state.center);
  sol.radius_mm = run->state.radius * model->scale_mm();
  // Radius beyond 1e6 x the extent of the data, or not positive: no usable D-sphere.
  if (!(sol.radius_mm > 0.0) || !sol.center_mm.allFinite() || !(run->state.radius <= 1e6 * extent)) {
    return Status(StatusCode::kDegenerate, what + ": the least-squares " + HypersphereName(D) +
                                               " has no positive radius below 1e6 x the extent of the data (points nearly " +
                                               (D == 2 ? "collinear)" : "coplanar)"));
  }
  sol.summary = std::move(*summary);
  return sol;
}

}  // namespace tpcal::fitting::internal
