// Internal to tpcal::fitting: the Gauss-Newton / Levenberg-Marquardt engine shared by the
// iterative least-squares fitters (circle, sphere, cylinder, cone), and the step from its
// converged state to the FitResult fields (statistics, covariance, identifiability).
//
// A Model works in centred, scaled coordinates (q = (p - origin) / scale, scale a power of
// two so the scaling is exact), so parameters are O(1) and every tolerance is relative to
// the feature size. It provides:
//   static constexpr int kParams;                 // P, the minimal parametrisation
//   using State = ...;                            // the current feature (any representation)
//   std::size_t num_residuals() const;
//   double scale_mm() const;                      // mm per scaled unit
//   std::array<bool, P> param_is_length() const;  // lengths scale with scale_mm, angles do not
//   Linearization<P> Linearize(const State&, double* residuals_mm, Eigen::MatrixXd* jacobian) const;
//   State Retract(const State&, const Eigen::Matrix<double, P, 1>& delta) const;
// Linearize evaluates residuals (scaled units) and the Jacobian d r / d delta at delta = 0
// of Retract, in one pass; it writes residuals in mm and the Jacobian in mm per unit of
// each parameter (if the pointers are non-null).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "fitting/fit_result.h"
#include "fitting/internal/accurate_sum.h"

namespace tpcal::fitting::internal {

template <int P>
struct Linearization {
  Eigen::Matrix<double, P, P> jtj = Eigen::Matrix<double, P, P>::Zero();  // J^T J
  Eigen::Matrix<double, P, 1> jtr = Eigen::Matrix<double, P, 1>::Zero();  // J^T r
  double cost = 0.0;                                                      // sum r^2
  double r_min = std::numeric_limits<double>::infinity();
  double r_max = -std::numeric_limits<double>::infinity();
};

// Accumulators per residual row: upper triangle of J^T J, then J^T r, then r^2.
template <int P>
inline constexpr std::size_t kRowSums = P * (P + 1) / 2 + P + 1;

// Term k of a row's sums as a product of two entries of (j_0 .. j_{P-1}, r).
template <int P>
inline constexpr auto kRowTerms = [] {
  std::array<std::pair<int, int>, kRowSums<P>> t{};
  std::size_t k = 0;
  for (int a = 0; a < P; ++a) {
    for (int b = a; b < P; ++b) t[k++] = {a, b};
  }
  for (int a = 0; a < P; ++a) t[k++] = {a, P};
  t[k] = {P, P};
  return t;
}();

// acc[k] += jr[first_k] * jr[second_k] with every index a compile-time constant, so the
// compiler keeps acc in registers (with loop-computed indices it stays in memory and the
// pass runs several times slower).
template <int P, std::size_t... K>
inline void AddRowTerms(std::array<double, kRowSums<P>>& acc, const std::array<double, P + 1>& jr,
                        std::index_sequence<K...>) {
  ((acc[K] += jr[kRowTerms<P>[K].first] * jr[kRowTerms<P>[K].second]), ...);
}

// One pass over n residual rows. row(i, j, r) sets the Jacobian row j (std::array<double, P>) and the
// residual r of row i, both in scaled units. residuals_mm / jacobian may be null.
// jacobian_mm_scale[k] converts column k to mm per unit of parameter k.
// Written for speed (this loop is the whole cost of an iterative fit): per block of
// kSumBlock rows the sums live in local scalars the compiler keeps in registers (no
// reference or pointer to them escapes, and the output pointers are __restrict), and the
// block totals are added with Neumaier compensation as in BlockSums.
template <int P, typename RowFn>
Linearization<P> LinearizeRows(std::size_t n, RowFn&& row, double scale_mm, double* __restrict residuals_mm,
                               Eigen::MatrixXd* jacobian, const Eigen::Matrix<double, P, 1>& jacobian_mm_scale) {
  constexpr std::size_t kN = kRowSums<P>;
  double* __restrict jac = nullptr;
  if (jacobian != nullptr) {
    jacobian->resize(static_cast<Eigen::Index>(n), P);
    jac = jacobian->data();  // column-major: (i, k) at k * n + i
  }
  std::array<NeumaierSum, kN> total{};
  double r_min = std::numeric_limits<double>::infinity();
  double r_max = -r_min;
  for (std::size_t b = 0; b < n; b += kSumBlock) {
    const std::size_t e = std::min(n, b + kSumBlock);
    std::array<double, kN> acc{};
    double block_r[kSumBlock];
    double block_min = std::numeric_limits<double>::infinity();
    double block_max = -block_min;
    for (std::size_t i = b; i < e; ++i) {
      std::array<double, P + 1> jr;  // (J row, r); not an Eigen vector: mixed packet/scalar access stalls
      std::array<double, P> j;
      row(i, j, jr[P]);
      for (int a = 0; a < P; ++a) jr[static_cast<std::size_t>(a)] = j[static_cast<std::size_t>(a)];
      AddRowTerms<P>(acc, jr, std::make_index_sequence<kN>{});
      const double r = jr[P];
      block_min = std::min(block_min, r);
      block_max = std::max(block_max, r);
      block_r[i - b] = r;
      if (jac != nullptr) {
        for (int a = 0; a < P; ++a) jac[static_cast<std::size_t>(a) * n + i] = j[a] * jacobian_mm_scale[a];
      }
    }
    if (residuals_mm != nullptr) {
      for (std::size_t i = b; i < e; ++i) residuals_mm[i] = block_r[i - b] * scale_mm;
    }
    for (std::size_t k = 0; k < kN; ++k) total[k].Add(acc[k]);
    r_min = std::min(r_min, block_min);
    r_max = std::max(r_max, block_max);
  }
  Linearization<P> lin;
  std::size_t k = 0;
  for (int a = 0; a < P; ++a) {
    for (int b = a; b < P; ++b, ++k) lin.jtj(a, b) = lin.jtj(b, a) = total[k].Total();
  }
  for (int a = 0; a < P; ++a) lin.jtr[a] = total[k++].Total();
  lin.cost = total[k].Total();
  lin.r_min = r_min;
  lin.r_max = r_max;
  return lin;
}

// Column scale that turns a scaled Jacobian into mm per unit of each parameter.
template <typename Model>
Eigen::Matrix<double, Model::kParams, 1> JacobianMmScale(const Model& m) {
  Eigen::Matrix<double, Model::kParams, 1> s;
  const auto is_length = m.param_is_length();
  for (int k = 0; k < Model::kParams; ++k) s[k] = is_length[k] ? 1.0 : m.scale_mm();
  return s;
}

template <typename Model>
struct LmRun {
  typename Model::State state;
  Linearization<Model::kParams> lin;  // at state
  std::vector<double> residuals_mm;   // at state (if options.keep_residuals)
  Termination termination = Termination::kConverged;
  int iterations = 0;
  double last_step = 0.0;  // max |Gauss-Newton step| at state (scaled units / rad)
  std::string message;
};

// Steps below this that no longer shrink are taken as the rounding floor of an
// ill-conditioned problem (e.g. a 20 deg arc): 1e-9 of the feature size is 0.5 nm on 500 mm.
inline constexpr double kRoundingFloorStep = 1e-9;
// A run stopped early (max_iterations) still returns a result if its last step is below
// this; farther from a minimum it is kNotConverged.
inline constexpr double kNearlyConvergedStep = 1e-6;

// Reciprocal condition of J^T J after Jacobi scaling (0 if a column vanishes).
template <int P>
double ScaledRcond(const Eigen::Matrix<double, P, P>& a) {
  const Eigen::Matrix<double, P, 1> d = a.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (!(d.minCoeff() > 0.0)) return 0.0;
  const Eigen::Matrix<double, P, P> s = d.cwiseInverse().asDiagonal() * a * d.cwiseInverse().asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, P, P>> es(s, Eigen::EigenvaluesOnly);
  return std::max(0.0, es.eigenvalues()[0]) / es.eigenvalues()[P - 1];
}

// Below this reciprocal condition of the scaled normal equations, steps are solved by QR
// of the Jacobian itself (accurate to eps x cond(J) instead of eps x cond(J)^2); this costs
// one extra pass and n x P memory, and only ill-conditioned fits (nearly straight arcs)
// take it.
inline constexpr double kQrRcond = 1e-10;

// Levenberg-Marquardt from `start`. Convergence: the undamped Gauss-Newton step is below
// options.step_tolerance_mm (relative), or below kRoundingFloorStep and no longer halving.
// Steps are accepted unless the cost rises by more than its own rounding noise.
template <typename Model>
Result<LmRun<Model>> RunLm(const Model& model, typename Model::State start, const FitOptions& options) {
  constexpr int P = Model::kParams;
  using PVec = Eigen::Matrix<double, P, 1>;
  using PMat = Eigen::Matrix<double, P, P>;
  const std::size_t n = model.num_residuals();
  const PVec jac_mm_scale = JacobianMmScale(model);
  LmRun<Model> run;
  run.state = std::move(start);
  // Residuals are written by the pass of each trial state straight into run.residuals_mm (no
  // second buffer): they are current when the last trial was accepted. Only a run that ends on a
  // state whose residuals were not written last (no step accepted, or a rejected trial after the
  // last accepted one) pays one more pass for them.
  if (options.keep_residuals) run.residuals_mm.resize(n);
  bool residuals_current = false;
  auto finish = [&]() -> LmRun<Model>& {
    if (options.keep_residuals && !residuals_current) model.Linearize(run.state, run.residuals_mm.data(), nullptr);
    return run;
  };
  run.lin = model.Linearize(run.state, nullptr, nullptr);
  if (!std::isfinite(run.lin.cost) || !run.lin.jtj.allFinite()) {
    return Status(StatusCode::kDegenerate, "non-finite residuals at the start point (degenerate geometry)");
  }
  const double eps = std::numeric_limits<double>::epsilon();
  double lambda = 0.0;
  double previous_step = std::numeric_limits<double>::infinity();
  // QR mode: the scaled Jacobian and residuals at run.state.
  Eigen::MatrixXd j_qr;
  Eigen::VectorXd r_qr;
  for (int it = 1;; ++it) {
    run.iterations = it - 1;
    const PMat& a = run.lin.jtj;
    const PVec& g = run.lin.jtr;
    const bool use_qr = ScaledRcond<P>(a) < kQrRcond;
    if (use_qr) {
      r_qr.resize(static_cast<Eigen::Index>(n));
      model.Linearize(run.state, r_qr.data(), &j_qr);
      r_qr /= model.scale_mm();
      j_qr = j_qr * jac_mm_scale.cwiseInverse().asDiagonal();
    }
    // Step of the (damped) linearised problem min |J d + r|^2 + lambda |D d|^2, D^2 = diag(J^T J).
    auto solve = [&](double lam, bool* ok) -> PVec {
      PVec d;
      if (use_qr) {
        Eigen::MatrixXd aug(j_qr.rows() + (lam > 0.0 ? P : 0), P);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(aug.rows());
        aug.topRows(j_qr.rows()) = j_qr;
        rhs.head(r_qr.size()) = -r_qr;
        if (lam > 0.0) aug.bottomRows(P) = (lam * a.diagonal()).cwiseSqrt().asDiagonal();
        d = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(aug).solve(rhs);
        *ok = d.allFinite();
      } else if (lam == 0.0) {
        Eigen::LDLT<PMat> ldlt(a);
        d = ldlt.solve(-g);
        *ok = ldlt.info() == Eigen::Success && ldlt.isPositive() && d.allFinite();
      } else {
        PMat damped = a;
        const double floor = 1e-12 * std::max(a.diagonal().maxCoeff(), 1e-300);
        damped.diagonal() += lam * a.diagonal().cwiseMax(floor);
        d = damped.ldlt().solve(-g);
        *ok = d.allFinite();
      }
      return d;
    };
    bool gn_ok = false;
    const PVec gn = solve(0.0, &gn_ok);  // undamped Gauss-Newton step: the distance to the minimum
    run.last_step = gn_ok ? gn.cwiseAbs().maxCoeff() : std::numeric_limits<double>::infinity();
    if (run.last_step <= options.step_tolerance_mm) {
      run.termination = Termination::kConverged;
      std::ostringstream os;
      os << "converged after " << run.iterations << " iterations, last step " << run.last_step
         << " (relative/rad) <= tolerance " << options.step_tolerance_mm;
      run.message = os.str();
      return std::move(finish());
    }
    if (run.last_step <= kRoundingFloorStep && run.last_step > 0.5 * previous_step) {
      run.termination = Termination::kConverged;
      std::ostringstream os;
      os << "converged after " << run.iterations << " iterations at the rounding floor: step " << run.last_step
         << " (relative/rad) no longer shrinks (tolerance " << options.step_tolerance_mm << ")";
      run.message = os.str();
      return std::move(finish());
    }
    if (it > options.max_iterations) break;
    previous_step = run.last_step;
    // Rounding noise of the cost: each residual carries ~eps of the O(1) coordinates.
    const double cost_noise = 16.0 * eps * std::sqrt(static_cast<double>(n) * run.lin.cost) + 1e-300;
    bool accepted = false;
    while (!accepted) {
      bool ok = false;
      const PVec step = (lambda == 0.0 && gn_ok) ? gn : solve(lambda, &ok);
      if (lambda == 0.0 && gn_ok) ok = true;
      if (ok) {
        auto trial = model.Retract(run.state, step);
        auto lin = model.Linearize(trial, options.keep_residuals ? run.residuals_mm.data() : nullptr, nullptr);
        residuals_current = false;
        if (std::isfinite(lin.cost) && lin.jtj.allFinite() && lin.cost <= run.lin.cost + cost_noise) {
          run.state = std::move(trial);
          run.lin = lin;
          residuals_current = true;
          lambda = lambda < 1e-9 ? 0.0 : 0.1 * lambda;
          accepted = true;
          break;
        }
      }
      lambda = lambda == 0.0 ? 1e-4 : 10.0 * lambda;
      if (lambda > 1e12) break;
    }
    if (!accepted) {
      // No step decreases the cost: a minimum within rounding if the last step was small.
      if (run.last_step <= kNearlyConvergedStep) {
        run.termination = Termination::kConverged;
        std::ostringstream os;
        os << "converged after " << run.iterations << " iterations: the cost no longer decreases, step "
           << run.last_step << " (relative/rad)";
        run.message = os.str();
        return std::move(finish());
      }
      std::ostringstream os;
      os << "Levenberg-Marquardt cannot decrease the cost after " << run.iterations
         << " iterations; Gauss-Newton step still " << run.last_step << " (relative/rad)";
      return Status(StatusCode::kNotConverged, os.str());
    }
  }
  std::ostringstream os;
  os << "stopped at max_iterations=" << options.max_iterations << " with last step " << run.last_step
     << " (relative/rad), tolerance " << options.step_tolerance_mm;
  if (run.last_step > kNearlyConvergedStep) return Status(StatusCode::kNotConverged, os.str());
  run.termination = Termination::kMaxIterations;
  run.message = os.str();
  return std::move(finish());
}

// The fields of a FitResult that every least-squares fitter fills the same way.
struct FitSummary {
  ResidualStats stats;
  std::vector<double> residuals_mm;
  Eigen::MatrixXd covariance;
  Eigen::MatrixXd jacobian;
  Termination termination = Termination::kClosedForm;
  int iterations = 0;
  std::string message;

  template <typename F>
  void MoveInto(FitResult<F>& r) {
    r.stats = stats;
    r.residuals_mm = std::move(residuals_mm);
    r.covariance = std::move(covariance);
    r.jacobian = std::move(jacobian);
    r.termination = termination;
    r.iterations = iterations;
    r.message = std::move(message);
  }
};

// Residual statistics from sums in mm: n observations, p parameters.
inline ResidualStats MakeStats(double cost_mm2, double min_mm, double max_mm, std::size_t n, int p) {
  ResidualStats s;
  const double nd = static_cast<double>(n);
  s.rms_mm = n > 0 ? std::sqrt(cost_mm2 / nd) : 0.0;
  s.min_mm = min_mm;
  s.max_mm = max_mm;
  s.form_mm = max_mm - min_mm;
  s.sigma_mm = nd > p ? std::sqrt(cost_mm2 / (nd - p)) : 0.0;
  return s;
}

// Identifiability of the parameters at a converged state. J^T J (any P) after Jacobi
// scaling resolves reciprocal conditions down to ~1e-14 only (its rounding is eps of its
// largest entry), so below that the decision is made on J itself: kDegenerate when the
// column-scaled J has condition above 1e12, i.e. some parameter combination would carry
// fewer than ~4 significant digits of the feature size. `jacobian` (n x P) is computed
// only in that case, by the callback.
template <typename ComputeJacobian>
Status CheckIdentifiable(const Eigen::MatrixXd& jtj, ComputeJacobian&& compute_jacobian,
                         const std::vector<std::string>& names, const std::string& what) {
  const Eigen::Index p = jtj.rows();
  const Eigen::VectorXd d = jtj.diagonal().cwiseMax(0.0).cwiseSqrt();
  const double dmax = d.maxCoeff();
  for (Eigen::Index k = 0; k < p; ++k) {
    if (!(d[k] > 1e-150 * dmax) || !(dmax > 0.0)) {
      return Status(StatusCode::kDegenerate, what + ": the data do not constrain " + names[static_cast<std::size_t>(k)]);
    }
  }
  const Eigen::MatrixXd s = d.cwiseInverse().asDiagonal() * jtj * d.cwiseInverse().asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(s);
  if (es.eigenvalues().minCoeff() > 1e-14 * es.eigenvalues().maxCoeff()) return Status::Ok();
  const Eigen::MatrixXd j = compute_jacobian();
  Eigen::VectorXd col(p);
  for (Eigen::Index k = 0; k < p; ++k) col[k] = j.col(k).norm();
  if (!(col.minCoeff() > 0.0)) {
    return Status(StatusCode::kDegenerate, what + ": the data do not constrain every parameter");
  }
  const Eigen::MatrixXd r = Eigen::HouseholderQR<Eigen::MatrixXd>(j * col.cwiseInverse().asDiagonal())
                                .matrixQR()
                                .topRows(p)
                                .template triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(r, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();  // descending
  const double cond = sv[0] / std::max(sv[p - 1], 1e-300);
  if (cond <= 1e12) return Status::Ok();
  std::ostringstream os;
  os << what << ": the data do not determine the combination of";
  const Eigen::VectorXd v = svd.matrixV().col(p - 1);
  for (Eigen::Index k = 0; k < p; ++k) {
    if (std::abs(v[k]) > 0.3) os << ' ' << names[static_cast<std::size_t>(k)];
  }
  os << " (condition of the scaled Jacobian " << cond << " > 1e12)";
  return Status(StatusCode::kDegenerate, os.str());
}

// sigma^2 (J^T J)^-1 in mm / rad from scaled normal equations; empty when n_obs <= p.
template <int P>
Eigen::MatrixXd CovarianceMm(const Linearization<P>& lin, std::size_t n_obs, const Eigen::Matrix<double, P, 1>& mm_per_unit) {
  if (n_obs <= static_cast<std::size_t>(P)) return {};
  const double sigma2 = lin.cost / static_cast<double>(n_obs - P);
  const Eigen::Matrix<double, P, P> inv = lin.jtj.ldlt().solve(Eigen::Matrix<double, P, P>::Identity());
  return Eigen::MatrixXd(sigma2 * mm_per_unit.asDiagonal() * inv * mm_per_unit.asDiagonal());
}

// Statistics, covariance, identifiability and (optionally) the Jacobian of a converged run.
template <typename Model>
Result<FitSummary> Summarize(const Model& model, LmRun<Model>& run, const std::vector<std::string>& names,
                             const std::string& what, const FitOptions& options) {
  constexpr int P = Model::kParams;
  FitSummary s;
  TPCAL_RETURN_IF_ERROR(CheckIdentifiable(
      run.lin.jtj,
      [&] {
        model.Linearize(run.state, nullptr, &s.jacobian);
        return s.jacobian;
      },
      names, what));
  const double scale = model.scale_mm();
  const std::size_t n = model.num_residuals();
  s.stats = MakeStats(run.lin.cost * scale * scale, run.lin.r_min * scale, run.lin.r_max * scale, n, P);
  s.residuals_mm = std::move(run.residuals_mm);
  Eigen::Matrix<double, P, 1> mm_per_unit;
  const auto is_length = model.param_is_length();
  for (int k = 0; k < P; ++k) mm_per_unit[k] = is_length[k] ? scale : 1.0;
  if (options.compute_covariance) s.covariance = CovarianceMm<P>(run.lin, n, mm_per_unit);
  if (!options.keep_jacobian) {
    s.jacobian.resize(0, 0);
  } else if (s.jacobian.rows() == 0) {
    model.Linearize(run.state, nullptr, &s.jacobian);
  }
  s.termination = run.termination;
  s.iterations = run.iterations;
  s.message = std::move(run.message);
  return s;
}

}  // namespace tpcal::fitting::internal
