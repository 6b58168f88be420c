#include "kinematics/circular_test_analysis.h"

#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics {
namespace {

// File-local names carry a Circ prefix (unity build: one translation unit per target).

constexpr double kCircTwoPi = 2.0 * std::numbers::pi;

// The columns of the model, in this order (circular_test_analysis.h).
enum CircColumn : int {
  kCircOffset = 0, kCircCos, kCircSin, kCircSin2, kCircCos2,  // always fitted
  kCircBacklash1, kCircBacklash2, kCircServo, kCircSpike1, kCircSpike2,
  kCircNumColumns,
};
constexpr int kCircNumBase = 5;

double CircWrap(double a_rad) {
  double r = std::fmod(a_rad, kCircTwoPi);
  if (r < 0.0) r += kCircTwoPi;
  return r >= kCircTwoPi ? 0.0 : r;
}

std::string CircNum(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The reversals of axis k (0: e1, 1: e2): path angles (rad).
constexpr double kCircReversals[2][2] = {{0.0, std::numbers::pi}, {0.5 * std::numbers::pi, 1.5 * std::numbers::pi}};

// Path angle travelled since reversal phi_c in direction s, in [0, 2 pi).
double CircTravelled(double phi, double phi_c, double s) { return CircWrap(s * (phi - phi_c)); }

// N_k: half the radial part of the unit lag after the axis's last reversal.
double CircBacklashColumn(int k, double phi, double s) {
  const double a0 = CircTravelled(phi, kCircReversals[k][0], s), a1 = CircTravelled(phi, kCircReversals[k][1], s);
  const double last = a0 <= a1 ? kCircReversals[k][0] : kCircReversals[k][1];
  return 0.5 * std::cos(phi - last);
}

// P_k: the two glitches of axis k, unit height outward.
double CircSpikeColumn(int k, double phi, double s, double decay_rad) {
  double v = 0.0;
  for (double phi_c : kCircReversals[k])
    v += std::exp(-CircTravelled(phi, phi_c, s) / decay_rad) * std::cos(phi - phi_c);
  return v;
}

// Readings strictly after a reversal of axis k (alpha > 0) and within 2 decay lengths of it.
int CircSpikeReadings(int k, const std::vector<double>& phi, const std::vector<double>& s, double decay_rad) {
  int n = 0;
  for (std::size_t i = 0; i < phi.size(); ++i)
    for (double phi_c : kCircReversals[k])
      if (const double alpha = CircTravelled(phi[i], phi_c, s[i]); alpha > 0.0 && alpha <= 2.0 * decay_rad) {
        ++n;
        break;
      }
  return n;
}

int CircRank(const Eigen::MatrixXd& a, double tol) {
  Eigen::MatrixXd scaled = a;
  for (int c = 0; c < scaled.cols(); ++c) {
    const double n = scaled.col(c).norm();
    if (n > 0.0) scaled.col(c) /= n;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  qr.setThreshold(tol);
  return static_cast<int>(qr.rank());
}

// The range statistics of ISO 230-4 on one set of dl values. The least-squares circles of each
// direction and of both, and the interpolation brackets of H, depend only on the angles: set up
// once, then evaluated on the data and on every bootstrap draw.
struct CircRangeStats {
  double g[3] = {0.0, 0.0, 0.0};  // ccw, cw, combined
  double h = 0.0;
};

struct CircBracket {
  int own = 0, lo = 0, hi = 0;
  double w = 0.0;  // other = (1 - w) y[lo] + w y[hi]
};

struct CircRangePlan {
  std::vector<int> rows[3];  // readings of ccw, cw, all
  bool g_ok[3] = {false, false, false};
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr[3];
  bool h_ok = false;
  std::vector<CircBracket> brackets;
};

// Brackets of the readings `own` in the periodic sequence of `other` (reduced angles, sorted).
void CircAddBrackets(const std::vector<double>& phi, const std::vector<int>& own, const std::vector<int>& other,
                     std::vector<CircBracket>* out) {
  std::vector<int> sorted = other;
  std::sort(sorted.begin(), sorted.end(), [&](int x, int y) { return phi[x] < phi[y]; });
  const int n = static_cast<int>(sorted.size());
  for (int i : own) {
    const auto it = std::upper_bound(sorted.begin(), sorted.end(), phi[i], [&](double v, int j) { return v < phi[j]; });
    const int hi_pos = static_cast<int>(it - sorted.begin()) % n;
    const int lo_pos = (hi_pos + n - 1) % n;
    const int lo = sorted[lo_pos], hi = sorted[hi_pos];
    double span = phi[hi] - phi[lo], at = phi[i] - phi[lo];
    if (span <= 0.0) span += kCircTwoPi;  // wraps through 0
    if (at < 0.0) at += kCircTwoPi;
    CircBracket b;
    b.own = i, b.lo = lo, b.hi = hi;
    b.w = span > 0.0 && span < kCircTwoPi ? std::clamp(at / span, 0.0, 1.0) : 0.5;
    out->push_back(b);
  }
}

CircRangePlan CircMakeRangePlan(const std::vector<double>& phi, const std::vector<double>& s, double tol) {
  CircRangePlan p;
  for (int i = 0; i < static_cast<int>(phi.size()); ++i) {
    p.rows[s[i] > 0 ? 0 : 1].push_back(i);
    p.rows[2].push_back(i);
  }
  for (int d = 0; d < 3; ++d) {
    const int n = static_cast<int>(p.rows[d].size());
    if (n < 3) continue;
    Eigen::MatrixXd a(n, 3);
    for (int r = 0; r < n; ++r) {
      const double f = phi[p.rows[d][r]];
      a(r, 0) = 1.0, a(r, 1) = std::cos(f), a(r, 2) = std::sin(f);
    }
    p.qr[d].setThreshold(tol);
    p.qr[d].compute(a);
    p.g_ok[d] = p.qr[d].rank() == 3 && (d < 2 || (!p.rows[0].empty() && !p.rows[1].empty()));
  }
  p.h_ok = p.rows[0].size() >= 2 && p.rows[1].size() >= 2;
  if (p.h_ok) {
    CircAddBrackets(phi, p.rows[0], p.rows[1], &p.brackets);
    CircAddBrackets(phi, p.rows[1], p.rows[0], &p.brackets);
  }
  return p;
}

CircRangeStats CircEvaluateRanges(const CircRangePlan& p, const std::vector<double>& phi, const Eigen::VectorXd& y) {
  CircRangeStats st;
  for (int d = 0; d < 3; ++d) {
    if (!p.g_ok[d]) continue;
    const int n = static_cast<int>(p.rows[d].size());
    Eigen::VectorXd yd(n);
    for (int r = 0; r < n; ++r) yd(r) = y(p.rows[d][r]);
    const Eigen::Vector3d c = p.qr[d].solve(yd);
    double lo = 1e300, hi = -1e300;
    for (int r = 0; r < n; ++r) {
      const double f = phi[p.rows[d][r]];
      const double dev = yd(r) - (c(0) + c(1) * std::cos(f) + c(2) * std::sin(f));
      lo = std::min(lo, dev), hi = std::max(hi, dev);
    }
    st.g[d] = hi - lo;
  }
  for (const CircBracket& b : p.brackets)
    st.h = std::max(st.h, std::abs(y(b.own) - ((1.0 - b.w) * y(b.lo) + b.w * y(b.hi))));
  return st;
}

struct CircBootstrap {
  bool known = false;
  double sd_g[3] = {0.0, 0.0, 0.0}, sd_h = 0.0;
  // Bootstrap mean - the figure of the fitted model alone: the share of the readings' noise.
  double bias_g[3] = {0.0, 0.0, 0.0}, bias_h = 0.0;
};

// `model`: the range figures of the fitted values (noise-free), the bootstrap's truth.
CircBootstrap CircRunBootstrap(const CircRangePlan& p, const std::vector<double>& phi, const Eigen::VectorXd& fitted,
                               const Eigen::VectorXd& resid, int dof, const CircRangeStats& model,
                               const CircularTestOptions& options) {
  CircBootstrap out;
  const int n = static_cast<int>(resid.size());
  if (options.bootstrap_samples <= 0 || dof <= 0) return out;
  out.known = true;
  const double inflate = std::sqrt(static_cast<double>(n) / dof);
  std::mt19937_64 rng(options.bootstrap_seed);
  double sum[4] = {0, 0, 0, 0}, sum2[4] = {0, 0, 0, 0};
  Eigen::VectorXd y(n);
  for (int b = 0; b < options.bootstrap_samples; ++b) {
    for (int i = 0; i < n; ++i) {
      const int j = std::min(n - 1, static_cast<int>(UniformUnit(rng) * n));
      y(i) = fitted(i) + inflate * resid(j);
    }
    const CircRangeStats st = CircEvaluateRanges(p, phi, y);
    const double v[4] = {st.g[0], st.g[1], st.g[2], st.h};
    for (int k = 0; k < 4; ++k) sum[k] += v[k], sum2[k] += v[k] * v[k];
  }
  const double nb = options.bootstrap_samples;
  const double val[4] = {model.g[0], model.g[1], model.g[2], model.h};
  double sd[4], bias[4];
  for (int k = 0; k < 4; ++k) {
    const double mean = sum[k] / nb;
    sd[k] = std::sqrt(std::max(0.0, (sum2[k] - nb * mean * mean) / (nb - 1.0)));
    bias[k] = mean - val[k];
  }
  for (int d = 0; d < 3; ++d) out.sd_g[d] = sd[d], out.bias_g[d] = bias[d];
  out.sd_h = sd[3], out.bias_h = bias[3];
  return out;
}

Status CircCheck(const BallbarInstallation& circle, const std::vector<CircularReading>& readings,
                 const CircularTestOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (circle.kind != BallbarKind::kCircle)
    return Status(StatusCode::kInvalidArgument, "ball bar '" + circle.name + "' is a " +
                                                    BallbarKindName(circle.kind) +
                                                    " installation, not a circle of two linear axes");
  if (!(std::isfinite(circle.nominal_length_mm) && circle.nominal_length_mm > 0.0))
    return Status(StatusCode::kInvalidArgument, "ball bar '" + circle.name + "': the radius must be finite and > 0");
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const CircularReading& r = readings[i];
    if (std::isfinite(r.angle_deg) && std::isfinite(r.dl_um)) continue;
    const std::string where = r.line > 0 ? "line " + std::to_string(r.line) : "reading " + std::to_string(i + 1);
    return Status(StatusCode::kInvalidArgument, where + ": the angle or dl is not finite");
  }
  return Status();
}

// The candidate columns of every reading (all kCircNumColumns; which are fitted is decided later).
Eigen::MatrixXd CircDesign(const std::vector<double>& phi, const std::vector<double>& s, double decay_rad) {
  const int n = static_cast<int>(phi.size());
  Eigen::MatrixXd a(n, kCircNumColumns);
  for (int i = 0; i < n; ++i) {
    const double f = phi[i];
    a(i, kCircOffset) = 1.0;
    a(i, kCircCos) = std::cos(f);
    a(i, kCircSin) = std::sin(f);
    a(i, kCircSin2) = std::sin(2.0 * f);
    a(i, kCircCos2) = std::cos(2.0 * f);
    a(i, kCircBacklash1) = CircBacklashColumn(0, f, s[i]);
    a(i, kCircBacklash2) = CircBacklashColumn(1, f, s[i]);
    a(i, kCircServo) = s[i] * std::sin(2.0 * f);
    a(i, kCircSpike1) = CircSpikeColumn(0, f, s[i], decay_rad);
    a(i, kCircSpike2) = CircSpikeColumn(1, f, s[i], decay_rad);
  }
  return a;
}

struct CircFit {
  std::vector<int> columns;        // fitted candidate columns
  std::string why_not[kCircNumColumns];  // for the others
  Eigen::VectorXd x;               // per candidate column (0 when not fitted)
  Eigen::MatrixXd cov;             // per candidate column, sigma^2 (A^T A)^-1 (zero when not fitted)
  Eigen::VectorXd fitted, resid;
};

// Least squares on the chosen columns: scaled-column QR with column pivoting; (A^T A)^-1 from R.
void CircSolve(const Eigen::MatrixXd& all, const Eigen::VectorXd& y, CircFit* fit) {
  const int n = static_cast<int>(all.rows()), m = static_cast<int>(fit->columns.size());
  Eigen::MatrixXd a(n, m);
  Eigen::VectorXd scale(m);
  for (int c = 0; c < m; ++c) {
    a.col(c) = all.col(fit->columns[c]);
    scale(c) = 1.0 / a.col(c).norm();
    a.col(c) *= scale(c);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::VectorXd xs = qr.solve(y);
  const Eigen::MatrixXd r = qr.matrixR().topLeftCorner(m, m).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_inv = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(m, m));
  const Eigen::MatrixXd p = qr.colsPermutation();
  const Eigen::MatrixXd inv_s = p * r_inv * r_inv.transpose() * p.transpose();
  fit->x = Eigen::VectorXd::Zero(kCircNumColumns);
  fit->cov = Eigen::MatrixXd::Zero(kCircNumColumns, kCircNumColumns);
  for (int c = 0; c < m; ++c) {
    fit->x(fit->columns[c]) = scale(c) * xs(c);
    for (int d = 0; d < m; ++d) fit->cov(fit->columns[c], fit->columns[d]) = scale(c) * scale(d) * inv_s(c, d);
  }
  fit->fitted = a * xs;
  fit->resid = y - fit->fitted;
}

}  // namespace

Status CircularTestOptions::Validate() const {
  if (!(std::isfinite(spike_decay_deg) && spike_decay_deg > 0.0))
    return Status(StatusCode::kInvalidArgument, "spike_decay_deg must be finite and > 0");
  if (min_spike_readings < 1) return Status(StatusCode::kInvalidArgument, "min_spike_readings must be >= 1");
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1.0))
    return Status(StatusCode::kInvalidArgument, "rank_tolerance must be in (0, 1)");
  if (bootstrap_samples != 0 && bootstrap_samples < 20)
    return Status(StatusCode::kInvalidArgument, "bootstrap_samples must be 0 or >= 20");
  return Status();
}

const CircularFigure* CircularTestResult::Find(const std::string& name) const {
  for (const CircularFigure& f : figures)
    if (f.name == name) return &f;
  return nullptr;
}

Result<CircularTestResult> AnalyseCircularTest(const BallbarInstallation& circle,
                                               const std::vector<CircularReading>& readings,
                                               const CircularTestOptions& options) {
  // 1. Inputs: the plane, the reduced angles, the direction signs.
  TPCAL_RETURN_IF_ERROR(CircCheck(circle, readings, options));
  CircularTestResult out;
  out.plane = BallbarPlaneName(circle.plane);
  out.radius_mm = circle.nominal_length_mm;
  const double radius = circle.nominal_length_mm;
  const std::string key1(1, static_cast<char>(std::tolower(out.plane[0])));
  const std::string key2(1, static_cast<char>(std::tolower(out.plane[1])));
  const std::string ax1(1, out.plane[0]), ax2(1, out.plane[1]);
  const int n = static_cast<int>(readings.size());
  std::vector<double> phi(n), s(n);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    phi[i] = CircWrap(DegToRad(readings[i].angle_deg));
    s[i] = readings[i].ccw ? 1.0 : -1.0;
    y(i) = readings[i].dl_um;
    (readings[i].ccw ? out.ccw_rows : out.cw_rows) += 1;
  }
  const bool both = out.ccw_rows > 0 && out.cw_rows > 0;
  const double decay_rad = DegToRad(options.spike_decay_deg);

  // 2. The columns: the five of every test, then each further term if it adds rank.
  const Eigen::MatrixXd all = CircDesign(phi, s, decay_rad);
  CircFit fit;
  for (int c = 0; c < kCircNumBase; ++c) fit.columns.push_back(c);
  if (n < kCircNumBase || CircRank(all.leftCols(kCircNumBase), options.rank_tolerance) < kCircNumBase)
    return Status(StatusCode::kInvalidArgument,
                  "the readings do not determine the offset, centring, squareness and scale terms of the circular "
                  "test (they need 5 or more distinct path angles modulo 360 deg; " + std::to_string(n) +
                      " readings given)");
  fit.why_not[kCircServo] = both ? "" : "needs both path directions (cw and ccw): it is the difference between them";
  for (int k = 0; k < 2; ++k) {
    const int c = k == 0 ? kCircSpike1 : kCircSpike2;
    if (!options.fit_spikes) {
      fit.why_not[c] = "not fitted (fit_spikes is false)";
      continue;
    }
    const int near = CircSpikeReadings(k, phi, s, decay_rad);
    if (near < options.min_spike_readings)
      fit.why_not[c] = std::to_string(near) + " readings lie strictly after a reversal of " + (k ? ax2 : ax1) +
                       " and within 2 decay lengths (" + CircNum(2.0 * options.spike_decay_deg) +
                       " deg) of it, fewer than min_spike_readings = " + std::to_string(options.min_spike_readings) +
                       ": the sampling is too coarse to see the spike";
  }
  for (int c = kCircNumBase; c < kCircNumColumns; ++c) {
    if (!fit.why_not[c].empty()) continue;
    std::vector<int> trial = fit.columns;
    trial.push_back(c);
    Eigen::MatrixXd a(n, static_cast<int>(trial.size()));
    for (int j = 0; j < static_cast<int>(trial.size()); ++j) a.col(j) = all.col(trial[j]);
    if (CircRank(a, options.rank_tolerance) == static_cast<int>(trial.size())) {
      fit.columns = trial;
    } else {
      fit.why_not[c] = "the readings do not separate it from the other terms (its column adds no rank: e.g. they "
                       "do not straddle the reversal points)";
    }
  }
  const int m = static_cast<int>(fit.columns.size());
  if (n < m)
    return Status(StatusCode::kInvalidArgument, "fewer readings (" + std::to_string(n) + ") than unknowns (" +
                                                    std::to_string(m) + ") of the circular test");

  // 3. Least squares, sigma, covariance.
  CircSolve(all, y, &fit);
  out.rows = n, out.unknowns = m, out.dof = n - m;
  out.sigma_known = out.dof > 0;
  out.sigma_um = out.sigma_known ? std::sqrt(fit.resid.squaredNorm() / out.dof) : 0.0;
  for (int i = 0; i < n; ++i) out.residuals_um.push_back(fit.resid(i));
  const double var = out.sigma_um * out.sigma_um;
  const double k95 = out.sigma_known ? internal::StudentTQuantile975(out.dof) : 0.0;

  // 4. The ISO 230-4 range figures and their bootstrap.
  const CircRangePlan plan = CircMakeRangePlan(phi, s, options.rank_tolerance);
  const CircRangeStats ranges = CircEvaluateRanges(plan, phi, y);
  const CircRangeStats model_ranges = CircEvaluateRanges(plan, phi, fit.fitted);
  const CircBootstrap boot = CircRunBootstrap(plan, phi, fit.fitted, fit.resid, out.dof, model_ranges, options);
  const std::string boot_words =
      boot.known ? "; u: sd of " + std::to_string(options.bootstrap_samples) +
                       " residual-bootstrap draws (fitted model + residuals resampled, x sqrt(rows / dof))"
                 : "; u unknown (" + std::string(out.sigma_known ? "bootstrap_samples = 0" : "dof = 0") + ")";
  auto range_figure = [&](const std::string& name, const std::string& symbol, bool ok, double value, double model,
                          double u, double bias, const std::string& what, const std::string& why_not) {
    CircularFigure f;
    f.name = name, f.symbol = symbol, f.unit = "um";
    f.identifiable = ok;
    if (!ok) {
      f.note = why_not;
      out.figures.push_back(f);
      return;
    }
    f.value = value;
    f.u = boot.known ? u : 0.0;
    f.note = what + boot_words + "; the fitted model alone gives " + CircNum(model) + " um" +
             (boot.known ? ", the readings' noise adds about " + CircNum(bias) + " um (bootstrap mean - that)" : "");
    if (f.u > 0.0) f.ci95_low = f.value - k95 * f.u, f.ci95_high = f.value + k95 * f.u;
    out.figures.push_back(f);
  };
  const char* dir_name[2] = {"ccw", "cw"};
  for (int d = 0; d < 2; ++d) {
    const int count = d == 0 ? out.ccw_rows : out.cw_rows;
    range_figure(std::string("circular_deviation_") + dir_name[d], "G", plan.g_ok[d], ranges.g[d], model_ranges.g[d],
                 boot.sd_g[d], boot.bias_g[d],
                 std::string("ISO 230-4: max - min of dl about the least-squares circle of the ") + dir_name[d] +
                     " readings",
                 count == 0 ? std::string("no ") + dir_name[d] + " readings"
                            : std::string("the ") + dir_name[d] + " readings lie at fewer than 3 distinct angles");
  }
  range_figure("circular_deviation", "G", plan.g_ok[2], ranges.g[2], model_ranges.g[2], boot.sd_g[2], boot.bias_g[2],
               "max - min of dl of both directions about their common least-squares circle",
               "needs both path directions (cw and ccw): the combined path");
  range_figure("circular_hysteresis", "H", plan.h_ok, ranges.h, model_ranges.h, boot.sd_h, boot.bias_h,
               "ISO 230-4: the largest |dl_ccw - dl_cw| at the readings' angles, the other direction linearly "
               "interpolated (common centre, which cancels)",
               both ? "needs 2 or more readings in each direction"
                    : "needs both path directions (cw and ccw): it is the difference between them");

  // 5. The model figures: display value = gain * coefficient.
  auto model_figure = [&](const std::string& name, const std::string& symbol, const std::string& unit, int column,
                          double gain, const std::string& what, bool setup) {
    CircularFigure f;
    f.name = name, f.symbol = symbol, f.unit = unit, f.setup = setup;
    const bool fitted = std::find(fit.columns.begin(), fit.columns.end(), column) != fit.columns.end();
    f.identifiable = fitted;
    if (!fitted) {
      f.note = fit.why_not[column];
      out.figures.push_back(f);
      return;
    }
    f.value = gain * fit.x(column);
    f.u = out.sigma_known ? std::abs(gain) * std::sqrt(std::max(0.0, var * fit.cov(column, column))) : 0.0;
    if (f.u > 0.0) f.ci95_low = f.value - k95 * f.u, f.ci95_high = f.value + k95 * f.u;
    f.note = (setup ? "set-up: " : "") + what + (out.sigma_known ? "" : "; u unknown (dof = 0)");
    out.figures.push_back(f);
  };
  const double per_radius = 2.0 * 1000.0 / radius;  // 2 * coefficient (um) / R (mm), in urad or um/m
  const double sq_sign = circle.plane == BallbarPlane::kZX ? 1.0 : -1.0;
  const char* sq_symbol = circle.plane == BallbarPlane::kXY ? "E_C(0X)Y" : circle.plane == BallbarPlane::kYZ
                                                                            ? "E_A(0Y)Z" : "E_B(0X)Z";
  model_figure("squareness", sq_symbol, "urad", kCircSin2, sq_sign * per_radius,
               std::string("ISO 230-1 ") + sq_symbol + " = " + (sq_sign > 0 ? "+" : "-") +
                   "2 A / R, A the sin 2 phi term of dl (um), R (mm)",
               false);
  model_figure("scale_mismatch", "", "um/m", kCircCos2, per_radius,
               "scale of " + ax1 + " - scale of " + ax2 + " (E_" + ax1 + ax1 + " and E_" + ax2 + ax2 +
                   " per metre of travel) = 2 B / R, B the cos 2 phi term of dl (um); the mean scale is in the bar "
                   "length offset",
               false);
  model_figure("servo_mismatch", "", "urad", kCircServo, -per_radius,
               "path-angle lag of " + ax2 + " behind " + ax1 + " = -2 M / R, M the s sin 2 phi term (s = +1 ccw, -1 "
                   "cw); a time lag dt at path speed v: dt = lag R / v",
               false);
  for (int k = 0; k < 2; ++k) {
    const std::string a = k ? key2 : key1, A = k ? ax2 : ax1;
    model_figure("backlash_" + a, "", "um", k ? kCircBacklash2 : kCircBacklash1, 1.0,
                 "lost motion of " + A + " at its reversals (+: the step after the reversal points outward), " +
                     (both ? std::string("from the difference between the directions")
                           : std::string("from the step at the reversals within the one direction (correlated with "
                                         "the squareness term)")),
                 false);
  }
  for (int k = 0; k < 2; ++k) {
    const std::string a = k ? key2 : key1, A = k ? ax2 : ax1;
    model_figure("reversal_spike_" + a, "", "um", k ? kCircSpike2 : kCircSpike1, 1.0,
                 "peak outward deviation just after the reversals of " + A + ": height of the glitch exp(-alpha / " +
                     CircNum(options.spike_decay_deg) + " deg) fitted over both reversals and the directions present",
                 false);
  }
  model_figure("bar_length_offset", "", "um", kCircOffset, 1.0,
               "constant of dl: the bar-length calibration, plus R times the mean scale of " + ax1 + " and " + ax2,
               true);
  model_figure("centre_offset_" + key1, "", "um", kCircCos, 1.0,
               "the cos phi term of dl: the path centre minus the workpiece ball along " + ax1, true);
  model_figure("centre_offset_" + key2, "", "um", kCircSin, 1.0,
               "the sin phi term of dl: the path centre minus the workpiece ball along " + ax2, true);

  out.conventions = {
      "plane " + out.plane + ": the path angle phi runs from +" + ax1 + " toward +" + ax2 +
          "; ccw: phi increases, cw: phi decreases; dl = bar length - nominal length (+: longer, the path outside "
          "the circle)",
      std::string("squareness: ISO 230-1 ") + sq_symbol + " (kinematics/conventions.h signs), urad",
      "scale_mismatch: linear positioning scale of " + ax1 + " minus that of " + ax2 + " (um/m; + : " + ax1 +
          " travels further per commanded metre than " + ax2 + ")",
      "backlash: + is lost motion (the axis lags its new direction by half the value after each of its "
      "reversals); reversal spikes: + is outward",
      "servo_mismatch: + when " + ax2 + " lags " + ax1 + " (urad of path angle)",
      "set-up terms (bar_length_offset, centre offsets) are fitted and removed; they are not machine figures",
      out.sigma_known ? "u: k = 1, sigma from the residuals with dof = rows - unknowns; 95 % intervals Student t"
                      : "dof = 0: sigma unknown, no u is given",
  };
  return out;
}

}  // namespace tpcal::kinematics
