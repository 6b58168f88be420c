// The linearised Chebyshev LP (exact, CGAL QP solver over Gmpzf), the sequential-LP loop and the
// local certificate. The only translation unit of fitting/ that includes the CGAL QP solver.
#include "fitting/minimum_zone_lp.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace tpcal::fitting::internal {
namespace {

using Program = CGAL::Quadratic_program<double>;
using Solution = CGAL::Quadratic_program_solution<CGAL::Gmpzf>;

constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2;

// The k rows with the largest (largest = true) or smallest values, not already in `set`.
void AddExtremeRows(const Eigen::VectorXd& v, int count, bool largest, std::vector<int>* set) {
  const int n = static_cast<int>(v.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  const int m = std::min(n, count + static_cast<int>(set->size()));
  auto cmp = [&](int a, int b) { return largest ? v[a] > v[b] : v[a] < v[b]; };
  std::partial_sort(order.begin(), order.begin() + m, order.end(), cmp);
  int added = 0;
  for (int i = 0; i < m && added < count; ++i) {
    if (std::find(set->begin(), set->end(), order[i]) == set->end()) {
      set->push_back(order[i]);
      ++added;
    }
  }
}

}  // namespace

LpBox LpBox::Cube(int k, double half_width) {
  return {Eigen::VectorXd::Constant(k, -half_width), Eigen::VectorXd::Constant(k, half_width)};
}

void NormalizeContacts(std::vector<ZoneContact>* contacts) {
  std::sort(contacts->begin(), contacts->end(), [](const ZoneContact& a, const ZoneContact& b) {
    return a.index != b.index ? a.index < b.index : a.side < b.side;
  });
  contacts->erase(std::unique(contacts->begin(), contacts->end()), contacts->end());
}

LpResult SolveChebyshevLp(const LinearModel& model, ChebyshevKind kind, const LpBox& box,
                          WorkingSet* working_set, const Eigen::MatrixXd* curvature) {
  LpResult out;
  const int n = static_cast<int>(model.value.size());
  const int k = static_cast<int>(model.jacobian.cols());
  const bool zone = kind == ChebyshevKind::kZone;
  if (n == 0) {
    out.message = "no residuals";
    return out;
  }
  // Shift the residuals so the LP works on small numbers; the objective U - V is unchanged.
  const double vmax = model.value.maxCoeff(), vmin = model.value.minCoeff();
  const double shift = zone ? 0.5 * (vmax + vmin) : vmax;
  const Eigen::VectorXd v = model.value.array() - shift;
  const double value_scale = std::max(v.cwiseAbs().maxCoeff(), std::abs(shift) * kUnitRoundoff);

  WorkingSet local;
  WorkingSet& ws = working_set ? *working_set : local;
  if (ws.upper.size() + ws.lower.size() > static_cast<std::size_t>(40 * (k + 2))) ws = WorkingSet{};
  const bool quadratic = curvature != nullptr && curvature->cwiseAbs().maxCoeff() > 0;
  const int per_round = k + 2;
  AddExtremeRows(v, std::max(0, 2 * k + 4 - static_cast<int>(ws.upper.size())), true, &ws.upper);
  if (zone) {
    AddExtremeRows(v, std::max(0, 2 * k + 4 - static_cast<int>(ws.lower.size())), false, &ws.lower);
  } else {
    ws.lower.clear();
  }

  const int iu = k, il = k + 1;  // variable indices of U and V
  for (int round = 0; round < 200; ++round) {
    Program lp(CGAL::SMALLER, false, 0, false, 0);
    int row = 0;
    for (int i : ws.upper) {
      for (int j = 0; j < k; ++j) lp.set_a(j, row, model.jacobian(i, j));
      lp.set_a(iu, row, -1.0);
      lp.set_b(row, -v[i]);
      lp.set_r(row, CGAL::SMALLER);
      ++row;
    }
    for (int i : ws.lower) {
      for (int j = 0; j < k; ++j) lp.set_a(j, row, model.jacobian(i, j));
      lp.set_a(il, row, -1.0);
      lp.set_b(row, -v[i]);
      lp.set_r(row, CGAL::LARGER);
      ++row;
    }
    for (int j = 0; j < k; ++j) {
      lp.set_l(j, true, box.lower[j]);
      lp.set_u(j, true, box.upper[j]);
    }
    lp.set_c(iu, 1.0);
    if (zone) lp.set_c(il, -1.0);
    if (quadratic) {  // CGAL's D holds 2D: objective x^T D x = delta^T W delta / 2 needs 2D = W
      for (int i = 0; i < k; ++i) {
        for (int j = 0; j <= i; ++j) lp.set_d(i, j, (*curvature)(i, j));
      }
    }

    Solution s = quadratic ? CGAL::solve_quadratic_program(lp, CGAL::Gmpzf())
                           : CGAL::solve_linear_program(lp, CGAL::Gmpzf());
    if (!s.is_optimal()) {
      out.message = s.is_infeasible() ? "linearised LP infeasible" : "linearised LP unbounded";
      return out;
    }
    std::vector<double> x;
    x.reserve(k + 2);
    for (auto it = s.variable_values_begin(); it != s.variable_values_end(); ++it) {
      x.push_back(CGAL::to_double(*it));
    }
    out.delta = Eigen::Map<const Eigen::VectorXd>(x.data(), k);
    const double U = x[iu];
    const double V = zone ? x[il] : 0.0;

    // Constraint generation: add the most violated rows.
    const Eigen::VectorXd lin = v + model.jacobian * out.delta;
    const double tol = 64 * kUnitRoundoff *
                       (value_scale + model.jacobian.cwiseAbs().maxCoeff() * out.delta.cwiseAbs().sum());
    std::vector<std::pair<double, int>> viol_up, viol_lo;
    for (int i = 0; i < n; ++i) {
      if (lin[i] - U > tol) viol_up.emplace_back(lin[i] - U, i);
      if (zone && V - lin[i] > tol) viol_lo.emplace_back(V - lin[i], i);
    }
    if (viol_up.empty() && viol_lo.empty()) {
      const double quad = quadratic ? 0.5 * out.delta.dot(*curvature * out.delta) : 0.0;
      const double obj = quadratic ? (zone ? U - V : U) : CGAL::to_double(s.objective_value());
      out.objective = zone ? obj : obj + shift;
      out.model_value = out.objective + quad;
      // Rounding of the quotient, of the shifted values (u |v_i|), of the shift itself.
      const double margin = 4 * kUnitRoundoff * (std::abs(obj) + value_scale) +
                            (zone ? 0.0 : 2 * kUnitRoundoff * std::abs(shift));
      out.objective_lower = out.objective - margin;
      out.active.clear();
      out.multipliers.clear();
      int r = 0;
      for (auto it = s.optimality_certificate_begin(); it != s.optimality_certificate_end(); ++it, ++r) {
        const double lambda = CGAL::to_double(*it);
        if (lambda == 0) continue;
        const bool up = r < static_cast<int>(ws.upper.size());
        const int idx = up ? ws.upper[r] : ws.lower[r - ws.upper.size()];
        out.active.push_back({static_cast<std::size_t>(idx), up ? ZoneSide::kUpper : ZoneSide::kLower});
        out.multipliers.push_back(std::abs(lambda));
      }
      out.box_active = false;
      for (int j = 0; j < k; ++j) {
        if (out.delta[j] <= box.lower[j] || out.delta[j] >= box.upper[j]) out.box_active = true;
      }
      out.ok = true;
      return out;
    }
    auto take = [&](std::vector<std::pair<double, int>>& viol, std::vector<int>* set) {
      std::sort(viol.begin(), viol.end(), std::greater<>());
      for (int t = 0; t < static_cast<int>(viol.size()) && t < per_round; ++t) set->push_back(viol[t].second);
    };
    take(viol_up, &ws.upper);
    take(viol_lo, &ws.lower);
  }
  out.message = "constraint generation did not settle in 200 rounds";
  return out;
}

SlpResult RunSlp(ChebyshevProblem& problem, int max_iterations, double initial_step_mm) {
  SlpResult out;
  const int k = problem.num_params();
  const double scale = problem.Scale();
  const double tol = 64 * kUnitRoundoff * scale;  // rounding level of the residuals
  double step = initial_step_mm;
  WorkingSet ws;
  Eigen::MatrixXd curvature = Eigen::MatrixXd::Zero(k, k);
  double f = problem.Objective(Eigen::VectorXd::Zero(k));
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it + 1;
    const LinearModel model = problem.Linearize();
    LpResult lp = SolveChebyshevLp(model, problem.kind(), LpBox::Cube(k, step), &ws, &curvature);
    if (!lp.ok) {
      out.message = lp.message;
      return out;
    }
    const double predicted = f - lp.model_value;
    if (predicted <= tol) {
      out.converged = true;
      out.objective = f;
      out.last_lp = std::move(lp);
      out.message = "LP predicts no decrease beyond rounding";
      return out;
    }
    const double f_new = problem.Objective(lp.delta);
    const double ratio = (f - f_new) / predicted;
    const double step_len = lp.delta.cwiseAbs().maxCoeff();
    if (ratio > 1e-4) {
      problem.Apply(lp.delta);
      curvature = problem.Curvature(lp.active, lp.multipliers);
      f = problem.Objective(Eigen::VectorXd::Zero(k));
      if (ratio > 0.5 && lp.box_active) step *= 2;
      else if (!lp.box_active) step = std::max(4 * step_len, 1e-12 * scale);
    } else {
      step = 0.25 * std::min(step, std::max(step_len, 1e-300));
      if (step < 1e-15 * scale) {
        out.converged = true;
        out.objective = f;
        out.last_lp = std::move(lp);
        out.message = "step below rounding level";
        return out;
      }
    }
  }
  out.objective = f;
  out.message = "no convergence in " + std::to_string(max_iterations) + " iterations";
  return out;
}

LocalCertificate CertifyLocal(const ChebyshevProblem& problem, double objective,
                              const std::function<double(double)>& quadratic_bound,
                              double radius_limit_mm) {
  LocalCertificate out;
  const int k = problem.num_params();
  const double scale = problem.Scale();
  const LinearModel model = problem.Linearize();
  const bool zone = problem.kind() == ChebyshevKind::kZone;
  const double l0 = zone ? model.value.maxCoeff() - model.value.minCoeff() : model.value.maxCoeff();
  // Inner box: where the quadratic term is negligible (1e-12 mm, 0.001 pm).
  double s = 1e-3 * scale;
  while (s > 1e-12 * scale && quadratic_bound(s) > 1e-12) s *= 0.5;
  WorkingSet ws;
  const LpResult inner = SolveChebyshevLp(model, problem.kind(), LpBox::Cube(k, s), &ws);
  if (!inner.ok) {
    out.message = "certificate LP failed: " + inner.message;
    return out;
  }
  // Boundary of the inner box: 2k faces, each an LP with one coordinate fixed at +-s.
  double boundary_min = std::numeric_limits<double>::infinity();
  for (int j = 0; j < k; ++j) {
    for (double sign : {-1.0, 1.0}) {
      LpBox face = LpBox::Cube(k, s);
      face.lower[j] = face.upper[j] = sign * s;
      const LpResult r = SolveChebyshevLp(model, problem.kind(), face, &ws);
      if (!r.ok) {
        out.message = "certificate LP failed: " + r.message;
        return out;
      }
      boundary_min = std::min(boundary_min, r.objective_lower);
    }
  }
  // Rounding of the residual values and Jacobians computed in double (a few ulps of the scale).
  const double margin = 32 * kUnitRoundoff * scale;
  out.sharpness = (boundary_min - l0 - margin) / s;
  out.gap_mm = std::max(0.0, objective - (inner.objective_lower - quadratic_bound(s))) + margin +
               std::max(0.0, objective - l0);
  out.radius_mm = s;
  if (out.sharpness > 0) {
    // Largest t with quadratic_bound(t) <= sharpness * t (quadratic_bound(t)/t grows with t).
    double lo = s, hi = radius_limit_mm;
    if (quadratic_bound(hi) <= out.sharpness * hi) {
      lo = hi;
    } else {
      for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (quadratic_bound(mid) <= out.sharpness * mid ? lo : hi) = mid;
      }
    }
    out.radius_mm = lo;
  }
  std::ostringstream msg;
  msg << "exact LP on the linearisation: no descent beyond " << out.gap_mm << " mm within "
      << out.radius_mm << " mm (sharpness " << out.sharpness << ")";
  out.message = msg.str();
  out.ok = true;
  return out;
}

}  // namespace tpcal::fitting::internal
