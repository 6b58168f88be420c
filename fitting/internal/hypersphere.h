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
  double ToScaledCoordinate(const Vec& p_mm, int t) const { return (p_mm[t] - origin_[t]) * inv_scale_; }
  Vec ToMm(const Vec& q) const { return origin_ + q * scale_; }
  const Vec& origin_mm() const { return origin_; }
  double inv_scale() const { return inv_scale_; }

  Linearization<kParams> Linearize(const State& s, double* residuals_mm, Eigen::MatrixXd* jacobian) const {
    if (jacobian == nullptr) return LinearizeBlocks(s, residuals_mm);
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

  // The same sums as Linearize without a Jacobian, in one fused loop over the points, two
  // points at a time in SIMD lanes (Eigen::Array2d: packed square roots, reciprocals and
  // products, two lanes of every partial sum): J^T J and J^T r follow from
  // j = (-(q - c)/rho, -1), so no per-point Jacobian row is formed. Per block of kSumBlock
  // points the lanes are added and the block totals combined with Neumaier compensation, as
  // BlockSums does.
  Linearization<kParams> LinearizeBlocks(const State& s, double* __restrict residuals_mm) const {
    using V = Eigen::Array2d;
    constexpr int kSums = D * (D + 1) / 2 + 2 * D + 2;  // sum j_t j_u (t <= u), sum j_t, sum j_t r, sum r, sum r^2
    std::array<NeumaierSum, kSums> total{};
    const std::size_t n = points_.size();
    const double* __restrict xyz = points_.data()->data();  // D doubles per point, contiguous
    const double inv_scale = inv_scale_, radius = s.radius, scale = scale_;
    V lo = V::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t b = 0; b < n; b += kSumBlock) {
      const std::size_t e = std::min(n, b + kSumBlock);
      std::array<V, kSums> acc;
      for (auto& a : acc) a.setZero();
      // Lanes i and i + 1; `valid` = 1 lane (the odd last point of the data) zeroes lane 1.
      auto add = [&](std::size_t i, int valid) {
        std::array<V, D> j;
        for (int t = 0; t < D; ++t) {
          // The same rounding as Linearize (the Jacobian pass): (p - origin) / scale - c.
          const V p{xyz[i * D + t], valid == 2 ? xyz[(i + 1) * D + t] : xyz[i * D + t]};
          j[static_cast<std::size_t>(t)] = (p - origin_[t]) * inv_scale - s.center[t];
        }
        V rho = j[0].square();
        for (int t = 1; t < D; ++t) rho += j[static_cast<std::size_t>(t)].square();
        rho = rho.sqrt();
        // d r / d c = -(q - c)/|q - c|; at the centre itself (rho = 0, q - c = 0) any unit
        // vector is a subgradient: the floor makes it 0 * -1e300 = 0 and keeps the sums finite
        // (a packed division; a per-lane select would be scalarised).
        V minus_inv = -(rho.max(1e-300).inverse());
        V r = rho - radius;
        if (valid == 1) {
          minus_inv[1] = 0.0;
          r[1] = r[0];  // duplicate lane 0 for min/max; its sums are masked below
        }
        for (int t = 0; t < D; ++t) j[static_cast<std::size_t>(t)] *= minus_inv;
        if (residuals_mm != nullptr) {
          residuals_mm[i] = r[0] * scale;
          if (valid == 2) residuals_mm[i + 1] = r[1] * scale;
        }
        lo = lo.min(r);
        hi = hi.max(r);
        if (valid == 1) r[1] = 0.0;
        int k = 0;
        for (int t = 0; t < D; ++t) {
          for (int u = t; u < D; ++u) acc[static_cast<std::size_t>(k++)] += j[static_cast<std::size_t>(t)] * j[static_cast<std::size_t>(u)];
        }
        for (int t = 0; t < D; ++t) acc[static_cast<std::size_t>(k++)] += j[static_cast<std::size_t>(t)];
        for (int t = 0; t < D; ++t) acc[static_cast<std::size_t>(k++)] += j[static_cast<std::size_t>(t)] * r;
        acc[static_cast<std::size_t>(k++)] += r;
        acc[static_cast<std::size_t>(k)] += r.square();
      };
      std::size_t i = b;
      for (; i + 1 < e; i += 2) add(i, 2);
      if (i < e) add(i, 1);
      for (int a = 0; a < kSums; ++a) total[static_cast<std::size_t>(a)].Add(acc[static_cast<std::size_t>(a)].sum());
    }
    // Assemble with j_D = -1 for the radius: J^T J = [[S_jj, -S_j], [-S_j^T, n]],
    // J^T r = [S_jr, -S_r], cost = S_rr.
    Linearization<kParams> lin;
    int k = 0;
    for (int t = 0; t < D; ++t) {
      for (int u = t; u < D; ++u) lin.jtj(t, u) = lin.jtj(u, t) = total[static_cast<std::size_t>(k++)].Total();
    }
    for (int t = 0; t < D; ++t) lin.jtj(t, D) = lin.jtj(D, t) = -total[static_cast<std::size_t>(k++)].Total();
    lin.jtj(D, D) = static_cast<double>(n);
    for (int t = 0; t < D; ++t) lin.jtr[t] = total[static_cast<std::size_t>(k++)].Total();
    lin.jtr[D] = -total[static_cast<std::size_t>(k++)].Total();
    lin.cost = total[static_cast<std::size_t>(k)].Total();
    lin.r_min = lo.minCoeff();
    lin.r_max = hi.maxCoeff();
    return lin;
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
  // Moments of z = (|q|^2, q, 1) in one fused loop, two points at a time in SIMD lanes
  // (Eigen::Array2d), lanes added per block of kSumBlock points and block totals combined with
  // Neumaier compensation as in BlockSums. The (1, 1) moment is the count.
  using V = Eigen::Array2d;
  std::array<NeumaierSum, kSums> total{};
  for (std::size_t b = 0; b < m; b += kSumBlock) {
    const std::size_t e = std::min(m, b + kSumBlock);
    std::array<V, kSums - 1> acc;
    for (auto& a : acc) a.setZero();
    auto add = [&](std::size_t i, bool pair) {
      const Vec& p0 = points_mm[i * stride];
      const Vec& p1 = points_mm[(pair ? i + 1 : i) * stride];
      std::array<V, K - 1> z;  // |q|^2, q_0 .. q_{D-1}
      for (int t = 0; t < D; ++t) {  // packed (p - origin) / scale, as ToScaledCoordinate
        const V p{p0[t], p1[t]};
        z[static_cast<std::size_t>(t + 1)] = (p - model.origin_mm()[t]) * model.inv_scale();
      }
      z[0] = z[1].square();
      for (int t = 1; t < D; ++t) z[0] += z[static_cast<std::size_t>(t + 1)].square();
      if (!pair) {
        for (auto& zz : z) zz[1] = 0.0;  // lane 1 of an odd last point counts nothing
      }
      std::size_t k = 0;
      for (int r = 0; r < K - 1; ++r) {
        for (int c = r; c < K - 1; ++c) acc[k++] += z[static_cast<std::size_t>(r)] * z[static_cast<std::size_t>(c)];
        acc[k++] += z[static_cast<std::size_t>(r)];
      }
    };
    std::size_t i = b;
    for (; i + 1 < e; i += 2) add(i, true);
    if (i < e) add(i, false);
    for (std::size_t k = 0; k + 1 < kSums; ++k) total[k].Add(acc[k].sum());
    total[kSums - 1].Add(static_cast<double>(e - b));
  }
  KMat mom;
  {
    std::size_t t = 0;
    for (int r = 0; r < K; ++r) {
      for (int c = r; c < K; ++c, ++t) mom(r, c) = mom(c, r) = total[t].Total() / static_cast<double>(m);
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
