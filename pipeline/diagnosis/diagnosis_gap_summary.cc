#include "pipeline/diagnosis/diagnosis_gap_summary.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/units.h"
#include "pipeline/diagnosis/diagnosis_base_fit.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

using PointGroups = std::map<std::string, std::vector<Eigen::Index>>;

// The points grouped by feature, operation ("op 2") and A (B) index ("A=-90 deg"), and each
// point's machining time.
struct GapGroups {
  std::vector<double> t_s;
  PointGroups by_feature, by_op, by_a;
};

// Group keys are formatted once per distinct value (not once per point).
GapGroups GroupGapPoints(const kinematics::MachineModel& machine, const testpieces::MeasuredObservations& mo) {
  const auto& obs = mo.observations;
  const auto n = static_cast<Eigen::Index>(obs.size());
  GapGroups out;
  out.t_s.resize(static_cast<std::size_t>(n));
  std::vector<std::vector<Eigen::Index>> of_group(mo.feature_names.size());
  std::map<int, std::vector<Eigen::Index>> of_op;
  std::map<double, std::vector<Eigen::Index>> of_a;  // rounded to 0.001 deg
  const bool has_a = machine.HasAxis(kinematics::Axis::kA);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& o = obs[static_cast<std::size_t>(i)];
    out.t_s[static_cast<std::size_t>(i)] = o.cut.axes.t_s;
    of_group[static_cast<std::size_t>(o.group)].push_back(i);
    of_op[o.cut.axes.op].push_back(i);
    const double a_deg = RadToDeg(has_a ? o.cut.axes.a_rad : o.cut.axes.b_rad);
    of_a[std::round(a_deg * 1000.0) / 1000.0 + 0.0].push_back(i);
  }
  for (std::size_t g = 0; g < of_group.size(); ++g)
    if (!of_group[g].empty()) out.by_feature[mo.feature_names[g]] = std::move(of_group[g]);
  char buf[32];
  for (auto& [op, idx] : of_op) {
    std::snprintf(buf, sizeof(buf), "op %d", op);
    out.by_op[buf] = std::move(idx);
  }
  for (auto& [a, idx] : of_a) {
    std::snprintf(buf, sizeof(buf), "%s=%g deg", has_a ? "A" : "B", a);
    auto& v = out.by_a[buf];  // distinct values print distinctly at 0.001 deg; merge if not
    v.insert(v.end(), idx.begin(), idx.end());
  }
  return out;
}

// The normal score of a chi-square value x with k degrees of freedom (Wilson-Hilferty: (x/k)^(1/3)
// is nearly normal): a group of 8 points has as few false alarms at z > 4 as a group of 300. The
// plain (x - k) / sqrt(2k) is far from normal for small k: P(chi2_8 > 8 + 4 sqrt(16)) = 2.3e-3,
// not 3.2e-5, and with 40 groups a clean piece stood out in 2 of 6 simulated trials.
double ChiSquareZ(double x, double k) {
  const double v = 2.0 / (9.0 * k);
  return (std::cbrt(x / k) - (1.0 - v)) / std::sqrt(v);
}

// The rows `idx` of a reference's leftover factor R (BaseFit::reference_remaining_um; n x 0: none).
Eigen::MatrixXd RowsOf(const Eigen::MatrixXd& R, const std::vector<Eigen::Index>& idx) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), R.cols());
  if (R.cols() > 0)
    for (std::size_t row = 0; row < idx.size(); ++row) out.row(static_cast<Eigen::Index>(row)) = R.row(idx[row]);
  return out;
}

// The normal score of a sum of squares `ss` (um^2) of `k` components holding noise of sigma and a
// reference's leftover part of factor Z (k x r rows; none: ChiSquareZ(ss / sigma^2, k)): that of
// ss / c against chi2_d, c d and d from SatterthwaiteLaw.
double SpreadZ(double ss, int k, double sigma, const Eigen::MatrixXd& Z) {
  if (Z.cols() == 0) return ChiSquareZ(ss / (sigma * sigma), k);
  const ChiSquareLaw law = SatterthwaiteLaw(k, sigma * sigma, Z);
  return ChiSquareZ(ss * law.dof / law.mean_um2, law.dof);
}

// What the noise tests see: the gap and a reference's leftover factor with each row divided by its
// observation's noise scale (noise of one hit's sigma at every observation); as given for hits.
struct TestedGap {
  Eigen::VectorXd r;
  Eigen::MatrixXd R;
  bool scaled = false;
};

TestedGap Tested(const Eigen::VectorXd& r0, const Eigen::MatrixXd& R, const Eigen::VectorXd& scale) {
  if (scale.size() == 0) return {r0, R, false};
  const Eigen::VectorXd inverse = scale.cwiseInverse();
  return {r0.cwiseProduct(inverse), R.cols() > 0 ? Eigen::MatrixXd(inverse.asDiagonal() * R) : R, true};
}

// Per group: its statistics, and its excess over noise of sigma and what a reference's leftover
// part (factor R, n x r; none: n x 0) adds, mean and spread (SpreadZ), tested on r_test (r over
// the noise scales; R's rows alike).
void GroupStats(const PointGroups& groups, const Eigen::VectorXd& r, const Eigen::VectorXd& r_test,
                const Eigen::MatrixXd& R, const std::vector<double>& t_s, double sigma, double z_out,
                std::vector<GroupGap>* out, std::vector<std::string>* standing, const std::string& prefix) {
  for (const auto& [name, idx] : groups) {
    GroupGap g;
    g.group = name;
    g.n_points = static_cast<int>(idx.size());
    double ss = 0, ss_test = 0, sum = 0, tsum = 0;
    for (auto i : idx) {
      ss += r(i) * r(i);
      ss_test += r_test(i) * r_test(i);
      sum += r(i);
      tsum += t_s[static_cast<std::size_t>(i)];
      g.max_abs_um = std::max(g.max_abs_um, std::abs(r(i)));
    }
    const double n = static_cast<double>(idx.size());
    g.rms_um = std::sqrt(ss / n);
    g.mean_um = sum / n;
    g.mean_t_s = tsum / n;
    g.z = sigma > 0 ? SpreadZ(ss_test, g.n_points, sigma, RowsOf(R, idx)) : 0.0;
    g.stands_out = g.z > z_out;
    if (g.stands_out) standing->push_back(prefix + name);
    out->push_back(g);
  }
}

// Linear trend of the gap with machining time (um per hour) and its uncertainty: of the noise
// sigma s (times each observation's `scale`; empty: 1) and of a reference's leftover part
// (factor R, n x r; none: n x 0).
void FitDrift(const Eigen::VectorXd& r0, const Eigen::MatrixXd& R, const Eigen::VectorXd& scale,
              const std::vector<double>& t_s, double s, DiagnosisResult* out) {
  const auto n = r0.size();
  Eigen::MatrixXd T(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) T(i, 0) = 1.0, T(i, 1) = t_s[static_cast<std::size_t>(i)] / 3600.0;
  const Eigen::MatrixXd TtT = T.transpose() * T;
  if (std::abs(TtT.determinant()) > 1e-12) {
    const Eigen::Vector2d beta = TtT.ldlt().solve(T.transpose() * r0);
    out->drift_um_per_h = beta(1);
    const Eigen::Matrix2d inverse = TtT.inverse();
    out->drift_u_um_per_h = s * std::sqrt(inverse(1, 1));
    if (scale.size() > 0)
      out->drift_u_um_per_h = s * ((inverse * T.transpose()).row(1).transpose().cwiseProduct(scale)).norm();
    if (R.cols() > 0) {
      const Eigen::RowVectorXd slope = (inverse * T.transpose()).row(1) * R;  // um/h per factor column
      out->drift_u_um_per_h = std::hypot(out->drift_u_um_per_h, slope.norm());
    }
  }
}

// Whether the feature's points lie on circles about the Z line through `c`: their radii about it
// spread by at most 20 % of the mean. A line or a plane (M1's slot sides, the square's faces) has
// radii from 0 to half its length: its "harmonics" are its bow and tilt, and read as 1, 3, 5 lobes.
constexpr double kCircularRadiusSpread = 0.2;

bool IsCircularProfile(const std::vector<Eigen::Index>& idx, const std::vector<kinematics::Observation>& obs,
                       const Eigen::Vector3d& c) {
  double lo = 1e300, hi = 0.0, sum = 0.0;
  for (auto i : idx) {
    const Eigen::Vector3d d = obs[static_cast<std::size_t>(i)].cut.nominal_point_mm - c;
    const double rho = std::hypot(d.x(), d.y());
    lo = std::min(lo, rho), hi = std::max(hi, rho), sum += rho;
  }
  const double mean = sum / static_cast<double>(idx.size());
  return mean > 0 && hi - lo <= kCircularRadiusSpread * mean;
}

// The centre of a profile's nominal points: the circle through them in part XY (an algebraic
// fit, exact for points on a circle: x^2 + y^2 + D x + E y + F = 0 by least squares, about the
// centroid), at the centroid's Z, when the fit is well posed and its azimuths leave no gap above
// 120 deg; else the centroid. Hits missing on one side move the centroid off the circle's centre
// (the orders then leak into each other), not the circle.
Eigen::Vector3d ProfileCentre(const std::vector<Eigen::Index>& idx, const std::vector<kinematics::Observation>& obs) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (auto i : idx) c += obs[static_cast<std::size_t>(i)].cut.nominal_point_mm;
  c /= static_cast<double>(idx.size());
  if (idx.size() < 4) return c;
  const auto m = static_cast<Eigen::Index>(idx.size());
  Eigen::MatrixXd a(m, 3);
  Eigen::VectorXd b(m);
  for (Eigen::Index row = 0; row < m; ++row) {
    const Eigen::Vector3d d = obs[static_cast<std::size_t>(idx[static_cast<std::size_t>(row)])].cut.nominal_point_mm - c;
    a.row(row) << d.x(), d.y(), 1.0;
    b(row) = -(d.x() * d.x() + d.y() * d.y());
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  if (!(sv(2) > 1e-6 * sv(0))) return c;  // collinear points: no circle
  const Eigen::Vector3d def = svd.solve(b);
  const Eigen::Vector3d centre = c + Eigen::Vector3d(-0.5 * def(0), -0.5 * def(1), 0.0);
  std::vector<double> phi;
  for (auto i : idx) {
    const Eigen::Vector3d d = obs[static_cast<std::size_t>(i)].cut.nominal_point_mm - centre;
    phi.push_back(std::atan2(d.y(), d.x()));
  }
  std::sort(phi.begin(), phi.end());
  double gap = phi.front() + 2.0 * kPi - phi.back();
  for (std::size_t k = 1; k < phi.size(); ++k) gap = std::max(gap, phi[k] - phi[k - 1]);
  return gap <= 2.0 * kPi / 3.0 ? centre : c;
}

// Distinct azimuths among `phi` (rad; within 1e-6 rad, across the +-pi seam too): a profile probed
// at several levels repeats them, and orders beyond half their number are aliases.
int DistinctAzimuths(std::vector<double> phi) {
  std::sort(phi.begin(), phi.end());
  int n = 0;
  for (std::size_t k = 0; k < phi.size(); ++k) n += k == 0 || phi[k] - phi[k - 1] > 1e-6;
  if (n > 1 && phi.back() - phi.front() > 2.0 * kPi - 1e-6) --n;
  return n;
}

// The least-squares fit of y on [1, cos k phi, sin k phi], k = 1..kmax: coefficients, (X^T X)^-1
// and, when `gain` is given, (X^T X)^-1 X^T that maps y to them.
// False when an order's variance exceeds 100 x the equal-spacing 2 / m (its amplitude would be
// noise: azimuths too uneven or too few for that many orders) or the design is singular.
bool FitOrders(const std::vector<double>& phi, const Eigen::VectorXd& y, int kmax, Eigen::VectorXd* coef,
               Eigen::MatrixXd* cov, Eigen::MatrixXd* gain) {
  const auto m = static_cast<Eigen::Index>(phi.size());
  Eigen::MatrixXd X(m, 1 + 2 * kmax);
  for (Eigen::Index row = 0; row < m; ++row) {
    X(row, 0) = 1.0;
    for (int k = 1; k <= kmax; ++k) {
      const double a = k * phi[static_cast<std::size_t>(row)];
      X(row, 2 * k - 1) = std::cos(a), X(row, 2 * k) = std::sin(a);
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> normal(X.transpose() * X);
  const Eigen::VectorXd d = normal.vectorD();
  if (normal.info() != Eigen::Success || d.minCoeff() <= 1e-9 * d.maxCoeff()) return false;
  *cov = normal.solve(Eigen::MatrixXd::Identity(X.cols(), X.cols()));
  if (cov->diagonal().tail(2 * kmax).maxCoeff() > 100.0 * 2.0 / static_cast<double>(m)) return false;
  *coef = normal.solve(X.transpose() * y);
  if (gain) *gain = *cov * X.transpose();
  return true;
}

// The Rayleigh score of a profile order's energy (um^2) under noise of sigma and a reference's
// leftover part of whitened factor Z (2 x r, ProfileHarmonics): the z whose chi2_2 value
// has the normal score (ChiSquareZ) that energy has against SatterthwaiteLaw's c chi2_d.
double RayleighEquivalentZ(double energy_um2, double sigma, const Eigen::MatrixXd& Z) {
  const double zn = SpreadZ(energy_um2, 2, sigma, Z);
  const double v2 = 1.0 / 9.0;  // 2 / (9 k) at k = 2
  const double root = std::max(0.0, 1.0 - v2 + zn * std::sqrt(v2));
  return std::sqrt(2.0 * root * root * root);
}

// Harmonics 1..kmax of the gap around one circular profile (azimuth phi about its centre,
// ProfileCentre, part Z): least squares on [1, cos k phi, sin k phi], so that unevenly spaced
// azimuths (hits left out, a tilted hole seen about Z) keep the mean and the orders apart; a
// DFT's sums assume equal spacing. kmax: the most orders, up to min(max_harmonic, distinct azimuths / 2 - 1), that FitOrders
// accepts (a tilted hole probed at two levels has its azimuths in close pairs). energy = (a, b)
// C^-1 (a, b)^T, C the (a, b) block of (X^T X)^-1, z = sqrt(energy) / s: m A^2 / 2 and
// A / (s sqrt(2 / m)) on m equally spaced points. With a reference's leftover factor R (n x r),
// each order's share of it, whitened as the energy is (L^-1 G R_idx, C = L L^T, G the order's
// rows of the gain), and z is RayleighEquivalentZ. Amplitude and phase are r0's; energy, z and
// R's share are of `test` (r0 over the noise scales, R's rows alike: TestedGap). Appended to *all
// and *ref_z (2 x 0 without).
void ProfileHarmonics(const std::string& name, const std::vector<Eigen::Index>& idx,
                      const std::vector<kinematics::Observation>& obs, const Eigen::VectorXd& r0,
                      const TestedGap& test, double s, int max_harmonic, std::vector<HarmonicGap>* all,
                      std::vector<Eigen::MatrixXd>* ref_z) {
  const Eigen::MatrixXd& R = test.R;
  const Eigen::Vector3d c = ProfileCentre(idx, obs);
  if (!IsCircularProfile(idx, obs, c)) return;
  std::vector<double> phi(idx.size());
  Eigen::VectorXd y(static_cast<Eigen::Index>(idx.size())), y_test(y.size());
  for (std::size_t row = 0; row < idx.size(); ++row) {
    const Eigen::Vector3d d = obs[static_cast<std::size_t>(idx[row])].cut.nominal_point_mm - c;
    phi[row] = std::atan2(d.y(), d.x());
    y(static_cast<Eigen::Index>(row)) = r0(idx[row]);
    y_test(static_cast<Eigen::Index>(row)) = test.r(idx[row]);
  }
  Eigen::VectorXd coef, coef_test;
  Eigen::MatrixXd cov, gain;
  int kmax = std::min<int>(max_harmonic, DistinctAzimuths(phi) / 2 - 1);
  while (kmax >= 1 && !FitOrders(phi, y, kmax, &coef, &cov, R.cols() > 0 ? &gain : nullptr)) --kmax;
  if (kmax >= 1 && test.scaled) FitOrders(phi, y_test, kmax, &coef_test, &cov, nullptr);
  const Eigen::VectorXd& tested = test.scaled ? coef_test : coef;
  const Eigen::MatrixXd R_idx = RowsOf(R, idx);
  for (int k = 1; k <= kmax; ++k) {
    const Eigen::Vector2d ab(coef(2 * k - 1), coef(2 * k)), ab_test(tested(2 * k - 1), tested(2 * k));
    const double energy = ab_test.dot(cov.block<2, 2>(2 * k - 1, 2 * k - 1).inverse() * ab_test);
    HarmonicGap h{name, k, ab.norm(), RadToDeg(std::atan2(ab.y(), ab.x())), 0.0, false, energy};
    h.z = s > 0 ? std::sqrt(energy) / s : 0.0;
    Eigen::MatrixXd Z(2, 0);
    if (R.cols() > 0) {
      // C = L L^T: positive definite, since FitOrders accepted X^T X.
      const Eigen::LLT<Eigen::Matrix2d> c_factor(cov.block<2, 2>(2 * k - 1, 2 * k - 1));
      assert(c_factor.info() == Eigen::Success);
      Z = c_factor.matrixL().solve(gain.middleRows(2 * k - 1, 2) * R_idx);
      h.z = s > 0 ? RayleighEquivalentZ(energy, s, Z) : 0.0;
    }
    all->push_back(h);
    ref_z->push_back(std::move(Z));
  }
}

// Order k pooled over every circular profile that has it: S_k = sum of the profiles' energy_um2 (chi-square
// with 2 F_k degrees of freedom times sigma^2 under noise) against the profiles' residual sum of
// squares without it, an F test that needs no noise estimate from elsewhere (an error motion of
// more lobes than the neighbour spacing resolves inflates every other noise figure). Stands out
// below 1 % / (number of orders), Bonferroni, when S_k also stands out against the noise sigma.
// With a reference's leftover factor R, S_k's law is SatterthwaiteLaw's over the orders' stacked
// whitened factors `ref_z`, and the residual's share of R is taken off its sum of squares.
void PooledHarmonics(const std::vector<HarmonicGap>& all, const std::vector<Eigen::MatrixXd>& ref_z,
                     const PointGroups& by_feature, const TestedGap& test, double s, DiagnosisResult* out) {
  const Eigen::VectorXd& r0 = test.r;
  const Eigen::MatrixXd& R = test.R;
  double ssr = 0.0, n = 0.0, ref_ss = 0.0;
  for (const auto& [name, idx] : by_feature)
    if (idx.size() >= 8) {
      n += static_cast<double>(idx.size());
      for (auto i : idx) ssr += r0(i) * r0(i);
      if (R.cols() > 0) ref_ss += RowsOf(R, idx).squaredNorm();
    }
  struct OrderSum {
    double sum_um2 = 0.0;          // S_k
    int profiles = 0;              // F_k
    std::vector<std::size_t> of;   // its harmonics in `all`
  };
  std::map<int, OrderSum> energy;
  for (std::size_t j = 0; j < all.size(); ++j) {
    auto& e = energy[all[j].order];
    e.sum_um2 += all[j].energy_um2;
    e.profiles += 1;
    e.of.push_back(j);
  }
  for (const auto& [k, e] : energy) {
    const double d1 = 2.0 * e.profiles, d2 = n - 2.0 * e.profiles;
    if (e.profiles < 2 || d2 <= 30 || ssr - e.sum_um2 <= 0) continue;
    double p = FUpperTail((e.sum_um2 / d1) / ((ssr - e.sum_um2) / d2), d1, d2);
    // and beyond the noise sigma (chi-square with d1 degrees of freedom): on noise-free data
    // the F ratio of rounding residuals is meaningless.
    double p_noise = s > 0 ? FUpperTail((e.sum_um2 / d1) / (s * s), d1, 1e12) : 1.0;
    if (R.cols() > 0) {
      Eigen::MatrixXd Zk(2 * e.profiles, R.cols());
      for (std::size_t j = 0; j < e.of.size(); ++j) Zk.middleRows(2 * static_cast<Eigen::Index>(j), 2) = ref_z[e.of[j]];
      const double s2_hat = (ssr - e.sum_um2 - std::max(0.0, ref_ss - Zk.squaredNorm())) / d2;
      if (!(s2_hat > 0)) continue;
      const ChiSquareLaw law = SatterthwaiteLaw(2 * e.profiles, s2_hat, Zk);
      p = FUpperTail(e.sum_um2 / law.mean_um2, law.dof, d2);
      const ChiSquareLaw known = SatterthwaiteLaw(2 * e.profiles, s * s, Zk);
      p_noise = s > 0 ? FUpperTail(e.sum_um2 / known.mean_um2, known.dof, 1e12) : 1.0;
    }
    const double bound = 0.01 / static_cast<double>(energy.size());
    if (p < bound && p_noise < bound)
      out->standing_out.push_back(fmt::format("harmonic {} on {} circular profiles (pooled, p = {:.2g})", k, e.profiles, p));
  }
}

// C harmonics of every circular profile (a feature of at least 8 points), and which stand out;
// R: a reference's leftover factor (n x r; none: n x 0).
void CircularHarmonics(const PointGroups& by_feature, const std::vector<kinematics::Observation>& obs,
                       const Eigen::VectorXd& r0, const TestedGap& test, double s, int max_harmonic,
                       DiagnosisResult* out) {
  std::vector<HarmonicGap> all;
  std::vector<Eigen::MatrixXd> ref_z;
  for (const auto& [name, idx] : by_feature)
    if (idx.size() >= 8) ProfileHarmonics(name, idx, obs, r0, test, s, max_harmonic, &all, &ref_z);
  // Rayleigh tail with a Bonferroni bound at 1 %: P(z > t) = exp(-t^2 / 2) per test.
  const double t = all.empty() ? 0.0 : std::sqrt(2.0 * std::log(static_cast<double>(all.size()) / 0.01));
  for (auto& h : all) {
    h.stands_out = h.z > t;
    if (h.stands_out) out->standing_out.push_back("feature " + h.feature + " harmonic " + std::to_string(h.order));
  }
  PooledHarmonics(all, ref_z, by_feature, test, s, out);
  out->harmonics = std::move(all);
}

}  // namespace

void SummariseGap(const kinematics::MachineModel& machine, const testpieces::MeasuredObservations& mo,
                  const Eigen::VectorXd& r0, double s, const DiagnosisOptions& options, DiagnosisResult* out,
                  const Eigen::MatrixXd& reference_remaining_um) {
  const GapGroups groups = GroupGapPoints(machine, mo);
  const double z = options.stand_out_z;
  const Eigen::MatrixXd& R = reference_remaining_um;  // no column: none (any row count)
  assert(R.cols() == 0 || R.rows() == r0.size());
  const Eigen::VectorXd scale = NoiseScales(mo);
  const TestedGap test = Tested(r0, R, scale);
  GroupStats(groups.by_feature, r0, test.r, test.R, groups.t_s, s, z, &out->by_feature, &out->standing_out, "feature ");
  GroupStats(groups.by_op, r0, test.r, test.R, groups.t_s, s, z, &out->by_operation, &out->standing_out, "");
  GroupStats(groups.by_a, r0, test.r, test.R, groups.t_s, s, z, &out->by_a_index, &out->standing_out, "");
  FitDrift(r0, R, scale, groups.t_s, s, out);
  CircularHarmonics(groups.by_feature, mo.observations, r0, test, s, options.max_harmonic, out);
}

}  // namespace tpcal::pipeline::diagnosis_internal
