#include "fitting/plane_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <array>
#include <limits>
#include <cmath>
#include <sstream>
#include <string>

#include "fitting/internal/accurate_sum.h"
#include "fitting/internal/lm.h"
#include "fitting/internal/orientation.h"

namespace tpcal::fitting {
namespace {

// Index of the first non-finite point, for the error message.
std::size_t FirstNonFinite(std::span<const Eigen::Vector3d> p) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) return i;
  }
  return p.size();
}

// Sum of squares, minimum and maximum of the residuals n . (p - c) (written to out[i] if out is
// not null), two points at a time in SIMD lanes, lane totals per block of kSumBlock points
// combined with Neumaier compensation (as internal::SumValues does).
internal::ValueSums PlaneResiduals(std::span<const Eigen::Vector3d> points_mm, const Eigen::Vector3d& normal,
                                   const Eigen::Vector3d& centroid, double* __restrict out) {
  using V = Eigen::Array2d;
  const std::size_t n = points_mm.size();
  const double* __restrict xyz = points_mm.data()->data();
  internal::NeumaierSum total;
  // Constants in locals (the compiler cannot keep referenced values in registers across the
  // stores to `out`).
  const V cx = V::Constant(centroid.x()), cy = V::Constant(centroid.y()), cz = V::Constant(centroid.z());
  const V nx = V::Constant(normal.x()), ny = V::Constant(normal.y()), nz = V::Constant(normal.z());
  V lo = V::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  [[maybe_unused]] const bool aligned = reinterpret_cast<std::uintptr_t>(out) % 16 == 0;
  auto residual = [&](std::size_t i) {  // points i and i + 1
    const V x{xyz[3 * i], xyz[3 * i + 3]}, y{xyz[3 * i + 1], xyz[3 * i + 4]}, z{xyz[3 * i + 2], xyz[3 * i + 5]};
    return V((x - cx) * nx + (y - cy) * ny + (z - cz) * nz);
  };
  for (std::size_t b = 0; b < n; b += internal::kSumBlock) {
    const std::size_t e = std::min(n, b + internal::kSumBlock);
    V acc0 = V::Zero(), acc1 = V::Zero();  // two chains: the adds do not wait on each other
    std::size_t i = b;
    for (; i + 3 < e; i += 4) {
      const V r0 = residual(i), r1 = residual(i + 2);
      acc0 += r0.square();
      acc1 += r1.square();
      lo = lo.min(r0).min(r1);
      hi = hi.max(r0).max(r1);
      if (out != nullptr) {
#if defined(__SSE2__)
        if (aligned) {  // streaming stores: the residuals bypass the cache (no read for ownership)
          _mm_stream_pd(out + i, _mm_load_pd(r0.data()));
          _mm_stream_pd(out + i + 2, _mm_load_pd(r1.data()));
        } else
#endif
        {
          out[i] = r0[0];
          out[i + 1] = r0[1];
          out[i + 2] = r1[0];
          out[i + 3] = r1[1];
        }
      }
    }
    double tail = 0.0;
    for (; i < e; ++i) {
      const double r = normal.dot(points_mm[i] - centroid);
      tail += r * r;
      lo[0] = std::min(lo[0], r);
      hi[0] = std::max(hi[0], r);
      if (out != nullptr) out[i] = r;
    }
    total.Add((acc0 + acc1).sum() + tail);
  }
#if defined(__SSE2__)
  if (out != nullptr && aligned) _mm_sfence();  // the streamed residuals are visible to later loads
#endif
  internal::ValueSums s;
  s.sum_sq = total.Total();
  s.min = lo.minCoeff();
  s.max = hi.maxCoeff();
  return s;
}

}  // namespace

Result<FitResult<Plane>> FitPlane(std::span<const Eigen::Vector3d> points_mm, const FitOptions& options,
                                  std::optional<Eigen::Vector3d> normal_hint) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::size_t n = points_mm.size();
  if (n < 3) {
    return Status(StatusCode::kTooFewPoints, "FitPlane needs at least 3 points, got " + std::to_string(n));
  }
  // One pass: first and second moments about the first point (a point inside the data, so
  // no cancellation against a far origin), two points at a time in SIMD lanes; per block of
  // kSumBlock points the lanes are added and the block totals combined with Neumaier
  // compensation (as BlockSums does).
  const Eigen::Vector3d shift = points_mm[0];
  const double* __restrict xyz = points_mm.data()->data();  // 3 doubles per point, contiguous
  std::array<double, 9> m{};
  {
    using V = Eigen::Array2d;
    std::array<internal::NeumaierSum, 9> total{};
    for (std::size_t b = 0; b < n; b += internal::kSumBlock) {
      const std::size_t e = std::min(n, b + internal::kSumBlock);
      std::array<V, 9> acc;
      for (auto& a : acc) a.setZero();
      auto add = [&](std::size_t i, bool pair) {
        const std::size_t k = pair ? i + 1 : i;
        const V x = V(xyz[3 * i], xyz[3 * k]) - shift.x();
        const V y = V(xyz[3 * i + 1], xyz[3 * k + 1]) - shift.y();
        V z = V(xyz[3 * i + 2], xyz[3 * k + 2]) - shift.z();
        const V w = pair ? V::Ones() : V(1.0, 0.0);  // lane 1 of an odd last point counts nothing
        const V xw = x * w, yw = y * w;
        z *= w;
        acc[0] += xw;
        acc[1] += yw;
        acc[2] += z;
        acc[3] += xw * x;
        acc[4] += xw * y;
        acc[5] += z * x;
        acc[6] += yw * y;
        acc[7] += z * y;
        acc[8] += z * z;
      };
      std::size_t i = b;
      for (; i + 1 < e; i += 2) add(i, true);
      if (i < e) add(i, false);
      for (std::size_t k = 0; k < 9; ++k) total[k].Add(acc[k].sum());
    }
    for (std::size_t k = 0; k < 9; ++k) m[k] = total[k].Total();
  }
  const double nd = static_cast<double>(n);
  const Eigen::Vector3d mean_d(m[0] / nd, m[1] / nd, m[2] / nd);
  if (!mean_d.allFinite()) {
    return Status(StatusCode::kInvalidArgument,
                  "FitPlane: point " + std::to_string(FirstNonFinite(points_mm)) + " is not finite");
  }
  Eigen::Matrix3d scatter;
  scatter << m[3], m[4], m[5], m[4], m[6], m[7], m[5], m[7], m[8];
  scatter -= nd * mean_d * mean_d.transpose();
  const Eigen::Vector3d centroid = shift + mean_d;

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter);  // ascending eigenvalues
  const Eigen::Vector3d lambda = es.eigenvalues().cwiseMax(0.0);
  // The normal is defined when the two smallest eigenvalues are separated; 1e-12 of the
  // largest is an in-plane width below 1e-6 of the length (collinear within rounding).
  if (!(lambda[2] > 0.0)) return Status(StatusCode::kDegenerate, "FitPlane: all points coincide");
  if (lambda[1] - lambda[0] <= 1e-12 * lambda[2]) {
    std::ostringstream os;
    os << "FitPlane: points are collinear (or isotropic): scatter eigenvalues " << lambda.transpose()
       << " mm^2 do not single out a normal";
    return Status(StatusCode::kDegenerate, os.str());
  }
  const Eigen::Vector3d normal = internal::OrientAlong(es.eigenvectors().col(0), normal_hint);
  const Eigen::Vector3d u = es.eigenvectors().col(2);  // major in-plane direction
  const Eigen::Vector3d v = normal.cross(u);           // (u, v, normal) right-handed

  FitResult<Plane> r;
  r.feature = Plane{centroid, normal};
  r.n_points = n;
  r.local_axes.col(0) = u;
  r.local_axes.col(1) = v;
  r.local_axes.col(2) = normal;
  r.parameter_names = {"offset_mm", "tilt_u_rad", "tilt_v_rad"};
  if (options.keep_residuals) r.residuals_mm.resize(n);
  if (options.keep_jacobian) r.jacobian.resize(static_cast<Eigen::Index>(n), 3);
  // Second pass: residuals n . (p - c) (and, if asked, the Jacobian rows: moving the plane
  // by +offset along the normal lowers every residual by 1; tilting the normal toward u by
  // t raises r by t * u.(p - c)).
  const internal::ValueSums ss = PlaneResiduals(points_mm, normal, centroid,
                                                options.keep_residuals ? r.residuals_mm.data() : nullptr);
  if (options.keep_jacobian) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = points_mm[i] - centroid;
      r.jacobian.row(static_cast<Eigen::Index>(i)) << -1.0, u.dot(d), v.dot(d);
    }
  }
  r.stats = internal::MakeStats(ss.sum_sq, ss.min, ss.max, n, 3);
  if (options.compute_covariance && n > 3) {
    // J^T J = diag(n, lambda_u, lambda_v): the centroid and the principal axes decouple it.
    const double sigma2 = ss.sum_sq / (nd - 3.0);
    r.covariance = Eigen::Vector3d(sigma2 / nd, sigma2 / lambda[2], sigma2 / lambda[1]).asDiagonal();
  }
  r.termination = Termination::kClosedForm;
  std::ostringstream os;
  os << "closed form (centroid and scatter eigenvector), " << n << " points";
  r.message = os.str();
  return r;
}

}  // namespace tpcal::fitting
