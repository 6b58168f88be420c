#include "kinematics/prior_update.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

namespace tpcal::kinematics {
namespace {

// (I - P_A) M: M with its component in the column space of A removed (A full column rank or not).
Eigen::MatrixXd WithoutSpanOf(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M) {
  if (A.cols() == 0) return M;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(A.rows(), qr.rank());
  return M - Q * (Q.transpose() * M);
}

// Information of the prior: 1 / u^2 where it knows the coefficient, 0 where it does not.
Eigen::VectorXd PriorInformation(std::span<const double> prior_u) {
  Eigen::VectorXd info(static_cast<Eigen::Index>(prior_u.size()));
  for (std::size_t k = 0; k < prior_u.size(); ++k) {
    const double u = prior_u[k];
    info(static_cast<Eigen::Index>(k)) = (std::isfinite(u) && u > 0.0) ? 1.0 / (u * u) : 0.0;
  }
  return info;
}

// Information of a prior known by its covariance: its pseudo-inverse, nothing along the directions
// it does not determine (eigenvalues below 1e-12 of the largest: rounding of a zero).
Result<Eigen::MatrixXd> CovarianceInformation(const Eigen::MatrixXd& cov) {
  if (cov.size() == 0) return cov;
  if (!cov.allFinite() || (cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * cov.cwiseAbs().maxCoeff())
    return Status(StatusCode::kInvalidArgument, "prior update: the prior's covariance is not finite and symmetric");
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double top = lambda.maxCoeff();
  if (lambda.minCoeff() < -1e-9 * top)
    return Status(StatusCode::kInvalidArgument, "prior update: the prior's covariance is not positive semi-definite");
  Eigen::MatrixXd info = Eigen::MatrixXd::Zero(cov.rows(), cov.cols());
  for (Eigen::Index k = 0; k < lambda.size(); ++k)
    if (lambda(k) > 1e-12 * top) info += eig.eigenvectors().col(k) * eig.eigenvectors().col(k).transpose() / lambda(k);
  return info;
}

// Coefficients the piece or the prior sees, each judged against its own best-seen coefficient
// (information above 1e-6 of it: u less than 1000x the best's, as Identify's rank tolerance 1e-3).
// Each on its own scale: a prior far tighter on one coefficient than the piece on any does not hide
// what the piece sees. The piece sees a coefficient only where the re-alignment leaves more than
// 1e-6 of its column's norm (`raw_piece_diag`: the information before the re-alignment is projected
// out), so rounding is not taken for a signal when the re-alignment absorbs every one. The others
// are left at the prior.
std::vector<Eigen::Index> SeenCoefficients(const Eigen::MatrixXd& piece_info, const Eigen::VectorXd& raw_piece_diag,
                                           const Eigen::MatrixXd& prior_info) {
  constexpr double kUnseen = 1e-6, kAbsorbed = 1e-12;
  const Eigen::Index n = piece_info.rows();
  std::vector<Eigen::Index> seen;
  if (n == 0) return seen;
  const double piece_best = piece_info.diagonal().maxCoeff(), prior_best = prior_info.diagonal().maxCoeff();
  for (Eigen::Index k = 0; k < n; ++k) {
    const bool by_piece = piece_info(k, k) > kUnseen * piece_best && piece_info(k, k) > kAbsorbed * raw_piece_diag(k);
    if (by_piece || prior_info(k, k) > kUnseen * prior_best) seen.push_back(k);
  }
  return seen;
}

Result<PriorUpdate> UpdateWithInformation(const MachineModel& model, const ErrorState& prior, const ActiveSet& active,
                                          const Eigen::MatrixXd& prior_info, std::span<const Observation> observations,
                                          double sigma_um) {
  if (!(sigma_um > 0.0)) return Status(StatusCode::kInvalidArgument, "prior update: noise sigma must be > 0 um");
  if (observations.empty()) return Status(StatusCode::kInvalidArgument, "prior update: no observation");
  auto lin = LineariseObservations(model, prior, active, observations);
  if (!lin.ok()) return lin.status();
  const Eigen::MatrixXd J = WithoutSpanOf(lin->J_dev_alignment, lin->J_dev_params);
  const Eigen::VectorXd y = WithoutSpanOf(lin->J_dev_alignment, lin->measured_dev_um - lin->predicted_dev_um);
  const double w = 1.0 / (sigma_um * sigma_um);
  const Eigen::MatrixXd piece_info = w * J.transpose() * J;
  const Eigen::MatrixXd info = piece_info + prior_info;
  const Eigen::VectorXd raw_piece_diag = w * lin->J_dev_params.colwise().squaredNorm().transpose();
  const std::vector<Eigen::Index> seen = SeenCoefficients(piece_info, raw_piece_diag, prior_info);
  const auto q = static_cast<Eigen::Index>(seen.size());
  Eigen::MatrixXd info_seen(q, q);
  Eigen::VectorXd rhs_seen(q);
  const Eigen::VectorXd rhs = w * J.transpose() * y;
  for (Eigen::Index i = 0; i < q; ++i) {
    rhs_seen(i) = rhs(seen[i]);
    for (Eigen::Index j = 0; j < q; ++j) info_seen(i, j) = info(seen[i], seen[j]);
  }
  // Jacobi-scaled so the rank threshold is relative to each coefficient's own information.
  const Eigen::VectorXd d = info_seen.diagonal().cwiseSqrt().cwiseInverse();
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(1e-9);  // before compute: the rank it finds shapes the decomposition
  cod.compute(d.asDiagonal() * info_seen * d.asDiagonal());
  const Eigen::VectorXd delta_seen = d.asDiagonal() * cod.solve(d.asDiagonal() * rhs_seen);
  const Eigen::MatrixXd cov_seen = d.asDiagonal() * cod.pseudoInverse() * d.asDiagonal();
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(info.rows()), var = Eigen::VectorXd::Zero(info.rows());
  for (Eigen::Index i = 0; i < q; ++i) delta(seen[i]) = delta_seen(i), var(seen[i]) = cov_seen(i, i);
  PriorUpdate out(prior);
  for (int k = 0; k < active.size(); ++k) {
    const int c = active.coefficients[static_cast<std::size_t>(k)];
    const double per = prior.coefficient_info(c).display_per_internal;
    out.posterior.set_coefficient(c, prior.coefficient(c) + delta(k) / per);
    out.delta.push_back(delta(k));
    out.posterior_u.push_back(std::sqrt(std::max(0.0, var(k))));
  }
  return out;
}

}  // namespace

Result<PriorUpdate> UpdateWithinPrior(const MachineModel& model, const ErrorState& prior, const ActiveSet& active,
                                      std::span<const double> prior_u, std::span<const Observation> observations,
                                      double sigma_um) {
  if (prior_u.size() != active.coefficients.size())
    return Status(StatusCode::kInvalidArgument, "prior update: " + std::to_string(prior_u.size()) +
                                                    " uncertainties for " + std::to_string(active.size()) + " coefficients");
  const Eigen::MatrixXd info = PriorInformation(prior_u).asDiagonal();
  return UpdateWithInformation(model, prior, active, info, observations, sigma_um);
}

Result<PriorUpdate> UpdateWithinPriorCovariance(const MachineModel& model, const ErrorState& prior,
                                                const ActiveSet& active, const Eigen::MatrixXd& prior_cov,
                                                std::span<const Observation> observations, double sigma_um) {
  const auto q = static_cast<Eigen::Index>(active.coefficients.size());
  if (prior_cov.rows() != q || prior_cov.cols() != q)
    return Status(StatusCode::kInvalidArgument, "prior update: a " + std::to_string(prior_cov.rows()) + " x " +
                                                    std::to_string(prior_cov.cols()) + " covariance for " +
                                                    std::to_string(q) + " coefficients");
  auto info = CovarianceInformation(prior_cov);
  if (!info.ok()) return info.status();
  return UpdateWithInformation(model, prior, active, *info, observations, sigma_um);
}

}  // namespace tpcal::kinematics
