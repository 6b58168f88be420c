#include "kinematics/datum_ball.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/internal/combination.h"
#include "kinematics/jacobians.h"

namespace tpcal::kinematics {
namespace {

AxisState WithLinear(AxisState axes, const Eigen::Vector3d& xyz_mm) {
  axes.x_mm = xyz_mm.x(), axes.y_mm = xyz_mm.y(), axes.z_mm = xyz_mm.z();
  return axes;
}

// dP/d(X, Y, Z) of the tool point in the part frame, central differences of 1 mm (P is linear in
// the linear commands up to their position-dependent errors, whose curvature over 1 mm is nil).
Eigen::Matrix3d CommandJacobian(const MachineModel& model, const ErrorState& errors, const AxisState& rotary,
                                const Eigen::Vector3d& q, Workspace* ws) {
  Eigen::Matrix3d A;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d(k) = 1.0;
    A.col(k) = 0.5 * (ToolPointInPart(model, errors, WithLinear(rotary, q + d), Eigen::Vector3d::Zero(), ws) -
                      ToolPointInPart(model, errors, WithLinear(rotary, q - d), Eigen::Vector3d::Zero(), ws));
  }
  return A;
}

// The linearised problem at the current errors and ball centre: rows 3 per reading (um), columns
// the active coefficients (display units) then the ball centre (um) when fitted. J_params, J_ball
// and residual are whitened (each reading's rows divided by its weight's u, 1 when unweighted).
struct BallDesign {
  Eigen::MatrixXd J_params, J_ball;
  Eigen::VectorXd residual;     // whitened
  Eigen::VectorXd residual_um;  // measured - model command
};

// 1 / u per reading (all ones when unweighted).
using ReadingWeights = std::vector<double>;

Result<BallDesign> LineariseReadings(const MachineModel& model, const ErrorState& errors, const ActiveSet& active,
                                     const std::vector<double>& scales, std::span<const BallReading> readings,
                                     const ReadingWeights& weights, const Eigen::Vector3d& ball_mm) {
  const Eigen::Index n = static_cast<Eigen::Index>(readings.size()), q = active.size();
  BallDesign d{Eigen::MatrixXd(3 * n, q), Eigen::MatrixXd(3 * n, 3), Eigen::VectorXd(3 * n), Eigen::VectorXd(3 * n)};
  Workspace ws;
  for (Eigen::Index i = 0; i < n; ++i) {
    const BallReading& r = readings[static_cast<std::size_t>(i)];
    auto cmd = BallCentreCommand(model, errors, r.rotary, ball_mm);
    if (!cmd.ok()) return cmd.status().WithLocation("", r.line);
    const Eigen::Matrix3d A_inv = CommandJacobian(model, errors, r.rotary, *cmd, &ws).inverse();
    Eigen::Matrix<double, 3, Eigen::Dynamic> Jp;
    ToolPointJacobian(model, errors, active, WithLinear(r.rotary, *cmd), Eigen::Vector3d::Zero(), &Jp);
    for (Eigen::Index k = 0; k < q; ++k)
      d.J_params.block<3, 1>(3 * i, k) = -MmToUm(1.0) * (A_inv * Jp.col(k)) / scales[static_cast<std::size_t>(k)];
    d.J_ball.block<3, 3>(3 * i, 0) = A_inv;
    d.residual_um.segment<3>(3 * i) = MmToUm(1.0) * (r.command_mm - *cmd);
    const double w = weights[static_cast<std::size_t>(i)];
    d.J_params.middleRows(3 * i, 3) *= w;
    d.J_ball.middleRows(3 * i, 3) *= w;
    d.residual.segment<3>(3 * i) = w * d.residual_um.segment<3>(3 * i);
  }
  return d;
}

// The identifiable directions of the coefficients, the ball centre projected out (as Identify).
struct Directions {
  Eigen::MatrixXd V_r, V_null;  // q x rank, q x (q - rank), display units
  std::vector<double> singular_values;
};

Directions SplitDirections(const BallDesign& d, bool fit_ball, double tolerance) {
  Eigen::MatrixXd X = d.J_params;
  const double largest_column = X.colwise().norm().maxCoeff();
  if (fit_ball) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(d.J_ball);
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(d.J_ball.rows(), 3);
    X -= Q * (Q.transpose() * X);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double reference = std::max(s.size() ? s(0) : 0.0, largest_column);
  Eigen::Index rank = 0;
  while (rank < s.size() && s(rank) > tolerance * reference) ++rank;
  Directions out{svd.matrixV().leftCols(rank), svd.matrixV().rightCols(X.cols() - rank), {}};
  for (Eigen::Index k = 0; k < s.size(); ++k) out.singular_values.push_back(s(k));
  return out;
}

// The reduced design [J_params V_r | J_ball] and its least-squares solution of `rhs`.
Eigen::MatrixXd ReducedDesign(const BallDesign& d, const Directions& dir, bool fit_ball) {
  Eigen::MatrixXd Z(d.J_params.rows(), dir.V_r.cols() + (fit_ball ? 3 : 0));
  Z.leftCols(dir.V_r.cols()) = d.J_params * dir.V_r;
  if (fit_ball) Z.rightCols(3) = d.J_ball;
  return Z;
}

void SetParams(const ActiveSet& active, const std::vector<double>& scales, const Eigen::VectorXd& theta_display,
               ErrorState* errors) {
  for (int k = 0; k < active.size(); ++k)
    errors->set_coefficient(active.coefficients[static_cast<std::size_t>(k)],
                            theta_display(k) / scales[static_cast<std::size_t>(k)]);
}

// Delete one reading (its three rows), linearised at the solution: u per coefficient (display).
Eigen::VectorXd JackknifeReadings(const Eigen::MatrixXd& Z, const Eigen::VectorXd& r, const Eigen::MatrixXd& V_r) {
  const Eigen::Index n = Z.rows() / 3, q = V_r.rows();
  Eigen::MatrixXd thetas(q, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::MatrixXd Zi(Z.rows() - 3, Z.cols());
    Eigen::VectorXd ri(Z.rows() - 3);
    Zi << Z.topRows(3 * i), Z.bottomRows(Z.rows() - 3 * i - 3);
    ri << r.head(3 * i), r.tail(r.size() - 3 * i - 3);
    const Eigen::VectorXd sol = Zi.colPivHouseholderQr().solve(ri);
    thetas.col(i) = V_r * sol.head(V_r.cols());
  }
  const Eigen::VectorXd mean = thetas.rowwise().mean();
  const double f = static_cast<double>(n - 1) / static_cast<double>(n);
  return ((thetas.colwise() - mean).array().square().rowwise().sum() * f).sqrt();
}

void FillIdentifiability(const std::vector<std::string>& names, const Directions& dir, const Eigen::VectorXd& theta,
                         const Eigen::MatrixXd& cov, Identifiability* id) {
  const Eigen::Index q = dir.V_r.rows();
  id->num_parameters = static_cast<int>(q);
  id->rank = static_cast<int>(dir.V_r.cols());
  id->singular_values = dir.singular_values;
  if (id->rank > 0) id->condition_number = dir.singular_values.front() / dir.singular_values[id->rank - 1];
  std::vector<int> subset;
  for (Eigen::Index k = 0; k < q; ++k)
    if (dir.V_null.cols() > 0 && dir.V_null.row(k).norm() > 1e-6) {
      subset.push_back(static_cast<int>(k));
      id->not_identifiable.push_back(names[static_cast<std::size_t>(k)]);
    }
  auto combination = [&](Eigen::VectorXd c) {
    internal::NormaliseCombination(&c);
    Combination out;
    for (Eigen::Index k = 0; k < q; ++k)
      if (c(k) != 0.0) out.names.push_back(names[static_cast<std::size_t>(k)]), out.coefficients.push_back(c(k));
    out.text = internal::FormatCombination(out.names, out.coefficients);
    out.value = c.dot(theta);
    out.u = std::sqrt(std::max(0.0, c.dot(cov * c)));
    return out;
  };
  for (const auto& c : internal::EstimableCombinations(dir.V_null, subset)) id->estimable.push_back(combination(c));
  for (Eigen::Index j = 0; j < dir.V_null.cols(); ++j) id->null_directions.push_back(combination(dir.V_null.col(j)));
}

// The weights of the readings: all u_um > 0 (weighted), all 0 (unweighted), else an error.
Result<ReadingWeights> WeightsOf(std::span<const BallReading> readings, bool* weighted) {
  *weighted = !readings.empty() && readings.front().u_um != 0.0;
  ReadingWeights w;
  for (const BallReading& r : readings) {
    if (!std::isfinite(r.u_um) || r.u_um < 0.0 || (r.u_um != 0.0) != *weighted)
      return Status(StatusCode::kInvalidArgument,
                    "datum ball: u_um " + std::to_string(r.u_um) +
                        ": expected > 0 for every reading (weights) or for none",
                    "", r.line);
    w.push_back(*weighted ? 1.0 / r.u_um : 1.0);
  }
  return w;
}

// Monte Carlo: `runs` whitened noise vectors (sd `noise_scale` per row) mapped through the
// least-squares solution of Z (linearised at the solution) onto the coefficients: q x runs
// deviations from the solution, display units.
Eigen::MatrixXd MonteCarloDeviations(const Eigen::MatrixXd& Z, const Eigen::MatrixXd& V_r, double noise_scale, int runs,
                                     std::uint64_t seed) {
  const Eigen::MatrixXd solve = Z.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(Z.rows(), Z.rows()));
  const Eigen::MatrixXd map = V_r * solve.topRows(V_r.cols());
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd noise(Z.rows(), runs);
  for (int t = 0; t < runs; ++t)
    for (Eigen::Index i = 0; i < Z.rows(); ++i) noise(i, t) = noise_scale * StandardNormal(rng);
  return map * noise;
}

}  // namespace

Result<Eigen::Vector3d> BallCentreCommand(const MachineModel& model, const ErrorState& errors,
                                          const AxisState& rotary, const Eigen::Vector3d& ball_part_mm) {
  Workspace ws;
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int it = 0; it < 20; ++it) {
    const Eigen::Vector3d f =
        ToolPointInPart(model, errors, WithLinear(rotary, q), Eigen::Vector3d::Zero(), &ws) - ball_part_mm;
    if (f.norm() < 1e-9) return q;
    q -= CommandJacobian(model, errors, rotary, q, &ws).partialPivLu().solve(f);
  }
  return Status(StatusCode::kNotConverged, "datum ball: the probe could not be centred on the ball (20 Newton steps)");
}

Result<DatumBallResult> IdentifyDatumBall(const MachineModel& model, std::span<const BallReading> readings,
                                          const DatumBallOptions& options) {
  if (!model.HasAxis(Axis::kC))
    return Status(StatusCode::kInvalidArgument, "datum ball: the machine has no C table");
  if (options.monte_carlo_runs < 0 || options.monte_carlo_runs == 1)
    return Status(StatusCode::kInvalidArgument, "datum ball: monte_carlo_runs must be 0 (off) or >= 2");
  bool weighted = false;
  auto weights = WeightsOf(readings, &weighted);
  if (!weights.ok()) return weights.status();
  ErrorState errors(model);
  auto active = ActivateParameters(model, &errors, options.parameters.empty() ? IsoLocationSet(model) : options.parameters);
  if (!active.ok()) return active.status();
  const bool fit_ball = !options.ball_part_mm.has_value();
  const Eigen::Index q = active->size(), n_rows = 3 * static_cast<Eigen::Index>(readings.size());
  if (n_rows <= q + (fit_ball ? 3 : 0))
    return Status(StatusCode::kTooFewPoints, "datum ball: " + std::to_string(readings.size()) + " readings give " +
                                                 std::to_string(n_rows) + " values for " +
                                                 std::to_string(q + (fit_ball ? 3 : 0)) + " unknowns");
  std::vector<double> scales;
  std::vector<std::string> names;
  for (int c : active->coefficients) {
    scales.push_back(errors.coefficient_info(c).display_per_internal);
    names.push_back(errors.coefficient_info(c).name);
  }
  // Start: zero errors; the ball where the nominal machine sees the mean of the first reading.
  Eigen::Vector3d ball = fit_ball ? NominalToolPointInPart(model, WithLinear(readings.front().rotary,
                                                                             readings.front().command_mm),
                                                           Eigen::Vector3d::Zero())
                                  : *options.ball_part_mm;
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(q);
  DatumBallResult out(errors);
  BallDesign d;
  Directions dir;
  Eigen::MatrixXd Z;
  for (out.iterations = 1; out.iterations <= options.max_iterations; ++out.iterations) {
    SetParams(*active, scales, theta, &errors);
    auto lin = LineariseReadings(model, errors, *active, scales, readings, *weights, ball);
    if (!lin.ok()) return lin.status();
    d = std::move(*lin);
    if (out.iterations == 1) out.rms_before_um = std::sqrt(d.residual_um.squaredNorm() / static_cast<double>(n_rows));
    dir = SplitDirections(d, fit_ball, options.rank_tolerance);
    if (dir.V_r.cols() == 0) return Status(StatusCode::kNotIdentifiable, "datum ball: no error is identifiable from these readings");
    Z = ReducedDesign(d, dir, fit_ball);
    const Eigen::VectorXd step = Z.colPivHouseholderQr().solve(d.residual);
    theta += dir.V_r * step.head(dir.V_r.cols());
    if (fit_ball) ball += UmToMm(1.0) * step.tail(3);
    if (step.norm() < 1e-7) break;
  }
  // At the solution: residuals, sigma and the uncertainties.
  SetParams(*active, scales, theta, &errors);
  auto lin = LineariseReadings(model, errors, *active, scales, readings, *weights, ball);
  if (!lin.ok()) return lin.status();
  d = std::move(*lin);
  Z = ReducedDesign(d, dir, fit_ball);
  const double dof = static_cast<double>(n_rows - Z.cols());
  out.sigma_um = std::sqrt(d.residual_um.squaredNorm() / dof);
  out.rms_after_um = std::sqrt(d.residual_um.squaredNorm() / static_cast<double>(n_rows));
  out.weighted = weighted;
  if (weighted) out.chi_scale = std::sqrt(d.residual.squaredNorm() / dof);
  const double scale = weighted ? out.chi_scale : out.sigma_um;
  const Eigen::MatrixXd C = scale * scale * (Z.transpose() * Z).inverse();
  const Eigen::MatrixXd cov = dir.V_r * C.topLeftCorner(dir.V_r.cols(), dir.V_r.cols()) * dir.V_r.transpose();
  const Eigen::VectorXd jack = options.jackknife ? JackknifeReadings(Z, d.residual, dir.V_r) : Eigen::VectorXd();
  // Noise of the re-simulated readings: u_um (whitened: 1) when weighted, else the fitted sigma.
  out.monte_carlo_runs = options.monte_carlo_runs;
  const Eigen::MatrixXd mc = options.monte_carlo_runs > 0
                                 ? MonteCarloDeviations(Z, dir.V_r, weighted ? 1.0 : out.sigma_um,
                                                        options.monte_carlo_runs, options.monte_carlo_seed)
                                 : Eigen::MatrixXd();
  FillIdentifiability(names, dir, theta, cov, &out.identifiability);
  for (Eigen::Index k = 0; k < q; ++k) {
    ParameterEstimate p;
    p.name = names[static_cast<std::size_t>(k)];
    auto info = LookupParameter(model, p.name);
    p.iso_symbol = info.ok() ? info->iso_symbol : std::string();
    p.unit = errors.coefficient_info(active->coefficients[static_cast<std::size_t>(k)]).unit;
    p.identifiable = std::find(out.identifiability.not_identifiable.begin(), out.identifiability.not_identifiable.end(),
                               p.name) == out.identifiability.not_identifiable.end();
    p.value = theta(k);
    p.uncertainties.push_back(MakeUncertainty(UncertaintyMethod::kAnalytic, p.value, std::sqrt(cov(k, k)), dof));
    if (options.jackknife)
      p.uncertainties.push_back(MakeUncertainty(UncertaintyMethod::kJackknifePoints, p.value, jack(k), dof));
    if (mc.size() > 0)
      p.uncertainties.push_back(MonteCarloUncertainty(p.value, std::vector<double>(mc.row(k).begin(), mc.row(k).end())));
    p.u = p.uncertainties.front().u;
    p.ci95_low = p.uncertainties.front().ci95_low, p.ci95_high = p.uncertainties.front().ci95_high;
    out.parameters.push_back(std::move(p));
  }
  out.covariance = cov;
  out.fitted = errors;
  out.ball_part_mm = ball;
  if (fit_ball)
    for (int k = 0; k < 3; ++k) out.ball_u_um(k) = std::sqrt(C(Z.cols() - 3 + k, Z.cols() - 3 + k));
  for (Eigen::Index i = 0; i < n_rows / 3; ++i) out.residuals_um.push_back(d.residual_um.segment<3>(3 * i));
  return out;
}

}  // namespace tpcal::kinematics
