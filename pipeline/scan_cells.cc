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

// A cell's value at its representative: the deviation (mm, less its feature's trend) a linear fit
// over the cell predicts there, and that prediction's variance in units of one hit's.
struct CellValue {
  double deviation_mm = 0.0;
  double variance_per_hit = 1.0;
};

// Members b..e-1 of `cells` (positions into cells.at), d(i) the deviation of observation i.
template <typename Deviation>
CellValue MeanValue(const Cells& cells, std::size_t b, std::size_t e, Deviation d) {
  double sum = 0.0;
  for (std::size_t i = b; i < e; ++i) sum += d(cells.at[i]);
  return {sum / static_cast<double>(e - b), 1.0 / static_cast<double>(e - b)};
}

// A scan-line cell: a straight line along the cell's chord, d = a + slope t (t: distance from the
// representative along the chord); fewer than 3 points or no extent: the mean.
template <typename Deviation>
CellValue LineValueAt(const std::vector<kinematics::Observation>& obs, const Cells& cells, std::size_t b,
                      std::size_t e, std::size_t rep, Deviation d) {
  CellValue v = MeanValue(cells, b, e, d);
  const std::size_t k = e - b;
  const Eigen::Vector3d p_rep = obs[cells.at[rep]].cut.nominal_point_mm;
  const Eigen::Vector3d chord = obs[cells.at[e - 1]].cut.nominal_point_mm - obs[cells.at[b]].cut.nominal_point_mm;
  if (k < 3 || chord.norm() <= 1e-9) return v;
  const Eigen::Vector3d u = chord.normalized();
  double t_mean = 0.0;
  for (std::size_t i = b; i < e; ++i) t_mean += (obs[cells.at[i]].cut.nominal_point_mm - p_rep).dot(u);
  t_mean /= static_cast<double>(k);
  double stt = 0.0, std_ = 0.0;
  for (std::size_t i = b; i < e; ++i) {
    const double t = (obs[cells.at[i]].cut.nominal_point_mm - p_rep).dot(u) - t_mean;
    stt += t * t;
    std_ += t * (d(cells.at[i]) - v.deviation_mm);
  }
  if (stt > 0) {
    v.deviation_mm -= (std_ / stt) * t_mean;
    v.variance_per_hit += t_mean * t_mean / stt;
  }
  return v;
}

// A grid cell: a linear fit over the directions its members span (a line along one scan line, a
// plane over several), a direction kept when its spread is at least 5 % of the widest (a 2 deg
// arc's sagitta is 0.4 % of its chord) and at most k - 2 of them.
template <typename Deviation>
CellValue SpanValueAt(const std::vector<kinematics::Observation>& obs, const Cells& cells, std::size_t b,
                      std::size_t e, std::size_t rep, Deviation d) {
  CellValue v = MeanValue(cells, b, e, d);
  const std::size_t k = e - b;
  const Eigen::Vector3d p_rep = obs[cells.at[rep]].cut.nominal_point_mm;
  Eigen::Vector3d q_mean = Eigen::Vector3d::Zero();
  for (std::size_t i = b; i < e; ++i) q_mean += obs[cells.at[i]].cut.nominal_point_mm - p_rep;
  q_mean /= static_cast<double>(k);
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  Eigen::Vector3d cross = Eigen::Vector3d::Zero();
  for (std::size_t i = b; i < e; ++i) {
    const Eigen::Vector3d q = obs[cells.at[i]].cut.nominal_point_mm - p_rep - q_mean;
    spread += q * q.transpose();
    cross += q * (d(cells.at[i]) - v.deviation_mm);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
  const double widest = eig.eigenvalues()(2);
  std::size_t kept = 0;
  for (int j = 2; j >= 0 && kept + 2 <= k; --j) {
    const double lambda = eig.eigenvalues()(j);
    if (!(widest > 1e-18) || lambda < 0.05 * 0.05 * widest) break;
    const Eigen::Vector3d dir = eig.eigenvectors().col(j);
    const double t_rep = dir.dot(-q_mean);  // the representative along dir, from the members' mean
    v.deviation_mm += dir.dot(cross) / lambda * t_rep;
    v.variance_per_hit += t_rep * t_rep / lambda;
    ++kept;
  }
  return v;
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
  auto smooth_less = [&](std::size_t i) { return NormalDeviation_mm(obs[i]) - trends.At(obs[i]); };
  ParallelChunks(m, 2048, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const std::size_t b = cells.start[c], e = cells.start[c + 1], k = e - b;
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (std::size_t i = b; i < e; ++i) centroid += obs[cells.at[i]].cut.nominal_point_mm;
      centroid /= static_cast<double>(k);
      std::size_t rep = b;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = b; i < e; ++i) {
        const double d2 = (obs[cells.at[i]].cut.nominal_point_mm - centroid).squaredNorm();
        if (d2 < best) best = d2, rep = i;
      }
      // The linear fit to the deviations less their feature's trend, plus the trend there.
      const CellValue v = on_grid ? SpanValueAt(obs, cells, b, e, rep, smooth_less)
                                  : LineValueAt(obs, cells, b, e, rep, smooth_less);
      const kinematics::Observation& r = obs[cells.at[rep]];
      kinematics::Observation& o = out.observations.observations[c];
      o.cut = r.cut;
      o.group = r.group;
      o.measured_mm = r.cut.nominal_point_mm + (v.deviation_mm + trends.At(r)) * r.cut.nominal_normal;
      o.noise_scale = std::sqrt(v.variance_per_hit);
      out.observations.point_index[c] = per_point.point_index[cells.at[rep]];
      out.cell_points[c] = static_cast<std::uint32_t>(k);
    }
    return true;
  });
  return std::optional<ScanCells>(std::move(out));
}

}  // namespace tpcal::pipeline
