#include "pipeline/scan_cells.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "core/units.h"

namespace tpcal::pipeline {

Status ScanCellOptions::Validate() const {
  if (target_cells == 0) return Status(StatusCode::kInvalidArgument, "scan cells: target_cells must be at least 1");
  if (!(max_cell_mm > 0) || !(max_cell_deg > 0) || !(max_normal_turn_deg > 0) || !(max_step_mm > 0) || !(max_time_step_s > 0))
    return Status(StatusCode::kInvalidArgument,
                  "scan cells: max_cell_mm, max_cell_deg, max_normal_turn_deg, max_step_mm and max_time_step_s must be positive");
  return {};
}

namespace {

// Normal deviation of one observation, mm.
double NormalDeviation_mm(const kinematics::Observation& o) {
  return o.cut.nominal_normal.dot(o.measured_mm - o.cut.nominal_point_mm);
}

// The smooth part of each feature's deviations: a quadratic in the nominal position (about the
// feature's centroid, in units of its RMS extent) fitted by least squares to all its points. A
// cell's line is fitted to the deviations less it, so that the curvature of what the quadratic
// holds (a hole's offset and tilt: harmonics 0 to 2, a face's bow) is not filtered: 25 um of raw
// hole offset over a 10 deg cell is otherwise attenuated by 0.13 % (30 nm); the base fit takes
// most of it back and leaves a first harmonic of about 8 nm in one phase on every hole, which
// the diagnosis of 2e6 points finds (p = 4e-11 on the bench scan).
class FeatureTrends {
 public:
  using Terms = Eigen::Matrix<double, 10, 1>;

  FeatureTrends(const std::vector<kinematics::Observation>& obs, std::size_t groups) : fit_(groups) {
    std::vector<std::vector<std::uint32_t>> members(groups);
    for (std::size_t i = 0; i < obs.size(); ++i) members[static_cast<std::size_t>(obs[i].group)].push_back(static_cast<std::uint32_t>(i));
    ParallelForEach(groups, obs.size() >= kParallelMinPoints, [&](std::size_t g) { fit_[g] = Fit(obs, members[g]); });
  }

  // The quadratic of o's feature at o's nominal position (mm).
  double At(const kinematics::Observation& o) const {
    const Quadratic& q = fit_[static_cast<std::size_t>(o.group)];
    return q.coef.dot(TermsAt((o.cut.nominal_point_mm - q.centre_mm) / q.extent_mm));
  }

 private:
  struct Quadratic {
    Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
    double extent_mm = 1.0;
    Terms coef = Terms::Zero();
  };

  static Terms TermsAt(const Eigen::Vector3d& u) {
    Terms t;
    t << 1.0, u.x(), u.y(), u.z(), u.x() * u.x(), u.y() * u.y(), u.z() * u.z(), u.x() * u.y(), u.x() * u.z(),
        u.y() * u.z();
    return t;
  }

  // Normal equations; directions below 1e-10 of the largest eigenvalue (a plane's normal
  // coordinate, a circle's x^2 + y^2) are left out: only the fitted values matter.
  static Quadratic Fit(const std::vector<kinematics::Observation>& obs, const std::vector<std::uint32_t>& idx) {
    Quadratic q;
    if (idx.size() < 20) return q;
    for (auto i : idx) q.centre_mm += obs[i].cut.nominal_point_mm;
    q.centre_mm /= static_cast<double>(idx.size());
    double ss = 0.0;
    for (auto i : idx) ss += (obs[i].cut.nominal_point_mm - q.centre_mm).squaredNorm();
    q.extent_mm = std::max(1e-3, std::sqrt(ss / static_cast<double>(idx.size())));
    Eigen::Matrix<double, 10, 10> ata = Eigen::Matrix<double, 10, 10>::Zero();
    Terms atb = Terms::Zero();
    for (auto i : idx) {
      const Terms t = TermsAt((obs[i].cut.nominal_point_mm - q.centre_mm) / q.extent_mm);
      ata.selfadjointView<Eigen::Lower>().rankUpdate(t);
      atb += t * NormalDeviation_mm(obs[i]);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 10, 10>> eig(ata.selfadjointView<Eigen::Lower>());
    const Terms& ev = eig.eigenvalues();
    Terms z = eig.eigenvectors().transpose() * atb;
    for (int k = 0; k < 10; ++k) z(k) = ev(k) > 1e-10 * ev(9) ? z(k) / ev(k) : 0.0;
    q.coef = eig.eigenvectors() * z;
    return q;
  }

  std::vector<Quadratic> fit_;
};

double RotaryStep_rad(double a, double b) { return std::abs(std::remainder(b - a, 2.0 * kPi)); }

// The observations in the order cells are made of: `at[k]` is the k-th one's index, and cell c
// holds the k in [start[c], start[c + 1]).
struct Cells {
  std::vector<std::size_t> at, start;
};

// Whether point i may join the cell that starts at `first` and ends at i - 1 (file order).
bool Continues(const std::vector<kinematics::Observation>& obs, std::size_t first, std::size_t i,
               const ScanCellOptions& o) {
  const kinematics::Observation& a = obs[i - 1];
  const kinematics::Observation& b = obs[i];
  if (a.group != b.group || a.cut.axes.op != b.cut.axes.op) return false;
  if ((b.cut.nominal_point_mm - a.cut.nominal_point_mm).norm() > o.max_step_mm) return false;
  const double dt_s = b.cut.axes.t_s - a.cut.axes.t_s;
  if (std::abs(dt_s) > o.max_time_step_s) return false;
  if (i - first >= 2) {  // cutting time runs one way along a cell
    const double dt0_s = obs[first + 1].cut.axes.t_s - obs[first].cut.axes.t_s;
    // Cut together (one plunge, one turn): the measured depth moves the associated cutting time by
    // microseconds, either way.
    constexpr double kSameTime_s = 0.1;
    if ((dt0_s > kSameTime_s && dt_s < -kSameTime_s) || (dt0_s < -kSameTime_s && dt_s > kSameTime_s)) return false;
  }
  // One feed direction along a cell (a zigzag face is not pooled across its passes).
  const Eigen::Vector3d va(a.cut.du.axes.x_mm, a.cut.du.axes.y_mm, a.cut.du.axes.z_mm);
  const Eigen::Vector3d vb(b.cut.du.axes.x_mm, b.cut.du.axes.y_mm, b.cut.du.axes.z_mm);
  if (va.dot(vb) < 0.9 * va.norm() * vb.norm()) return false;
  if (a.cut.du.axes.c_rad * b.cut.du.axes.c_rad < 0 || a.cut.du.axes.a_rad * b.cut.du.axes.a_rad < 0) return false;
  const kinematics::Observation& f = obs[first];
  const double cos_max = std::cos(DegToRad(o.max_normal_turn_deg));
  if (f.cut.nominal_normal.dot(b.cut.nominal_normal) < cos_max) return false;
  if ((b.cut.nominal_point_mm - f.cut.nominal_point_mm).norm() > o.max_cell_mm) return false;
  const kinematics::AxisState& p = f.cut.axes;
  const kinematics::AxisState& q = b.cut.axes;
  if (std::abs(q.x_mm - p.x_mm) > o.max_cell_mm || std::abs(q.y_mm - p.y_mm) > o.max_cell_mm ||
      std::abs(q.z_mm - p.z_mm) > o.max_cell_mm)
    return false;
  const double max_rad = DegToRad(o.max_cell_deg);
  return RotaryStep_rad(p.a_rad, q.a_rad) <= max_rad && RotaryStep_rad(p.b_rad, q.b_rad) <= max_rad &&
         RotaryStep_rad(p.c_rad, q.c_rad) <= max_rad;
}

// Consecutive points of one scan line, in file order.
Cells ScanLineCells(const std::vector<kinematics::Observation>& obs, std::size_t cap, const ScanCellOptions& options) {
  Cells c;
  c.at.resize(obs.size());
  std::iota(c.at.begin(), c.at.end(), std::size_t{0});
  c.start.push_back(0);
  for (std::size_t i = 1; i < obs.size(); ++i)
    if (i - c.start.back() >= cap || !Continues(obs, c.start.back(), i, options)) c.start.push_back(i);
  return c;
}

// The grid bin of one observation: feature, operation, feed direction, a max_time_step_s window of
// cutting time, max_cell_mm of every linear axis command and of the nominal point, max_cell_deg of
// every rotary axis command and half max_normal_turn_deg of the normal's polar angles.
using GridKey = std::array<std::int64_t, 15>;

GridKey GridKeyOf(const kinematics::Observation& o, const ScanCellOptions& opt) {
  const kinematics::CutPoint& cut = o.cut;
  const Eigen::Vector3d feed(cut.du.axes.x_mm, cut.du.axes.y_mm, cut.du.axes.z_mm);
  Eigen::Index axis = 0;
  const double largest = feed.cwiseAbs().maxCoeff(&axis);
  const std::int64_t linear = largest > 1e-12 ? 1 + 2 * axis + (feed(axis) > 0) : 0;
  auto sign = [](double v) { return std::int64_t{v > 0} - std::int64_t{v < 0}; };
  const std::int64_t direction = linear * 9 + (sign(cut.du.axes.c_rad) + 1) * 3 + sign(cut.du.axes.a_rad) + 1;
  auto bin = [](double v, double width) { return static_cast<std::int64_t>(std::floor(v / width)); };
  const double mm = opt.max_cell_mm, rad = DegToRad(opt.max_cell_deg), turn = DegToRad(opt.max_normal_turn_deg) / 2;
  const Eigen::Vector3d& p = cut.nominal_point_mm;
  const Eigen::Vector3d& n = cut.nominal_normal;
  const kinematics::AxisState& q = cut.axes;
  return {o.group,          q.op,
          direction,        bin(q.t_s, opt.max_time_step_s),
          bin(q.x_mm, mm),  bin(q.y_mm, mm),
          bin(q.z_mm, mm),  bin(q.a_rad, rad),
          bin(q.b_rad, rad), bin(q.c_rad, rad),
          bin(p.x(), mm),   bin(p.y(), mm),
          bin(p.z(), mm),   bin(std::acos(std::clamp(n.z(), -1.0, 1.0)), turn),
          bin(std::atan2(n.y(), n.x()), turn)};
}

// Points in one bin of a fixed grid, whatever the file order (a scan not in the order it was
// taken); a bin above `cap` points is split in cutting-time order into cells of equal size.
Cells GridCells(const std::vector<kinematics::Observation>& obs, std::size_t cap, const ScanCellOptions& options) {
  std::vector<GridKey> key(obs.size());
  ParallelChunks(obs.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) key[i] = GridKeyOf(obs[i], options);
    return true;
  });
  Cells c;
  c.at.resize(obs.size());
  std::iota(c.at.begin(), c.at.end(), std::size_t{0});
  std::sort(c.at.begin(), c.at.end(), [&](std::size_t a, std::size_t b) {
    if (key[a] != key[b]) return key[a] < key[b];
    const double ta = obs[a].cut.axes.t_s, tb = obs[b].cut.axes.t_s;
    return ta != tb ? ta < tb : a < b;
  });
  // Each bin in ceil(size / cap) cells of equal size (within one point).
  for (std::size_t b = 0, e = 0; b < c.at.size(); b = e) {
    for (e = b + 1; e < c.at.size() && key[c.at[e]] == key[c.at[b]];) ++e;
    const std::size_t parts = (e - b + cap - 1) / cap;
    for (std::size_t j = 0; j < parts; ++j) c.start.push_back(b + (e - b) * j / parts);
  }
  return c;
}

// A linear fit of the deviations (mm, less their feature's trend) over a cell's members: the mean
// at their centroid and a slope along each of up to three orthogonal directions. A scan-line cell
// fits a line along its chord; a grid cell a line or plane over the directions its members span.
struct CellFit {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  double mean_mm = 0.0;
  double k = 1.0;  // members
  int terms = 0;
  std::array<Eigen::Vector3d, 3> dir{};
  std::array<double, 3> spread_mm2{}, slope{};  // sum of squared coordinates along dir, d(dev)/d(mm)

  double At(const Eigen::Vector3d& p_mm) const {
    double v = mean_mm;
    for (int j = 0; j < terms; ++j) v += slope[j] * dir[j].dot(p_mm - centre_mm);
    return v;
  }
  // The fit's variance at p in units of one hit's: 1 / k + sum of t_j^2 / spread_j (a member's
  // leverage).
  double VariancePerHit(const Eigen::Vector3d& p_mm) const {
    double v = 1.0 / k;
    for (int j = 0; j < terms; ++j) v += std::pow(dir[j].dot(p_mm - centre_mm), 2) / spread_mm2[j];
    return v;
  }
  int Parameters() const { return 1 + terms; }
};

// Members (observation indices, in the cell's order) and d(i) the deviation of observation i.
template <typename Deviation>
CellFit MeanFit(const std::vector<kinematics::Observation>& obs, const std::vector<std::size_t>& members,
                Deviation d) {
  CellFit f;
  f.k = static_cast<double>(members.size());
  for (std::size_t i : members) f.centre_mm += obs[i].cut.nominal_point_mm, f.mean_mm += d(i);
  f.centre_mm /= f.k;
  f.mean_mm /= f.k;
  return f;
}

// A scan-line cell: a straight line along the chord from its first to its last member; fewer than
// 3 members or no extent: the mean.
template <typename Deviation>
CellFit LineFit(const std::vector<kinematics::Observation>& obs, const std::vector<std::size_t>& members,
                Deviation d) {
  CellFit f = MeanFit(obs, members, d);
  const Eigen::Vector3d chord = obs[members.back()].cut.nominal_point_mm - obs[members.front()].cut.nominal_point_mm;
  if (members.size() < 3 || chord.norm() <= 1e-9) return f;
  const Eigen::Vector3d u = chord.normalized();
  double stt = 0.0, std_ = 0.0;
  for (std::size_t i : members) {
    const double t = (obs[i].cut.nominal_point_mm - f.centre_mm).dot(u);
    stt += t * t;
    std_ += t * (d(i) - f.mean_mm);
  }
  if (!(stt > 0)) return f;
  f.terms = 1;
  f.dir[0] = u;
  f.spread_mm2[0] = stt;
  f.slope[0] = std_ / stt;
  return f;
}

// A grid cell: a linear fit over the directions its members span (a line along one scan line, a
// plane over several), a direction kept when its spread is at least 5 % of the widest (a 2 deg
// arc's sagitta is 0.4 % of its chord) and at most k - 2 of them.
template <typename Deviation>
CellFit SpanFit(const std::vector<kinematics::Observation>& obs, const std::vector<std::size_t>& members,
                Deviation d) {
  CellFit f = MeanFit(obs, members, d);
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  Eigen::Vector3d cross = Eigen::Vector3d::Zero();
  for (std::size_t i : members) {
    const Eigen::Vector3d q = obs[i].cut.nominal_point_mm - f.centre_mm;
    spread += q * q.transpose();
    cross += q * (d(i) - f.mean_mm);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
  const double widest = eig.eigenvalues()(2);
  for (int j = 2; j >= 0 && static_cast<std::size_t>(f.terms) + 2 <= members.size(); --j) {
    const double lambda = eig.eigenvalues()(j);
    if (!(widest > 1e-18) || lambda < 0.05 * 0.05 * widest) break;
    f.dir[f.terms] = eig.eigenvectors().col(j);
    f.spread_mm2[f.terms] = lambda;
    f.slope[f.terms] = f.dir[f.terms].dot(cross) / lambda;
    ++f.terms;
  }
  return f;
}

// Floor of the hits' sigma, as the outlier screen's (OutlierScreenOptions::min_sigma_um, 10 nm): the
// rounding of noise-free (simulated) data is not screened.
constexpr double kMinHitSigma_mm = 1e-5;

struct HitFlag {
  std::size_t observation = 0;
  double departure_mm = 0.0;  // from the fit through the cell's other members
  double z = 0.0;
};

// Fits of cells to the deviations less their feature's trend (FeatureTrends), and the screening
// of single hits inside them: a hit's departure from the fit through the cell's other members is
// r / (1 - h) (r its residual, h its leverage), of standard deviation sigma / sqrt(1 - h); its z is
// r / (sigma sqrt(1 - h)). A cell is judged while its fit keeps at least 2 degrees of freedom
// (with 1, every member's z is the same: nothing says which one is off).
class CellFitter {
 public:
  CellFitter(const std::vector<kinematics::Observation>& obs, const FeatureTrends& trends, bool on_grid)
      : obs_(obs), trends_(trends), on_grid_(on_grid) {}

  double DeviationLessTrend_mm(std::size_t i) const { return NormalDeviation_mm(obs_[i]) - trends_.At(obs_[i]); }

  CellFit Fit(const std::vector<std::size_t>& members) const {
    auto d = [this](std::size_t i) { return DeviationLessTrend_mm(i); };
    return on_grid_ ? SpanFit(obs_, members, d) : LineFit(obs_, members, d);
  }

  // z of observation i against fit f of its cell; `departure_mm`: r / (1 - h).
  double Z(const CellFit& f, std::size_t i, double sigma_mm, double* departure_mm) const {
    const Eigen::Vector3d& p = obs_[i].cut.nominal_point_mm;
    const double h = std::min(f.VariancePerHit(p), 1.0 - 1e-12);
    const double r = DeviationLessTrend_mm(i) - f.At(p);
    if (departure_mm) *departure_mm = r / (1.0 - h);
    return r / (sigma_mm * std::sqrt(1.0 - h));
  }

  static bool Judged(const CellFit& f) { return f.k - f.Parameters() >= 2; }

  // The fit of `members` after the hits beyond z_max sigma are taken out of them into `flagged`,
  // worst first, refitting after each. Two flagged hits next to each other in the cell's order
  // with one sign are a patch (a burr, a chip), not single hits: the cell then keeps all its
  // members, for the screen of cells to judge. `z_kept` (optional): z of the members left.
  CellFit Screened(std::vector<std::size_t>* members, double sigma_mm, double z_max, std::vector<HitFlag>* flagged,
                   std::vector<double>* z_kept) const {
    CellFit f = Fit(*members);
    if (sigma_mm <= 0) return f;
    const std::vector<std::size_t> all = *members;
    std::vector<HitFlag> out;
    while (Judged(f)) {
      std::size_t worst = 0;
      double worst_z = 0.0;
      for (std::size_t j = 0; j < members->size(); ++j)
        if (const double z = Z(f, (*members)[j], sigma_mm, nullptr); std::abs(z) > std::abs(worst_z)) worst = j, worst_z = z;
      if (std::abs(worst_z) <= z_max) break;
      HitFlag hit{(*members)[worst], 0.0, worst_z};
      Z(f, hit.observation, sigma_mm, &hit.departure_mm);
      out.push_back(hit);
      members->erase(members->begin() + static_cast<std::ptrdiff_t>(worst));
      f = Fit(*members);
    }
    if (IsPatch(all, out)) {
      *members = all;
      f = Fit(*members);
      out.clear();
    }
    flagged->insert(flagged->end(), out.begin(), out.end());
    if (z_kept && Judged(f))
      for (std::size_t i : *members) z_kept->push_back(Z(f, i, sigma_mm, nullptr));
    return f;
  }

 private:
  static bool IsPatch(const std::vector<std::size_t>& all, const std::vector<HitFlag>& flagged) {
    if (flagged.size() < 2) return false;
    std::vector<std::pair<std::size_t, double>> at;  // position in the cell, sign
    for (const HitFlag& h : flagged)
      at.emplace_back(static_cast<std::size_t>(std::find(all.begin(), all.end(), h.observation) - all.begin()), h.z);
    std::sort(at.begin(), at.end());
    for (std::size_t j = 1; j < at.size(); ++j)
      if (at[j].first == at[j - 1].first + 1 && at[j].second * at[j - 1].second > 0) return true;
    return false;
  }

  const std::vector<kinematics::Observation>& obs_;
  const FeatureTrends& trends_;
  bool on_grid_;
};

// One hit's noise sigma (mm) from the cells' hits: 1.4826 times the median |z| of the members of
// judged cells about their fit, first of every member, then again after the hits beyond z_max of
// that first estimate are out (1 % of gross outliers in cells of 20 shift the first by about 10 %).
// Of every stride-th cell, about kSigmaCells of them (the median of 1e5 |z| is within 0.5 % at
// 1 sigma; every cell of the 2e6-hit benchmark scan would take 0.2 s).
constexpr std::size_t kSigmaCells = 20000;

template <typename Members>
double HitSigma_mm(const CellFitter& fitter, std::size_t m, Members members_of, double z_max) {
  const std::size_t stride = std::max<std::size_t>(1, m / kSigmaCells), sampled = (m + stride - 1) / stride;
  double sigma_mm = 1.0;
  for (const double round_z_max : {std::numeric_limits<double>::infinity(), z_max}) {
    std::vector<std::vector<double>> z(sampled);
    ParallelChunks(sampled, 1024, [&](std::size_t begin, std::size_t end) {
      std::vector<HitFlag> flags;
      for (std::size_t s = begin; s < end; ++s) {
        std::vector<std::size_t> members = members_of(s * stride);
        fitter.Screened(&members, sigma_mm, round_z_max, &flags, &z[s]);
      }
      return true;
    });
    std::vector<double> all;
    for (auto& v : z)
      for (double x : v) all.push_back(std::abs(x));
    if (all.empty()) return 0.0;
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2), all.end());
    sigma_mm *= 1.4826 * all[all.size() / 2];
  }
  return std::max(sigma_mm, kMinHitSigma_mm);
}

}  // namespace

ScanCellSummary Summarise(const ScanCells& cells) {
  ScanCellSummary s;
  s.num_points = cells.num_points;
  s.num_cells = cells.cell_points.size();
  s.points_per_cell_max = cells.points_per_cell_max;
  s.max_cell_mm = cells.max_cell_mm;
  s.max_cell_deg = cells.max_cell_deg;
  s.mean_points_per_cell = s.num_cells ? static_cast<double>(s.num_points) / static_cast<double>(s.num_cells) : 0.0;
  s.on_grid = cells.on_grid;
  s.flagged_hits = cells.flagged_hits.size();
  s.hit_sigma_um = cells.hit_sigma_um;
  return s;
}

Result<std::optional<ScanCells>> ReduceToScanCells(const testpieces::MeasuredObservations& per_point,
                                                   const ScanCellOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  const std::vector<kinematics::Observation>& obs = per_point.observations;
  const std::size_t n = obs.size();
  if (options.above_points == 0 || n <= options.above_points) return std::optional<ScanCells>();
  const std::size_t cap = options.points_per_cell > 0
                              ? options.points_per_cell
                              : (n + options.target_cells - 1) / options.target_cells;

  // Scan-line cells in file order; a file that pools fewer than 3 points a cell that way (not in
  // the order its points were taken) on a fixed grid instead, if that pools more.
  Cells cells = ScanLineCells(obs, cap, options);
  const bool on_grid = [&] {
    if (3 * cells.start.size() <= n) return false;
    Cells grid = GridCells(obs, cap, options);
    if (grid.start.size() >= cells.start.size()) return false;
    cells = std::move(grid);
    return true;
  }();
  const std::size_t m = cells.start.size();
  cells.start.push_back(n);

  ScanCells out;
  out.num_points = n;
  out.points_per_cell_max = cap;
  out.max_cell_mm = options.max_cell_mm;
  out.max_cell_deg = options.max_cell_deg;
  out.on_grid = on_grid;
  out.cell_points.resize(m);
  out.observations.feature_names = per_point.feature_names;
  out.observations.observations.resize(m);
  out.observations.point_index.resize(m);
  const FeatureTrends trends(obs, per_point.feature_names.size());
  const CellFitter fitter(obs, trends, on_grid);
  auto members_of = [&](std::size_t c) {
    return std::vector<std::size_t>(cells.at.begin() + static_cast<std::ptrdiff_t>(cells.start[c]),
                                    cells.at.begin() + static_cast<std::ptrdiff_t>(cells.start[c + 1]));
  };
  const double z_max = options.hit_outlier_z;
  const double sigma_mm = z_max > 0 ? HitSigma_mm(fitter, m, members_of, z_max) : 0.0;
  out.hit_sigma_um = sigma_mm * 1e3;
  out.hit_outlier_z = sigma_mm > 0 ? z_max : 0.0;
  out.hits_left_out = options.leave_out_flagged_hits;
  std::vector<std::vector<HitFlag>> flagged(m);
  ParallelChunks(m, 2048, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      std::vector<std::size_t> members = members_of(c);
      CellFit fit = fitter.Screened(&members, sigma_mm, z_max, &flagged[c], nullptr);
      if (!options.leave_out_flagged_hits && !flagged[c].empty()) fit = fitter.Fit(members = members_of(c));
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (std::size_t i : members) centroid += obs[i].cut.nominal_point_mm;
      centroid /= static_cast<double>(members.size());
      std::size_t rep = members.front();
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i : members) {
        const double d2 = (obs[i].cut.nominal_point_mm - centroid).squaredNorm();
        if (d2 < best) best = d2, rep = i;
      }
      // The linear fit to the deviations less their feature's trend, plus the trend there.
      const kinematics::Observation& r = obs[rep];
      kinematics::Observation& o = out.observations.observations[c];
      o.cut = r.cut;
      o.group = r.group;
      o.measured_mm = r.cut.nominal_point_mm + (fit.At(r.cut.nominal_point_mm) + trends.At(r)) * r.cut.nominal_normal;
      o.noise_scale = std::sqrt(fit.VariancePerHit(r.cut.nominal_point_mm));
      out.observations.point_index[c] = per_point.point_index[rep];
      out.cell_points[c] = static_cast<std::uint32_t>(members.size());
    }
    return true;
  });
  for (std::size_t c = 0; c < m; ++c)
    for (const HitFlag& h : flagged[c])
      out.flagged_hits.push_back({per_point.point_index[h.observation], h.observation, h.departure_mm * 1e3, h.z,
                                  static_cast<int>(cells.start[c + 1] - cells.start[c])});
  return std::optional<ScanCells>(std::move(out));
}

}  // namespace tpcal::pipeline
