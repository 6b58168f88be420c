// Internal to fitting/: the linearised Chebyshev LP behind the minimum-zone refinements
// (circularity, cylindricity, 3D straightness), solved exactly (CGAL QP solver, Gmpzf), and the
// generic sequential-LP loop and local certificate built on it. Not a public API.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fitting/minimum_zone.h"

namespace tpcal::fitting::internal {

enum class ChebyshevKind {
  kZone,   // minimise max_i r_i - min_i r_i (annulus, coaxial cylinders)
  kUpper,  // minimise max_i r_i (enclosing cylinder about a line)
};

// Residuals linearised about the current feature: r_i(delta) ~ value[i] + jacobian.row(i) * delta.
struct LinearModel {
  Eigen::VectorXd value;     // n, mm
  Eigen::MatrixXd jacobian;  // n x k
};

// Box for delta: lower[j] <= delta_j <= upper[j].
struct LpBox {
  Eigen::VectorXd lower, upper;
  static LpBox Cube(int k, double half_width);
};

struct LpResult {
  bool ok = false;
  std::string message;
  Eigen::VectorXd delta;       // minimiser (rounded to double)
  double objective = 0;        // U - V (or U) at the optimum: the exact LP optimum when no
                               // curvature was given, rounded to nearest
  double model_value = 0;      // objective + delta^T W delta / 2 (W: curvature; = objective for an LP)
  double objective_lower = 0;  // without curvature: a rigorous lower bound of the LP optimum over
                               // ALL n rows (subset LP is a relaxation; rounding margin subtracted)
  std::vector<ZoneContact> active;      // rows with non-zero multiplier (index, side)
  std::vector<double> multipliers;      // |lambda| per active row (sum 1 per side at optimum)
  bool box_active = false;              // delta touches the box
};

// Working set of rows carried between calls (constraint generation).
struct WorkingSet {
  std::vector<int> upper, lower;
};

// Solves min (U - V) [kZone] or min U [kUpper] subject to value_i + J_i delta <= U (all i),
// value_i + J_i delta >= V (kZone), delta in box. Exact LP (Gmpzf) on a working set of rows,
// grown until no row is violated at the solution (by more than ~1e-14 of the residual scale).
// With `curvature` W (k x k, positive semidefinite) the objective gains delta^T W delta / 2 and the
// problem is solved as an exact QP (the sequential-QP step; W from the active rows' Hessians).
LpResult SolveChebyshevLp(const LinearModel& model, ChebyshevKind kind, const LpBox& box,
                          WorkingSet* working_set, const Eigen::MatrixXd* curvature = nullptr);

// A feature parametrised by a local displacement delta (k parameters, mm) about its current state.
class ChebyshevProblem {
 public:
  virtual ~ChebyshevProblem() = default;
  virtual int num_params() const = 0;
  virtual ChebyshevKind kind() const = 0;
  virtual LinearModel Linearize() const = 0;               // at delta = 0
  virtual double Objective(const Eigen::VectorXd& delta) const = 0;  // exact (nonlinear) zone
  virtual void Apply(const Eigen::VectorXd& delta) = 0;    // move the state by delta
  // Positive semidefinite curvature sum_i lambda_i Hess r_i over the active upper rows (the convex
  // part of the Lagrangian Hessian), for a sequential-QP step. Default: none.
  virtual Eigen::MatrixXd Curvature(const std::vector<ZoneContact>& active,
                                    const std::vector<double>& multipliers) const {
    (void)active;
    (void)multipliers;
    return Eigen::MatrixXd::Zero(num_params(), num_params());
  }
  virtual double Scale() const = 0;                        // size of the feature, mm (for tolerances)
};

struct SlpResult {
  bool converged = false;
  int iterations = 0;
  double objective = 0;      // at the final state
  LpResult last_lp;          // the LP at the final state
  std::string message;
};

// Sequential LP/QP with a trust box (initial half-width `initial_step_mm`) until the exact model
// predicts no decrease beyond rounding. The QP curvature (Curvature()) makes the iteration converge
// fast where the optimum is not a vertex of the linear model (e.g. few contacts on a thin cylinder).
SlpResult RunSlp(ChebyshevProblem& problem, int max_iterations, double initial_step_mm);

// Local certificate at the current state of `problem`, given a rigorous bound
// Objective(delta) >= L(delta) - quadratic_bound(t) for ||delta||_inf <= t, where L is the
// piecewise-linear model of Linearize(). Proves Objective(delta) >= objective - gap for all
// ||delta||_inf <= radius. radius = 0 when no sharpness is visible.
struct LocalCertificate {
  bool ok = false;
  double gap_mm = std::numeric_limits<double>::infinity();
  double radius_mm = 0;
  double sharpness = 0;  // kappa: the model grows at least kappa * ||delta||_inf near 0
  std::string message;
};
LocalCertificate CertifyLocal(const ChebyshevProblem& problem, double objective,
                              const std::function<double(double)>& quadratic_bound,
                              double radius_limit_mm);

// Sorted, de-duplicated contacts.
void NormalizeContacts(std::vector<ZoneContact>* contacts);

}  // namespace tpcal::fitting::internal
