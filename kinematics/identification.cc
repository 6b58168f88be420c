#include "kinematics/identification.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>

#include "core/parallel.h"
#include "core/tall_svd.h"
#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/internal/combination.h"
#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics {
namespace {

using internal::FormatCombination;
using internal::NormaliseCombination;

// Nuisance columns are scaled to um per urad (rotation) and um per um (translation).
constexpr int kNuisance = 6;
constexpr double kUmPerUradPerMm = 1e-3;  // a rotation of 1 urad moves a point at 1 mm by 1e-3 um

Eigen::Matrix3d RotationFromUrad(const double* w_urad) {
  const Eigen::Vector3d w = Eigen::Vector3d(w_urad[0], w_urad[1], w_urad[2]) * 1e-6;
  const double a = w.norm();
  if (a == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

// Display units per internal unit of every active coefficient.
std::vector<double> DisplayScales(const ErrorState& errors, const ActiveSet& active) {
  std::vector<double> s;
  s.reserve(active.coefficients.size());
  for (int c : active.coefficients) s.push_back(errors.coefficient_info(c).display_per_internal);
  return s;
}

// Catalog symbol of a coefficient (only constant catalog parameters carry one).
std::string IsoSymbolOf(const MachineModel& model, const std::string& name) {
  auto info = LookupParameter(model, name);
  return info.ok() ? info->iso_symbol : std::string();
}

// Per-point loops: on up to HardwareThreads() threads, one per 2048 points (core/parallel.h).
bool ParallelChunks(std::size_t n, const std::function<bool(std::size_t, std::size_t)>& fn) {
  return tpcal::ParallelChunks(n, 2048, fn);
}

// Orthonormal basis of the nuisance columns (n x 6) or an empty matrix.
Eigen::MatrixXd NuisanceBasis(const Eigen::MatrixXd& N) {
  if (N.cols() == 0) return N;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(N);
  return qr.householderQ() * Eigen::MatrixXd::Identity(N.rows(), N.cols());
}

// Row weights of weighted least squares, 1 / Observation::noise_scale; empty when every scale is
// 1 (probe hits: ordinary least squares, with the same arithmetic).
Eigen::VectorXd RowWeights(std::span<const Observation> observations) {
  const bool weighted = std::any_of(observations.begin(), observations.end(), [](const Observation& o) {
    return o.noise_scale != 1.0;
  });
  if (!weighted) return {};
  Eigen::VectorXd w(static_cast<Eigen::Index>(observations.size()));
  for (std::size_t i = 0; i < observations.size(); ++i) w(static_cast<Eigen::Index>(i)) = 1.0 / observations[i].noise_scale;
  return w;
}

// The last evaluation with Jacobians: its parameters, residuals and Jacobian blocks (Ceres
// layout, row-major), so that the linearisation at the solution can reuse it when Ceres stopped
// at that very point.
struct JacobianCapture {
  std::vector<double> z, xi;
  std::vector<double> residuals_um, J_z, J_xi;
  bool valid = false;
};

// All residuals of the problem as one Ceres block: parameters z (reduced coefficients, display
// units along the identifiable directions) and xi (w urad, t um). At z = 0, xi = 0 (the base
// errors, no re-alignment: exactly the point of `lin0`) the values and Jacobians are taken from
// lin0 instead of another pass over the points.
class PointResiduals final : public ceres::CostFunction {
 public:
  PointResiduals(const MachineModel& model, const ErrorState& base, const ActiveSet& active,
                 std::span<const Observation> obs, const Eigen::MatrixXd& V_r,
                 const std::vector<double>& scales, bool with_alignment, const LinearDesign* lin0,
                 const Eigen::VectorXd& weights, JacobianCapture* capture)
      : model_(model), base_(base), active_(active), obs_(obs), V_r_(V_r), scales_(scales),
        with_alignment_(with_alignment), lin0_(lin0), weights_(weights), capture_(capture), work_(base) {
    set_num_residuals(static_cast<int>(obs.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(V_r.cols()));
    if (with_alignment) mutable_parameter_block_sizes()->push_back(kNuisance);
  }

  // Passes over the points that evaluated the Jacobian.
  int jacobian_passes() const { return jacobian_passes_; }

  // Coefficient values (internal units) for reduced coordinates z.
  void SetCoefficients(const double* z, ErrorState* e) const {
    const Eigen::Map<const Eigen::VectorXd> zz(z, V_r_.cols());
    const Eigen::VectorXd theta_disp = V_r_ * zz;
    for (int k = 0; k < active_.size(); ++k) {
      const int c = active_.coefficients[k];
      e->set_coefficient(c, base_.coefficient(c) + theta_disp(k) / scales_[k]);
    }
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const bool ok = IsBase(parameters) && lin0_ ? FromLin0(residuals, jacobians)
                                                : EvaluatePoints(parameters, residuals, jacobians);
    if (ok && weights_.size() > 0) Weigh(residuals, jacobians);
    if (ok && jacobians && capture_) Capture(parameters, residuals, jacobians);
    return ok;
  }

 private:
  bool IsBase(double const* const* parameters) const {
    for (Eigen::Index j = 0; j < V_r_.cols(); ++j)
      if (parameters[0][j] != 0.0) return false;
    if (with_alignment_)
      for (int k = 0; k < kNuisance; ++k)
        if (parameters[1][k] != 0.0) return false;
    return true;
  }

  // The same quantities as EvaluatePoints at z = 0, xi = 0 (to rounding), from lin0.
  bool FromLin0(double* residuals, double** jacobians) const {
    const Eigen::Index n = static_cast<Eigen::Index>(obs_.size()), r = V_r_.cols();
    for (Eigen::Index i = 0; i < n; ++i) residuals[i] = lin0_->measured_dev_um(i) - lin0_->predicted_dev_um(i);
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[0], n, r);
      J.noalias() = lin0_->J_dev_params * (-V_r_);
    }
    if (with_alignment_ && jacobians && jacobians[1]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kNuisance, Eigen::RowMajor>> J(jacobians[1], n, kNuisance);
      J = lin0_->J_dev_alignment;
    }
    return true;
  }

  // Rows times their weights (weighted least squares).
  void Weigh(double* residuals, double** jacobians) const {
    const std::size_t r = static_cast<std::size_t>(V_r_.cols());
    for (std::size_t i = 0; i < obs_.size(); ++i) {
      const double w = weights_(static_cast<Eigen::Index>(i));
      residuals[i] *= w;
      if (jacobians && jacobians[0])
        for (std::size_t j = 0; j < r; ++j) jacobians[0][i * r + j] *= w;
      if (with_alignment_ && jacobians && jacobians[1])
        for (int k = 0; k < kNuisance; ++k) jacobians[1][i * kNuisance + static_cast<std::size_t>(k)] *= w;
    }
  }

  void Capture(double const* const* parameters, const double* residuals, double** jacobians) const {
    const std::size_t n = obs_.size(), r = static_cast<std::size_t>(V_r_.cols());
    capture_->z.assign(parameters[0], parameters[0] + r);
    capture_->xi.clear();
    if (with_alignment_) capture_->xi.assign(parameters[1], parameters[1] + kNuisance);
    capture_->residuals_um.assign(residuals, residuals + n);
    capture_->J_z.clear();
    capture_->J_xi.clear();
    if (jacobians[0]) capture_->J_z.assign(jacobians[0], jacobians[0] + n * r);
    if (with_alignment_ && jacobians[1]) capture_->J_xi.assign(jacobians[1], jacobians[1] + n * kNuisance);
    capture_->valid = jacobians[0] && (!with_alignment_ || jacobians[1]);
  }

  bool EvaluatePoints(double const* const* parameters, double* residuals, double** jacobians) const {
    if (jacobians && jacobians[0]) ++jacobian_passes_;
    SetCoefficients(parameters[0], &work_);
    const double* xi = with_alignment_ ? parameters[1] : nullptr;
    const Eigen::Matrix3d R = xi ? RotationFromUrad(xi) : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d t_mm = xi ? Eigen::Vector3d(Eigen::Vector3d(xi[3], xi[4], xi[5]) * 1e-3) : Eigen::Vector3d::Zero();
    const Eigen::Index r = V_r_.cols();
    // The surface points depend on z only: Ceres evaluates the residuals at a candidate and, once
    // it accepts it, the Jacobian at the same z; the second call reuses the first's solutions.
    const std::size_t z_bytes = static_cast<std::size_t>(r) * sizeof(double);
    const bool reuse = solved_z_.size() == static_cast<std::size_t>(r) && solved_.size() == obs_.size() &&
                       std::memcmp(solved_z_.data(), parameters[0], z_bytes) == 0;
    if (!reuse) {
      solved_z_.clear();
      solved_.resize(obs_.size());
    }
    const bool ok = ParallelChunks(obs_.size(), [&](std::size_t begin, std::size_t end) {
      Workspace ws;
      for (std::size_t i = begin; i < end; ++i) {
        const Observation& o = obs_[i];
        const Eigen::Vector3d& n0 = o.cut.nominal_normal;
        const Eigen::Vector3d m = R * o.measured_mm + t_mm;
        if (!reuse) {
          auto solved = SimulateSurfacePoint(model_, work_, o.cut, &ws);
          if (!solved.ok()) return false;
          solved_[i] = *solved;
        }
        const SurfacePoint* sp = &solved_[i];
        residuals[i] = MmToUm(n0.dot(m - o.cut.nominal_point_mm) - sp->deviation_mm);
        if (jacobians && jacobians[0]) {
          auto row = SurfaceDeviationJacobian(model_, work_, active_, o.cut, *sp);
          if (!row.ok()) return false;
          for (Eigen::Index j = 0; j < r; ++j) {
            double d = 0.0;
            for (int k = 0; k < active_.size(); ++k) d += (*row)(k) / scales_[k] * V_r_(k, j);
            jacobians[0][i * r + j] = -MmToUm(d);
          }
        }
        if (with_alignment_ && jacobians && jacobians[1]) {
          const Eigen::Vector3d mxn = m.cross(n0);
          double* J = jacobians[1] + i * kNuisance;
          for (int k = 0; k < 3; ++k) J[k] = MmToUm(mxn(k)) * 1e-6;  // per urad
          for (int k = 0; k < 3; ++k) J[3 + k] = n0(k);              // um per um
        }
      }
      return true;
    });
    if (ok && !reuse) solved_z_.assign(parameters[0], parameters[0] + r);
    return ok;
  }

 private:
  const MachineModel& model_;
  const ErrorState& base_;
  const ActiveSet& active_;
  std::span<const Observation> obs_;
  const Eigen::MatrixXd& V_r_;
  const std::vector<double>& scales_;
  bool with_alignment_;
  const LinearDesign* lin0_;
  const Eigen::VectorXd& weights_;  // empty: none
  JacobianCapture* capture_;
  mutable ErrorState work_;
  mutable int jacobian_passes_ = 0;
  mutable std::vector<double> solved_z_;      // z of solved_ (empty: none)
  mutable std::vector<SurfacePoint> solved_;  // per observation
};

}  // namespace

Uncertainty MakeUncertainty(UncertaintyMethod m, double value, double u, double nu) {
  Uncertainty out;
  out.method = m;
  out.available = std::isfinite(u);
  out.u = u;
  const double k95 = internal::StudentTQuantile975(nu);
  out.ci95_low = value - k95 * u;
  out.ci95_high = value + k95 * u;
  return out;
}

Uncertainty MonteCarloUncertainty(double value, std::vector<double> draws) {
  Uncertainty out;
  out.method = UncertaintyMethod::kMonteCarlo;
  if (draws.size() < 2) {
    out.message = "fewer than 2 Monte Carlo draws";
    return out;
  }
  std::sort(draws.begin(), draws.end());
  double mean = 0, ss = 0;
  for (double d : draws) mean += d;
  mean /= static_cast<double>(draws.size());
  for (double d : draws) ss += (d - mean) * (d - mean);
  out.available = true;
  out.u = std::sqrt(ss / static_cast<double>(draws.size() - 1));
  const auto lo = static_cast<std::size_t>(std::floor(0.025 * static_cast<double>(draws.size())));
  const auto hi = std::min(draws.size() - 1, static_cast<std::size_t>(std::ceil(0.975 * static_cast<double>(draws.size()))));
  out.ci95_low = value + draws[lo];
  out.ci95_high = value + draws[hi];
  return out;
}

const char* UncertaintyMethodName(UncertaintyMethod m) {
  switch (m) {
    case UncertaintyMethod::kAnalytic: return "analytic";
    case UncertaintyMethod::kJackknifePoints: return "jackknife_points";
    case UncertaintyMethod::kJackknifeGroups: return "jackknife_groups";
    case UncertaintyMethod::kMonteCarlo: return "monte_carlo";
    case UncertaintyMethod::kRandomSubsets: return "random_subsets";
  }
  return "unknown";
}

Status IdentifyOptions::Validate() const {
  if (max_iterations < 1) return {StatusCode::kInvalidArgument, "max_iterations must be >= 1"};
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1.0))
    return {StatusCode::kInvalidArgument, "rank_tolerance must be in (0, 1)"};
  if (monte_carlo_trials < 0) return {StatusCode::kInvalidArgument, "monte_carlo_trials must be >= 0"};
  if (random_subset_trials < 0 || random_subset_size < 1)
    return {StatusCode::kInvalidArgument, "random_subset_trials must be >= 0 and random_subset_size >= 1"};
  if (primary == UncertaintyMethod::kRandomSubsets && random_subset_trials < 20)
    return {StatusCode::kInvalidArgument, "the random-subset method needs random_subset_trials >= 20"};
  if (primary == UncertaintyMethod::kMonteCarlo && monte_carlo_trials < 100)
    return {StatusCode::kInvalidArgument, "the Monte Carlo method needs monte_carlo_trials >= 100"};
  if (primary == UncertaintyMethod::kJackknifeGroups && !jackknife_groups)
    return {StatusCode::kInvalidArgument, "primary method jackknife_groups needs jackknife_groups = true"};
  return {};
}

namespace {

// The design with `q` parameter columns: row(o, sp) returns d s / d parameter (mm per internal
// unit) at the solution sp of observation o; column k is then scaled by 1000 / scales[k] (um per
// display unit).
template <typename RowFn>
Result<LinearDesign> LineariseWith(const MachineModel& model, const ErrorState& errors, int q,
                                   const std::vector<double>& scales, std::span<const Observation> observations,
                                   const RowFn& row_of) {
  const auto n = static_cast<Eigen::Index>(observations.size());
  LinearDesign d;
  d.J_dev_params.resize(n, q);
  d.J_dev_alignment.resize(n, kNuisance);
  d.measured_dev_um.resize(n);
  d.predicted_dev_um.resize(n);
  std::vector<Status> failures(observations.size() ? 1 : 0);
  std::mutex failure_mutex;
  const bool all_ok = ParallelChunks(observations.size(), [&](std::size_t begin, std::size_t end) {
    Workspace ws;
    for (std::size_t ii = begin; ii < end; ++ii) {
      const auto i = static_cast<Eigen::Index>(ii);
      const Observation& o = observations[ii];
      auto sp = SimulateSurfacePoint(model, errors, o.cut, &ws);
      Result<Eigen::RowVectorXd> row = Status(StatusCode::kInternal, "");
      if (sp.ok()) row = row_of(o, *sp);
      if (!sp.ok() || !row.ok()) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        failures[0] = (sp.ok() ? row.status() : sp.status()).WithContext("observation " + std::to_string(ii));
        return false;
      }
      for (int k = 0; k < q; ++k) d.J_dev_params(i, k) = MmToUm((*row)(k)) / scales[static_cast<std::size_t>(k)];
      const Eigen::Vector3d& n0 = o.cut.nominal_normal;
      const Eigen::Vector3d mxn = o.measured_mm.cross(n0);
      for (int k = 0; k < 3; ++k) d.J_dev_alignment(i, k) = mxn(k) * kUmPerUradPerMm;
      for (int k = 0; k < 3; ++k) d.J_dev_alignment(i, 3 + k) = n0(k);
      d.measured_dev_um(i) = MmToUm(n0.dot(o.measured_mm - o.cut.nominal_point_mm));
      d.predicted_dev_um(i) = MmToUm(sp->deviation_mm);
    }
    return true;
  });
  if (!all_ok) return failures[0];
  return d;
}

}  // namespace

Result<LinearDesign> LineariseObservations(const MachineModel& model, const ErrorState& errors,
                                           const ActiveSet& active, std::span<const Observation> observations) {
  return LineariseWith(model, errors, active.size(), DisplayScales(errors, active), observations,
                       [&](const Observation& o, const SurfacePoint& sp) {
                         return SurfaceDeviationJacobian(model, errors, active, o.cut, sp);
                       });
}

Result<LinearDesign> LineariseSlotObservations(const MachineModel& model, const ErrorState& errors,
                                               std::span<const ErrorSlot> slots,
                                               std::span<const Observation> observations) {
  for (const ErrorSlot& s : slots)
    if (!model.HasAxis(s.axis))
      return Status(StatusCode::kInvalidArgument, std::string("error slot on axis ") + AxisLetter(s.axis) +
                                                      ", which the machine does not have");
  return LineariseWith(model, errors, static_cast<int>(slots.size()), std::vector<double>(slots.size(), 1.0),
                       observations, [&](const Observation& o, const SurfacePoint& sp) {
                         return SurfaceDeviationSlotJacobian(model, errors, slots, o.cut, sp);
                       });
}

Result<IdentificationResult> Identify(const MachineModel& model, const ErrorState& base,
                                      const ActiveSet& active, std::span<const Observation> observations,
                                      const IdentifyOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (active.size() == 0) return Status(StatusCode::kInvalidArgument, "no error coefficient to identify");
  const int q = active.size();
  const int nq = q + (options.fit_alignment ? kNuisance : 0);
  const auto n = static_cast<Eigen::Index>(observations.size());
  if (n <= nq)
    return Status(StatusCode::kTooFewPoints, "identification of " + std::to_string(q) + " coefficients" +
                                                 (options.fit_alignment ? " and the 6 alignment terms" : "") +
                                                 " needs more than " + std::to_string(nq) + " points, got " +
                                                 std::to_string(n));
  for (std::size_t i = 0; i < observations.size(); ++i)
    if (!(observations[i].noise_scale > 0.0) || !std::isfinite(observations[i].noise_scale))
      return Status(StatusCode::kInvalidArgument,
                    "identification: observation " + std::to_string(i) + " has a noise_scale that is not positive and finite");
  const std::vector<double> scales = DisplayScales(base, active);

  // 1. Identifiability at the base errors.
  Result<LinearDesign> lin0_made = Status(StatusCode::kInternal, "not made");
  const LinearDesign* lin0 = options.initial_design.get();
  if (lin0) {
    if (lin0->J_dev_params.rows() != n || lin0->J_dev_params.cols() != q || lin0->J_dev_alignment.rows() != n ||
        lin0->measured_dev_um.size() != n || lin0->predicted_dev_um.size() != n)
      return Status(StatusCode::kInvalidArgument, "identification: the initial design does not match the " +
                                                      std::to_string(n) + " observations and " + std::to_string(q) +
                                                      " coefficients");
  } else {
    lin0_made = LineariseObservations(model, base, active, observations);
    if (!lin0_made.ok()) return lin0_made.status();
    lin0 = &*lin0_made;
  }
  // Weighted least squares when the observations' noise differs (pooled scan cells): every row of
  // the design and of the residuals times 1 / noise_scale, so sigma is one hit's.
  const Eigen::VectorXd w = RowWeights(observations);
  Eigen::MatrixXd A = w.size() > 0 ? Eigen::MatrixXd(w.asDiagonal() * lin0->J_dev_params) : lin0->J_dev_params;
  // Rank relative to the columns before the alignment took its share: a coefficient the
  // re-alignment absorbs whole leaves only rounding, which must not count even when it is all
  // that is left (relative to the projected columns alone it would).
  const double column_scale = A.colwise().norm().maxCoeff();
  if (options.fit_alignment) {
    const Eigen::MatrixXd Q = NuisanceBasis(w.size() > 0 ? Eigen::MatrixXd(w.asDiagonal() * lin0->J_dev_alignment)
                                                         : lin0->J_dev_alignment);
    A -= Q * (Q.transpose() * A);
  }
  const TallSvdResult svd = TallSvd(A, /*compute_u=*/false);
  const double smax = svd.sigma.size() ? svd.sigma(0) : 0.0;
  const double scale = std::max(smax, column_scale);
  int rank = 0;
  for (Eigen::Index k = 0; k < svd.sigma.size(); ++k)
    if (svd.sigma(k) > options.rank_tolerance * scale) ++rank;
  if (rank == 0)
    return Status(StatusCode::kNotIdentifiable, "the measured points do not depend on any of the " +
                                                     std::to_string(q) + " coefficients");
  const Eigen::MatrixXd V_r = svd.V.leftCols(rank);
  const Eigen::MatrixXd V_n = svd.V.rightCols(q - rank);

  IdentificationResult out(base);
  out.num_observations = static_cast<std::size_t>(n);
  {
    std::map<int, int> groups;
    for (const auto& o : observations) groups[o.group] = 1;
    out.num_groups = static_cast<int>(groups.size());
  }
  Identifiability& idf = out.identifiability;
  idf.num_parameters = q;
  idf.rank = rank;
  idf.condition_number = smax / svd.sigma(rank - 1);
  idf.singular_values.assign(svd.sigma.data(), svd.sigma.data() + svd.sigma.size());
  std::vector<std::string> names(static_cast<std::size_t>(q));
  std::vector<bool> identifiable(static_cast<std::size_t>(q), true);
  for (int k = 0; k < q; ++k) {
    names[k] = base.coefficient_info(active.coefficients[k]).name;
    if (V_n.cols() > 0 && V_n.row(k).norm() > 1e-6) identifiable[k] = false;
  }
  {
    Eigen::VectorXd r0 = lin0->measured_dev_um - lin0->predicted_dev_um;
    out.rms_before_um = std::sqrt(r0.squaredNorm() / static_cast<double>(n));
  }

  // 2. Nonlinear least squares (Ceres) in the identifiable directions and the nuisance.
  std::vector<double> z(static_cast<std::size_t>(rank), 0.0);
  std::vector<double> xi(kNuisance, 0.0);
  JacobianCapture capture;
  out.jacobian_passes = options.initial_design ? 0 : 1;  // lin0
  {
    ceres::Problem::Options popt;
    popt.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    auto* cost = new PointResiduals(model, base, active, observations, V_r, scales, options.fit_alignment,
                                    lin0, w, &capture);
    if (options.fit_alignment) {
      problem.AddResidualBlock(cost, nullptr, z.data(), xi.data());
    } else {
      problem.AddResidualBlock(cost, nullptr, z.data());
    }
    ceres::Solver::Options sopt;
    // Normal equations (one pass of J^T J over the points) instead of a dense QR of the n x m
    // Jacobian (m <= 30 columns: Eigen's unblocked QR then makes m passes over n rows, ~1 s per
    // iteration at 2e6 points). Their conditioning is fine here: z spans only the directions
    // whose singular value is >= rank_tolerance (1e-3) of the largest, and Ceres scales columns.
    sopt.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    sopt.max_num_iterations = options.max_iterations;
    // The model is nearly linear in the coefficients: Gauss-Newton steps converge in 2-4
    // iterations. Stop when a step changes the coefficients by < 1e-9 relative (5e-8 um on
    // 50 um) or the cost by < 1e-12 relative (noise-free data drive the cost to 0, so the
    // parameter test is the one that ends those).
    sopt.function_tolerance = 1e-12;
    sopt.parameter_tolerance = 1e-9;
    sopt.gradient_tolerance = 1e-16;
    sopt.num_threads = 1;
    // Start with negligible Levenberg-Marquardt damping (Ceres' default radius 1e4 damps the
    // weakest identifiable direction by ~1e-3 per step, which costs one or two more iterations,
    // each a pass of Jacobians over all points). A step that fails shrinks the radius as usual.
    sopt.initial_trust_region_radius = 1e10;
    sopt.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(sopt, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE)
      return Status(StatusCode::kNotConverged, "identification did not converge: " + summary.message);
    out.iterations = static_cast<int>(summary.iterations.size());
    out.termination = ceres::TerminationTypeToString(summary.termination_type) + std::string(": ") + summary.message;
    cost->SetCoefficients(z.data(), &out.fitted);
    out.jacobian_passes += cost->jacobian_passes();
  }
  lin0 = nullptr;
  lin0_made = Status(StatusCode::kInternal, "released");  // its memory, before the design at the solution
  const Eigen::Map<const Eigen::VectorXd> zz(z.data(), rank);
  const Eigen::VectorXd theta = V_r * zz;  // display units
  if (options.fit_alignment) {
    out.alignment = MakeRigid(RotationFromUrad(xi.data()), Eigen::Vector3d(xi[3], xi[4], xi[5]) * 1e-3);
  }

  // 3. The linearised problem at the solution: residuals and design in reduced coordinates. Ceres
  // ends at a point where it evaluated the Jacobian (the last accepted one); if that evaluation
  // is at exactly the solution (same bits), its residuals and Jacobian are the design (Ar =
  // d predicted / dz for z, d measured / dxi for xi: the negated and the plain Ceres blocks);
  // otherwise the points are linearised again.
  const int m = rank + (options.fit_alignment ? kNuisance : 0);
  Eigen::VectorXd e(n);
  Eigen::MatrixXd Ar(n, m);
  const bool captured = capture.valid && capture.z == z && (!options.fit_alignment || capture.xi == xi);
  if (captured) {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    e = Eigen::Map<const Eigen::VectorXd>(capture.residuals_um.data(), n);
    Ar.leftCols(rank) = -Eigen::Map<const RowMajor>(capture.J_z.data(), n, rank);
    if (options.fit_alignment) Ar.rightCols(kNuisance) = Eigen::Map<const RowMajor>(capture.J_xi.data(), n, kNuisance);
    capture = JacobianCapture();
  } else {
    std::vector<Observation> aligned(observations.begin(), observations.end());
    for (auto& o : aligned) o.measured_mm = out.alignment * o.measured_mm;
    auto lin = LineariseObservations(model, out.fitted, active, aligned);
    if (!lin.ok()) return lin.status();
    ++out.jacobian_passes;
    e = lin->measured_dev_um - lin->predicted_dev_um;
    Ar.leftCols(rank) = lin->J_dev_params * V_r;
    if (options.fit_alignment) Ar.rightCols(kNuisance) = lin->J_dev_alignment;
    if (w.size() > 0) {
      e.array() *= w.array();
      Ar = w.asDiagonal() * Ar;
    }
  }
  // e and Ar are weighted from here on; the residuals reported are not.
  const Eigen::VectorXd e_raw = w.size() > 0 ? Eigen::VectorXd(e.array() / w.array()) : e;
  out.residuals_um.assign(e_raw.data(), e_raw.data() + e_raw.size());
  out.rms_after_um = std::sqrt(e_raw.squaredNorm() / static_cast<double>(n));
  const double dof = static_cast<double>(n - m);
  const double sigma2 = e.squaredNorm() / dof;
  out.sigma_um = std::sqrt(sigma2);
  const Eigen::MatrixXd AtA = Ar.transpose() * Ar;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(AtA);
  const Eigen::MatrixXd M = ldlt.solve(Eigen::MatrixXd::Identity(m, m));  // (A^T A)^-1
  // Map from reduced to display coefficients: theta = T * beta, T = [V_r 0].
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(q, m);
  T.leftCols(rank) = V_r;
  const Eigen::MatrixXd cov_analytic = sigma2 * T * M * T.transpose();

  // Jackknife, delete one point (closed form).
  Eigen::VectorXd jk_mean = Eigen::VectorXd::Zero(q);
  Eigen::MatrixXd jk_delta(q, n);
  {
    const Eigen::MatrixXd MAt = M * Ar.transpose();  // m x n
    for (Eigen::Index i = 0; i < n; ++i) {
      const double h = Ar.row(i).dot(MAt.col(i));
      const Eigen::VectorXd db = -MAt.col(i) * e(i) / (1.0 - h);
      jk_delta.col(i) = T * db;
    }
    jk_mean = jk_delta.rowwise().mean();
  }
  const Eigen::MatrixXd jk_c = jk_delta.colwise() - jk_mean;
  const Eigen::VectorXd var_jk = jk_c.rowwise().squaredNorm() * (static_cast<double>(n - 1) / static_cast<double>(n));

  // Jackknife, delete one group (block downdate).
  Eigen::VectorXd var_jg = Eigen::VectorXd::Constant(q, std::numeric_limits<double>::quiet_NaN());
  std::string jg_message;
  if (options.jackknife_groups) {
    std::map<int, std::vector<Eigen::Index>> groups;
    for (Eigen::Index i = 0; i < n; ++i) groups[observations[static_cast<std::size_t>(i)].group].push_back(i);
    const int G = static_cast<int>(groups.size());
    if (G >= 2) {
      std::vector<Eigen::VectorXd> deltas;
      std::vector<int> unavailable_groups;
      for (const auto& [g, idx] : groups) {
        const auto ng = static_cast<Eigen::Index>(idx.size());
        Eigen::MatrixXd Ag(ng, m);
        Eigen::VectorXd eg(ng);
        for (Eigen::Index k = 0; k < ng; ++k) {
          Ag.row(k) = Ar.row(idx[k]);
          eg(k) = e(idx[k]);
        }
        // Block downdate without the n_g x n_g matrix (Woodbury):
        // M A_g^T (I - A_g M A_g^T)^-1 = (A^T A - A_g^T A_g)^-1 A_g^T.
        const Eigen::MatrixXd reduced = AtA - Ag.transpose() * Ag;
        Eigen::JacobiSVD<Eigen::MatrixXd> s(reduced);
        const double smax_r = s.singularValues()(0);
        if (!(s.singularValues()(m - 1) > 1e-10 * smax_r)) {
          unavailable_groups.push_back(g);
          continue;
        }
        deltas.push_back(T * (-reduced.ldlt().solve(Ag.transpose() * eg)));
      }
      if (unavailable_groups.empty()) {
        Eigen::VectorXd mean = Eigen::VectorXd::Zero(q);
        for (const auto& d : deltas) mean += d;
        mean /= static_cast<double>(G);
        var_jg.setZero();
        for (const auto& d : deltas) var_jg += (d - mean).cwiseAbs2();
        var_jg *= static_cast<double>(G - 1) / static_cast<double>(G);
      } else {
        jg_message = "deleting group(s)";
        for (int g : unavailable_groups) jg_message += " " + std::to_string(g);
        jg_message += " leaves the other features unable to determine some coefficients";
      }
    } else {
      jg_message = "only one group";
    }
  }

  // Monte Carlo (GUM S1) on the linearised model: deviations drawn from a scaled-shifted t
  // distribution about the fitted values.
  Eigen::MatrixXd mc;  // q x trials
  if (options.monte_carlo_trials > 0) {
    std::mt19937_64 rng(options.seed);
    std::normal_distribution<double> N01(0.0, 1.0);
    std::chi_squared_distribution<double> chi2(dof);
    // (A^T A)^-1 A^T eps with eps ~ s N(0, I_n) is s N(0, M): draw it in m dimensions.
    const Eigen::LLT<Eigen::MatrixXd> llt(M);
    const Eigen::MatrixXd L = llt.matrixL();
    mc.resize(q, options.monte_carlo_trials);
    Eigen::VectorXd zeta(m);
    for (int t = 0; t < options.monte_carlo_trials; ++t) {
      const double scale = std::sqrt(sigma2 * dof / chi2(rng));
      for (Eigen::Index i = 0; i < m; ++i) zeta(i) = N01(rng);
      mc.col(t) = T * (scale * (L * zeta));
    }
  }

  // Seed 002 section 5: random subsets of each feature's points, linearised refits.
  std::vector<Eigen::VectorXd> subset_solutions;
  std::string subset_message;
  if (options.random_subset_trials > 0) {
    std::map<int, std::vector<Eigen::Index>> groups;
    for (Eigen::Index i = 0; i < n; ++i) groups[observations[static_cast<std::size_t>(i)].group].push_back(i);
    std::mt19937_64 rng(options.seed ^ 0x5eed002ULL);
    int skipped = 0;
    for (int t = 0; t < options.random_subset_trials; ++t) {
      std::vector<Eigen::Index> rows;
      for (auto& [g, idx] : groups) {
        std::vector<Eigen::Index> pick = idx;
        std::shuffle(pick.begin(), pick.end(), rng);
        pick.resize(std::min<std::size_t>(pick.size(), static_cast<std::size_t>(options.random_subset_size)));
        rows.insert(rows.end(), pick.begin(), pick.end());
      }
      const auto ns = static_cast<Eigen::Index>(rows.size());
      Eigen::MatrixXd As(ns, m);
      Eigen::VectorXd es(ns);
      for (Eigen::Index k = 0; k < ns; ++k) {
        As.row(k) = Ar.row(rows[static_cast<std::size_t>(k)]);
        es(k) = e(rows[static_cast<std::size_t>(k)]);
      }
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
      qr.setThreshold(1e-9);
      if (qr.rank() < m) {
        ++skipped;
        continue;
      }
      subset_solutions.push_back(T * qr.solve(es));
    }
    if (subset_solutions.size() < 2)
      subset_message = "no subset of " + std::to_string(options.random_subset_size) +
                       " points per feature determines every coefficient";
    else if (skipped > 0)
      subset_message = std::to_string(skipped) + " of " + std::to_string(options.random_subset_trials) +
                       " subsets could not determine every coefficient and were skipped";
  }

  // 4. Estimates.
  const double nu_points = dof;
  for (int k = 0; k < q; ++k) {
    ParameterEstimate p;
    p.name = names[k];
    p.iso_symbol = IsoSymbolOf(model, p.name);
    p.unit = base.coefficient_info(active.coefficients[k]).unit;
    p.identifiable = identifiable[k];
    p.value = theta(k) + base.coefficient(active.coefficients[k]) * scales[k];
    if (p.identifiable) {
      p.uncertainties.push_back(
          MakeUncertainty(UncertaintyMethod::kAnalytic, p.value, std::sqrt(cov_analytic(k, k)), nu_points));
      p.uncertainties.push_back(
          MakeUncertainty(UncertaintyMethod::kJackknifePoints, p.value, std::sqrt(var_jk(k)), nu_points));
      if (options.jackknife_groups) {
        Uncertainty ug = MakeUncertainty(UncertaintyMethod::kJackknifeGroups, p.value, std::sqrt(var_jg(k)),
                                         std::max(1, out.num_groups - 1));
        if (!ug.available) ug.message = jg_message;
        p.uncertainties.push_back(ug);
      }
      if (mc.size() > 0) {
        std::vector<double> draws(static_cast<std::size_t>(mc.cols()));
        for (Eigen::Index t = 0; t < mc.cols(); ++t) draws[static_cast<std::size_t>(t)] = mc(k, t);
        p.uncertainties.push_back(MonteCarloUncertainty(p.value, std::move(draws)));
      }
      if (options.random_subset_trials > 0) {
        Uncertainty us;
        us.method = UncertaintyMethod::kRandomSubsets;
        us.message = subset_message;
        if (subset_solutions.size() >= 2) {
          double mean = 0, ss = 0;
          for (const auto& v : subset_solutions) mean += v(k);
          mean /= static_cast<double>(subset_solutions.size());
          for (const auto& v : subset_solutions) ss += (v(k) - mean) * (v(k) - mean);
          us = MakeUncertainty(UncertaintyMethod::kRandomSubsets, p.value,
                               std::sqrt(ss / static_cast<double>(subset_solutions.size() - 1)),
                               static_cast<double>(subset_solutions.size() - 1));
          us.message = subset_message;
        }
        p.uncertainties.push_back(us);
      }
      for (const auto& u : p.uncertainties) {
        if (u.method == options.primary && u.available) {
          p.u = u.u;
          p.ci95_low = u.ci95_low;
          p.ci95_high = u.ci95_high;
        }
      }
    } else {
      p.value = 0.0;
    }
    out.parameters.push_back(std::move(p));
  }

  // 5. Non-identifiable coefficients: null directions and estimable combinations.
  if (V_n.cols() > 0) {
    std::vector<int> S;
    for (int k = 0; k < q; ++k)
      if (!identifiable[k]) {
        S.push_back(k);
        idf.not_identifiable.push_back(names[k]);
      }
    const auto s = static_cast<Eigen::Index>(S.size());
    Eigen::MatrixXd NS(s, V_n.cols());
    for (Eigen::Index a = 0; a < s; ++a) NS.row(a) = V_n.row(S[a]);
    std::vector<std::string> snames;
    for (int k : S) snames.push_back(names[k]);
    for (Eigen::Index j = 0; j < V_n.cols(); ++j) {
      Eigen::VectorXd c = NS.col(j);
      NormaliseCombination(&c);
      Combination comb;
      comb.names = snames;
      comb.coefficients.assign(c.data(), c.data() + c.size());
      comb.text = FormatCombination(snames, comb.coefficients);
      idf.null_directions.push_back(comb);
    }
    for (const Eigen::VectorXd& full : internal::EstimableCombinations(V_n, S)) {
      Combination comb;
      comb.names = snames;
      for (int k : S) comb.coefficients.push_back(full(k));
      comb.text = FormatCombination(snames, comb.coefficients);
      double base_value = 0.0;
      for (int k : S) base_value += full(k) * base.coefficient(active.coefficients[k]) * scales[k];
      comb.value = full.dot(theta) + base_value;
      comb.u = std::sqrt(std::max(0.0, full.dot(cov_analytic * full)));
      idf.estimable.push_back(comb);
    }
  }
  return out;
}

}  // namespace tpcal::kinematics
