#include "pipeline/diagnosis/diagnosis_reference_nuisance.h"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

namespace tpcal::pipeline::diagnosis_internal {
namespace {

// A factor L of the covariance S = L L^T (eigenvectors scaled by the root of their non-negative
// eigenvalues: S may be singular, e.g. the maps' reference pose).
Eigen::MatrixXd CovarianceFactor(const Eigen::MatrixXd& S) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (S + S.transpose()));
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

// M with its component in the column space of A removed.
Eigen::MatrixXd OffSpanOf(const Eigen::MatrixXd& A, const Eigen::MatrixXd& M) {
  if (A.cols() == 0) return M;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(A.rows(), qr.rank());
  return M - Q * (Q.transpose() * M);
}

}  // namespace

Result<ReferenceNuisance> ReferenceNuisanceColumns(const kinematics::MachineModel& machine,
                                                   const kinematics::ErrorState& reference,
                                                   std::span<const kinematics::Observation> observations,
                                                   const Eigen::MatrixXd& held_design,
                                                   const ReferenceUncertainty& uncertainty, double ratio) {
  const auto m = static_cast<Eigen::Index>(uncertainty.names.size());
  if (uncertainty.covariance.rows() != m || uncertainty.covariance.cols() != m || !uncertainty.covariance.allFinite())
    return Status(StatusCode::kInvalidArgument, "reference uncertainty: a finite " + std::to_string(m) + " x " +
                                                    std::to_string(m) + " covariance expected");
  if (!(uncertainty.noise_um > 0.0)) return Status(StatusCode::kInvalidArgument, "reference uncertainty: noise must be > 0 um");
  const auto n = static_cast<Eigen::Index>(observations.size());
  if (held_design.rows() != n)
    return Status(StatusCode::kInvalidArgument, "reference uncertainty: the held design has " +
                                                    std::to_string(held_design.rows()) + " rows for " +
                                                    std::to_string(n) + " observations");
  if (m == 0) return ReferenceNuisance{Eigen::MatrixXd(n, 0), Eigen::MatrixXd(n, 0)};
  kinematics::ErrorState at = reference;
  auto active = kinematics::ActivateParameters(machine, &at, uncertainty.names);
  if (!active.ok()) return active.status();
  auto lin = kinematics::LineariseObservations(machine, at, *active, observations);
  if (!lin.ok()) return lin.status();
  const Eigen::MatrixXd B = OffSpanOf(held_design, lin->J_dev_params) * CovarianceFactor(uncertainty.covariance);
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinU);
  const double floor_um2 = ratio * uncertainty.noise_um * uncertainty.noise_um;
  const Eigen::VectorXd& s = svd.singularValues();
  const Eigen::Index k_max = std::max<Eigen::Index>(0, n / 2 - held_design.cols());
  Eigen::Index k = 0;
  while (k < s.size() && k < k_max && s(k) * s(k) > floor_um2) ++k;
  const Eigen::Index r = s.size() - k;
  ReferenceNuisance out;
  out.columns_um = svd.matrixU().leftCols(k) * s.head(k).asDiagonal();
  out.remaining_um = svd.matrixU().middleCols(k, r) * s.tail(r).asDiagonal();
  return out;
}

}  // namespace tpcal::pipeline::diagnosis_internal
