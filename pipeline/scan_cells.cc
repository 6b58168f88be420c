#include "pipeline/scan_cells.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
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
// hole offset over a 10 deg cell is otherwise attenuated by 0.13 %, a 30 nm first harmonic the
// same on every hole, which the diagnosis of 2e6 points finds (p = 4e-11 on the bench scan).
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

// Whether point i may join the cell that starts at `first` and ends at i - 1.
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

}  // namespace

ScanCellSummary Summarise(const ScanCells& cells) {
  ScanCellSummary s;
  s.num_points = cells.num_points;
  s.num_cells = cells.cell_points.size();
  s.points_per_cell_max = cells.points_per_cell_max;
  s.max_cell_mm = cells.max_cell_mm;
  s.max_cell_deg = cells.max_cell_deg;
  s.mean_points_per_cell = s.num_cells ? static_cast<double>(s.num_points) / static_cast<double>(s.num_cells) : 0.0;
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

  // Cell boundaries, in one pass over the file order.
  std::vector<std::size_t> start{0};
  for (std::size_t i = 1; i < n; ++i) {
    if (i - start.back() >= cap || !Continues(obs, start.back(), i, options)) start.push_back(i);
  }
  const std::size_t m = start.size();
  start.push_back(n);


  ScanCells out;
  out.num_points = n;
  out.points_per_cell_max = cap;
  out.max_cell_mm = options.max_cell_mm;
  out.max_cell_deg = options.max_cell_deg;
  out.cell_points.resize(m);
  out.observations.feature_names = per_point.feature_names;
  out.observations.observations.resize(m);
  out.observations.point_index.resize(m);
  const FeatureTrends trends(obs, per_point.feature_names.size());
  auto smooth_less = [&](std::size_t i) { return NormalDeviation_mm(obs[i]) - trends.At(obs[i]); };
  ParallelChunks(m, 2048, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const std::size_t b = start[c], e = start[c + 1], k = e - b;
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (std::size_t i = b; i < e; ++i) centroid += obs[i].cut.nominal_point_mm;
      centroid /= static_cast<double>(k);
      std::size_t rep = b;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = b; i < e; ++i) {
        const double d2 = (obs[i].cut.nominal_point_mm - centroid).squaredNorm();
        if (d2 < best) best = d2, rep = i;
      }
      // d = a + slope * t along the cell (t: distance from the representative along the chord),
      // d the deviation less its feature's trend; the value at the representative is a plus the
      // trend there. Fewer than 3 points or no extent: the mean.
      const Eigen::Vector3d p_rep = obs[rep].cut.nominal_point_mm;
      const Eigen::Vector3d chord = obs[e - 1].cut.nominal_point_mm - obs[b].cut.nominal_point_mm;
      double t_mean = 0.0, d_mean = 0.0;
      for (std::size_t i = b; i < e; ++i) d_mean += smooth_less(i);
      d_mean /= static_cast<double>(k);
      double deviation_mm = d_mean, variance_per_hit = 1.0 / static_cast<double>(k);
      if (k >= 3 && chord.norm() > 1e-9) {
        const Eigen::Vector3d u = chord.normalized();
        for (std::size_t i = b; i < e; ++i) t_mean += (obs[i].cut.nominal_point_mm - p_rep).dot(u);
        t_mean /= static_cast<double>(k);
        double stt = 0.0, std_ = 0.0;
        for (std::size_t i = b; i < e; ++i) {
          const double t = (obs[i].cut.nominal_point_mm - p_rep).dot(u) - t_mean;
          stt += t * t;
          std_ += t * (smooth_less(i) - d_mean);
        }
        if (stt > 0) {
          deviation_mm = d_mean - (std_ / stt) * t_mean;
          variance_per_hit += t_mean * t_mean / stt;
        }
      }
      kinematics::Observation& o = out.observations.observations[c];
      o.cut = obs[rep].cut;
      o.group = obs[rep].group;
      deviation_mm += trends.At(obs[rep]);
      o.measured_mm = p_rep + deviation_mm * obs[rep].cut.nominal_normal;
      o.noise_scale = std::sqrt(variance_per_hit);
      out.observations.point_index[c] = per_point.point_index[rep];
      out.cell_points[c] = static_cast<std::uint32_t>(k);
    }
    return true;
  });
  return std::optional<ScanCells>(std::move(out));
}

}  // namespace tpcal::pipeline
