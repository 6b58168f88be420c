#include "kinematics/seed002_closed_form.h"

#include <Eigen/Core>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>

#include "kinematics/internal/combination.h"

namespace tpcal::kinematics {
namespace {

enum P { kDx0, kDy0, kA0, kB0, kDyAR, kDzAR, kDyCA, kA90, kG90, kBZX, kAZY, kNumP };
constexpr double k = 1e-3;  // urad * mm -> um

using Row = std::array<double, kNumP>;

// Sensitivity rows of every item (d item / d parameter, parameters in um / urad).
std::map<std::string, Row> Rows(const Seed002Geometry& g, Seed002Equations eq) {
  std::map<std::string, Row> r;
  auto row = [&](const std::string& name) -> Row& {
    Row& x = r[name];
    x.fill(0.0);
    return x;
  };
  if (eq == Seed002Equations::kKinematics) {
    { Row& x = row("dx_Ch_SR_um"); x[kDx0] = 1; x[kB0] = g.z_h * k; x[kBZX] = -g.z_R * k; }
    { Row& x = row("dy_Ch_SR_um"); x[kDy0] = 1; x[kA0] = -g.z_h * k; x[kAZY] = g.z_R * k; }
    { Row& x = row("da_B1_BR_urad"); x[kA0] = 1; }
    { Row& x = row("db_B1_BR_urad"); x[kB0] = 1; }
    { Row& x = row("dd_B3_BR_um"); x[kDyAR] = -1; x[kDzAR] = -1; x[kA90] = g.rho_B3 * k; x[kAZY] = -g.rho_B3 * k; }
    { Row& x = row("dr_S3_um"); x[kDzAR] = -1; x[kDyCA] = -1; x[kA90] = g.z3 * k; }
    { Row& x = row("dx_S4_SR_um"); x[kDx0] = 1; x[kB0] = g.z4 * k; x[kBZX] = -g.z_R * k; }
    { Row& x = row("dy_S4_SR_um"); x[kDy0] = 1; x[kA0] = -g.z4 * k; x[kAZY] = g.z_R * k; }
    { Row& x = row("dx_S4_S1_um"); x[kB0] = -(g.z1 - g.z4) * k; }
    { Row& x = row("dy_S4_S1_um"); x[kA0] = (g.z1 - g.z4) * k; }
    { Row& x = row("dx_S6_S3_um"); x[kG90] = -(g.z3 - g.z6) * k; }
    { Row& x = row("dy_S6_S3_um"); x[kA90] = (g.z3 - g.z6) * k; }
    { Row& x = row("dx_S3_SR_um"); x[kDx0] = 1; x[kG90] = g.z3 * k; x[kBZX] = -g.z_R * k; }  // dx_CR(0) at every A
    { Row& x = row("dy_S3_SR_um"); x[kDyAR] = 1; x[kDyCA] = 1; x[kA90] = -g.z3 * k; x[kAZY] = g.z_R * k; }
    { Row& x = row("dr_S1_S4_um"); x[kBZX] = (g.z1 - g.z4) * k; x[kB0] = -(g.z1 - g.z4) * k; }
    { Row& x = row("dr_S2_S5_um"); x[kA0] = (g.z2 - g.z5) * k; x[kAZY] = -(g.z2 - g.z5) * k; }
  } else {
    // Seed 002 eqs. 10-21 as printed (gamma_YX = 0; alpha_CY(-90) read as alpha_CR(-90)).
    { Row& x = row("dx_Ch_SR_um"); x[kDx0] = 1; x[kB0] = g.z_h * k; x[kBZX] = -g.z_h * k; }
    { Row& x = row("dy_Ch_SR_um"); x[kDy0] = 1; x[kA0] = -g.z_h * k; x[kAZY] = g.z_h * k; }
    { Row& x = row("da_B1_BR_urad"); x[kB0] = 1; }
    { Row& x = row("db_B1_BR_urad"); x[kA0] = 1; }
    { Row& x = row("dd_B3_BR_um"); x[kDyAR] = -1; x[kDzAR] = -1; }
    { Row& x = row("dr_S3_um"); x[kDzAR] = -1; x[kDyAR] = -1; x[kDyCA] = -1; x[kA90] = g.z3 * k; }
    { Row& x = row("dx_S4_SR_um"); x[kDx0] = 1; x[kB0] = g.z4 * k; x[kBZX] = -g.z4 * k; }
    { Row& x = row("dy_S4_SR_um"); x[kDy0] = 1; x[kA0] = -g.z4 * k; x[kAZY] = g.z4 * k; }
    { Row& x = row("dx_S4_S1_um"); x[kB0] = -(g.z1 - g.z4) * k; x[kBZX] = (g.z1 - g.z4) * k; }
    { Row& x = row("dy_S4_S1_um"); x[kA0] = (g.z1 - g.z4) * k; x[kAZY] = -(g.z1 - g.z4) * k; }
    { Row& x = row("dx_S6_S3_um"); x[kG90] = -(g.z3 - g.z6) * k; }
    { Row& x = row("dy_S6_S3_um"); x[kA90] = (g.z3 - g.z6) * k; }
  }
  return r;
}

}  // namespace

const char* Seed002EquationsName(Seed002Equations e) {
  return e == Seed002Equations::kKinematics ? "kinematics" : "printed";
}

const std::vector<std::string>& Seed002ParameterNames() {
  static const std::vector<std::string> names = {"dx_CR(0)",     "dy_CR(0)",   "alpha_CR(0)", "beta_CR(0)",
                                                 "dy_AR(-90)",   "dz_AR(-90)", "dy_CA(-90)",  "alpha_CR(-90)",
                                                 "gamma_CR(-90)", "beta_ZX",   "alpha_ZY"};
  return names;
}

namespace {
bool IsAngle(int p) { return p == kA0 || p == kB0 || p == kA90 || p == kG90 || p == kBZX || p == kAZY; }
}  // namespace

Seed002Items PredictSeed002Items(const std::map<std::string, double>& parameters, const Seed002Geometry& g,
                                 Seed002Equations equations) {
  const auto& names = Seed002ParameterNames();
  Row x{};
  for (int p = 0; p < kNumP; ++p) {
    auto it = parameters.find(names[p]);
    x[p] = it == parameters.end() ? 0.0 : it->second;
  }
  Seed002Items out;
  for (const auto& [item, row] : Rows(g, equations)) {
    double v = 0.0;
    for (int p = 0; p < kNumP; ++p) v += row[p] * x[p];
    out[item] = v;
  }
  return out;
}

namespace {

// A combination c of the parameters `names` (coefficients over them; c over all parameters) with
// its value c.x and, when the items carry u, its u sqrt(c^T cov c).
Combination Seed002Combination(const std::vector<std::string>& names, const std::vector<double>& coeffs,
                               const Eigen::VectorXd& c, const Eigen::VectorXd& x, const Eigen::MatrixXd& cov,
                               bool have_u) {
  Combination out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (std::abs(coeffs[k]) < 1e-6) continue;  // as FormatCombination leaves them out
    out.names.push_back(names[k]);
    out.coefficients.push_back(coeffs[k]);
  }
  out.text = internal::FormatCombination(names, coeffs);
  out.value = c.dot(x);
  out.u = have_u ? std::sqrt(std::max(0.0, c.dot(cov * c))) : 0.0;
  return out;
}

}  // namespace

Result<ClosedFormResult> SolveSeed002(const Seed002Items& items, const Seed002Geometry& g,
                                      Seed002Equations equations, const Seed002Items& item_u) {
  const auto rows = Rows(g, equations);
  for (const auto& [name, value] : items) {
    if (!rows.count(name))
      return Status(StatusCode::kInvalidArgument,
                    "unknown item '" + name + "' for the " + Seed002EquationsName(equations) + " equations of seed 002");
    if (!std::isfinite(value)) return Status(StatusCode::kInvalidArgument, "item '" + name + "' is not finite");
  }
  if (items.empty()) return Status(StatusCode::kTooFewPoints, "no seed 002 item given");
  const auto m = static_cast<Eigen::Index>(items.size());
  Eigen::MatrixXd A(m, kNumP);
  Eigen::VectorXd b(m), w(m);
  ClosedFormResult out;
  out.equations = equations;
  bool have_u = !item_u.empty();
  Eigen::Index i = 0;
  for (const auto& [name, value] : items) {
    const Row& r = rows.at(name);
    for (int p = 0; p < kNumP; ++p) A(i, p) = r[p];
    b(i) = value;
    double u = 1.0;
    if (have_u) {
      auto it = item_u.find(name);
      if (it == item_u.end() || !(it->second > 0.0)) {
        have_u = false;
      } else {
        u = it->second;
      }
    }
    w(i) = u;
    out.items_used.push_back(name);
    out.matrix.emplace_back(r.begin(), r.end());
    ++i;
  }
  if (!have_u) w.setOnes();
  const Eigen::MatrixXd Aw = w.cwiseInverse().asDiagonal() * A;
  const Eigen::VectorXd bw = b.cwiseQuotient(w);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Aw, Eigen::ComputeThinU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double tol = 1e-9 * (s.size() ? s(0) : 0.0);
  int rank = 0;
  for (Eigen::Index j = 0; j < s.size(); ++j)
    if (s(j) > tol) ++rank;
  out.rank = rank;
  // Minimum-norm solution and its covariance (A^T W A)^+.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kNumP);
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(kNumP, kNumP);
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::MatrixXd& U = svd.matrixU();
  for (int j = 0; j < rank; ++j) {
    x += V.col(j) * (U.col(j).dot(bw) / s(j));
    cov += V.col(j) * V.col(j).transpose() / (s(j) * s(j));
  }
  const Eigen::MatrixXd Vn = V.rightCols(kNumP - rank);
  const auto& names = Seed002ParameterNames();
  std::vector<int> not_identifiable;
  for (int p = 0; p < kNumP; ++p) {
    ClosedFormParameter par;
    par.name = names[p];
    par.unit = IsAngle(p) ? "urad" : "um";
    par.identifiable = Vn.cols() == 0 || Vn.row(p).norm() < 1e-6;
    if (par.identifiable) {
      par.value = x(p);
      par.u = have_u ? std::sqrt(std::max(0.0, cov(p, p))) : 0.0;
    } else {
      not_identifiable.push_back(p);
    }
    out.parameters.push_back(par);
  }
  const Eigen::VectorXd pred = A * x;
  for (Eigen::Index j = 0; j < m; ++j) out.item_residuals.push_back(b(j) - pred(j));
  if (!not_identifiable.empty()) {
    std::vector<std::string> snames;
    for (int p : not_identifiable) snames.push_back(names[p]);
    for (const Eigen::VectorXd& c : internal::EstimableCombinations(Vn, not_identifiable)) {
      std::vector<double> coeffs;
      for (int p : not_identifiable) coeffs.push_back(c(p));
      char buf[64];
      std::snprintf(buf, sizeof buf, " = %.4g", c.dot(x));
      out.estimable.push_back(internal::FormatCombination(snames, coeffs) + buf);
      out.combinations.push_back(Seed002Combination(snames, coeffs, c, x, cov, have_u));
    }
  }
  return out;
}

Result<ErrorMotionProfile> SeparateErrorMotion(const std::vector<double>& c_deg, const std::vector<double>& dr_upper_um,
                                               const std::vector<double>& dr_lower_um, double z_upper_mm,
                                               double z_lower_mm) {
  if (c_deg.size() != dr_upper_um.size() || c_deg.size() != dr_lower_um.size())
    return Status(StatusCode::kInvalidArgument, "profiles must be sampled at the same C angles");
  if (c_deg.size() < 3) return Status(StatusCode::kTooFewPoints, "an error motion profile needs >= 3 C angles");
  const double dz = z_upper_mm - z_lower_mm;
  if (!(std::abs(dz) > 1.0))
    return Status(StatusCode::kDegenerate, "the two faces must be at least 1 mm apart in height to separate tilt");
  ErrorMotionProfile out;
  out.c_deg = c_deg;
  for (std::size_t j = 0; j < c_deg.size(); ++j) {
    // dr = -E_radial - E_tilt z (um, urad * mm * 1e-3).
    const double tilt_urad = -(dr_upper_um[j] - dr_lower_um[j]) / (dz * k);
    const double radial_um = -dr_upper_um[j] - tilt_urad * z_upper_mm * k;
    out.radial_um.push_back(radial_um);
    out.tilt_urad.push_back(tilt_urad);
  }
  auto pv = [](const std::vector<double>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *hi - *lo;
  };
  out.radial_pv_um = pv(out.radial_um);
  out.tilt_pv_urad = pv(out.tilt_urad);
  return out;
}

}  // namespace tpcal::kinematics
