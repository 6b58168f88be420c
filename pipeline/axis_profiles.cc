#include "pipeline/axis_profiles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "fitting/minimum_zone.h"

namespace tpcal::pipeline {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

double Wrap360(double deg) {
  double d = std::fmod(deg, 360.0);
  return d < 0 ? d + 360.0 : d;
}

struct Sample {
  double c_deg;
  double dr_um;
};

// Circularity profile of `characteristic` as (C at the cut, dr) sorted by C.
Result<std::vector<Sample>> ProfileByC(const IdentifyStageResult& stage, const std::string& characteristic) {
  const gdt::CharacteristicResult* c = stage.inspection.Characteristic(characteristic);
  if (c == nullptr) return std::vector<Sample>{};
  std::map<std::size_t, double> c_of_point;  // PointSet index -> C command (deg)
  const auto& obs = stage.observations;
  for (std::size_t k = 0; k < obs.point_index.size(); ++k)
    c_of_point[obs.point_index[k]] = obs.observations[k].cut.axes.c_rad * kRadToDeg;
  std::vector<Sample> out;
  for (const auto& s : c->profile) {
    auto it = c_of_point.find(s.point_index);
    if (it == c_of_point.end()) continue;
    out.push_back({Wrap360(it->second), s.dr_um});
  }
  if (out.size() < 4)
    return Status(StatusCode::kTooFewPoints,
                  characteristic + ": an error-motion profile needs at least 4 points, got " + std::to_string(out.size()));
  std::sort(out.begin(), out.end(), [](const Sample& a, const Sample& b) { return a.c_deg < b.c_deg; });
  return out;
}

// Periodic linear interpolation of a profile sorted by C.
double ProfileAt(const std::vector<Sample>& p, double c_deg) {
  const auto it = std::lower_bound(p.begin(), p.end(), c_deg, [](const Sample& s, double c) { return s.c_deg < c; });
  const Sample& hi = it == p.end() ? p.front() : *it;
  const Sample& lo = it == p.begin() ? p.back() : *(it - 1);
  double span = Wrap360(hi.c_deg - lo.c_deg);
  if (span == 0.0) return lo.dr_um;
  const double f = Wrap360(c_deg - lo.c_deg) / span;
  return lo.dr_um + f * (hi.dr_um - lo.dr_um);
}

}  // namespace

Result<std::vector<CAxisErrorMotion>> CAxisErrorMotions(const testpieces::TestPiece& piece,
                                                        const IdentifyStageResult& stage) {
  std::vector<CAxisErrorMotion> out;
  if (piece.kind() != testpieces::PieceKind::kTurning) return out;
  const auto* p = std::get_if<testpieces::TurningPieceParams>(&piece.config.params);
  struct Pair {
    const char* name;
    double a_deg;
    const char* upper;
    const char* lower;
    int upper_step, lower_step;
  };
  const std::array<Pair, 2> pairs = {Pair{"C at A=0", 0.0, "ta_circularity_S1", "tc_circularity_S4", 0, 3},
                                     Pair{"C at A=-90", -90.0, "tb_circularity_S3", "td_circularity_S6", 2, 5}};
  for (const Pair& pair : pairs) {
    auto upper = ProfileByC(stage, pair.upper);
    if (!upper.ok()) return upper.status();
    auto lower = ProfileByC(stage, pair.lower);
    if (!lower.ok()) return lower.status();
    if (upper->empty() || lower->empty()) continue;
    std::vector<double> c, du, dl;
    for (const Sample& s : *upper) {
      c.push_back(s.c_deg);
      du.push_back(s.dr_um);
      dl.push_back(ProfileAt(*lower, s.c_deg));
    }
    auto profile = kinematics::SeparateErrorMotion(c, du, dl, p->steps[pair.upper_step].probe_z_mm,
                                                   p->steps[pair.lower_step].probe_z_mm);
    if (!profile.ok()) return profile.status();
    const std::string su = "S" + std::to_string(pair.upper_step + 1), sl = "S" + std::to_string(pair.lower_step + 1);
    out.push_back({pair.name, su + " over " + sl, pair.a_deg, std::move(*profile)});
  }
  return out;
}

Result<std::vector<StraightnessProfile>> LinearAxisStraightness(const testpieces::TestPiece& piece,
                                                                const IdentifyStageResult& stage) {
  std::vector<StraightnessProfile> out;
  if (stage.identification.residuals_um.size() != stage.observations.observations.size()) return out;
  if (piece.machine.type != kinematics::MachineType::kXyz) return out;
  const auto& obs = stage.observations;
  const char* axis_names[3] = {"X", "Y", "Z"};
  for (std::size_t g = 0; g < obs.feature_names.size(); ++g) {
    std::vector<std::size_t> rows;
    for (std::size_t k = 0; k < obs.observations.size(); ++k)
      if (obs.observations[k].group == static_cast<int>(g)) rows.push_back(k);
    if (rows.size() < 5) continue;
    // The normal must be along one machine axis for the whole face.
    const Eigen::Vector3d n0 = obs.observations[rows.front()].cut.nominal_normal;
    int dir = -1;
    for (int a = 0; a < 3; ++a)
      if (std::abs(n0[a]) > 0.9999) dir = a;
    if (dir < 0 || dir == 2) continue;  // side faces only (normal along X or Y)
    bool planar = true;
    for (std::size_t k : rows) planar = planar && obs.observations[k].cut.nominal_normal.dot(n0) > 0.9999;
    if (!planar) continue;
    // Moving axis: the other horizontal axis (its command range along the face).
    const int mov = dir == 0 ? 1 : 0;
    std::vector<std::pair<double, double>> pts;  // (position mm, deviation um along +dir)
    for (std::size_t k : rows) {
      const auto& ax = obs.observations[k].cut.axes;
      const double pos = mov == 0 ? ax.x_mm : ax.y_mm;
      pts.emplace_back(pos, stage.identification.residuals_um[k] * (n0[dir] > 0 ? 1.0 : -1.0));
    }
    std::sort(pts.begin(), pts.end());
    const double range = pts.back().first - pts.front().first;
    if (range < 1.0) continue;
    StraightnessProfile s;
    s.moving_axis = axis_names[mov];
    s.direction = axis_names[dir];
    s.name = std::string("E_") + axis_names[dir] + axis_names[mov];
    s.feature = obs.feature_names[g];
    // Least-squares line, then P-V about it.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(pts.size());
    for (auto [x, y] : pts) { sx += x; sy += y; }
    const double mx = sx / n, my = sy / n;
    for (auto [x, y] : pts) { sxx += (x - mx) * (x - mx); sxy += (x - mx) * (y - my); }
    const double slope_um_per_mm = sxy / sxx;
    s.slope_urad = slope_um_per_mm * 1e3;
    double lo = 0, hi = 0;
    std::vector<Eigen::Vector2d> zone_pts;
    for (auto [x, y] : pts) {
      const double d = y - my - slope_um_per_mm * (x - mx);
      s.position_mm.push_back(x);
      s.deviation_um.push_back(d);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
      zone_pts.emplace_back(x, y * 1e-3);
    }
    s.pv_ls_um = hi - lo;
    auto zone = fitting::MinimumZoneStraightness2(zone_pts);
    if (!zone.ok()) return zone.status().WithContext("straightness of " + s.feature);
    s.mz_um = zone->width_mm * 1e3;
    s.mz_certified = zone->certificate.verified_optimal && zone->certificate.scope == fitting::OptimalityScope::kGlobal;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace tpcal::pipeline
