#include "pipeline/diagnosis/diagnosis_process_candidates.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/parallel.h"
#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "testpieces/process_effects.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

double Wrap2Pi(double a) {
  a = std::fmod(a, 2.0 * std::numbers::pi);
  return a < 0 ? a + 2.0 * std::numbers::pi : a;
}

// Drops all-zero columns (the effect never acts on this piece).
void DropZeroColumns(CandidateColumns* c) {
  std::vector<int> keep;
  for (int j = 0; j < c->J_dev_effect.cols(); ++j)
    if (c->J_dev_effect.col(j).squaredNorm() > 1e-20) keep.push_back(j);
  if (static_cast<int>(keep.size()) == c->J_dev_effect.cols()) return;
  Eigen::MatrixXd J(c->J_dev_effect.rows(), static_cast<Eigen::Index>(keep.size()));
  std::vector<std::string> names, units;
  for (std::size_t k = 0; k < keep.size(); ++k) {
    J.col(static_cast<Eigen::Index>(k)) = c->J_dev_effect.col(keep[k]);
    names.push_back(c->parameter_names[static_cast<std::size_t>(keep[k])]);
    units.push_back(c->units[static_cast<std::size_t>(keep[k])]);
  }
  c->J_dev_effect = std::move(J);
  c->parameter_names = std::move(names);
  c->units = std::move(units);
}

// Per observation: the machine-frame rotation of the part (nominal kinematics at its cut
// state) and the outward normal in the machine frame; and the cut of each feature (looked up once
// per feature, not per point).
struct ProcessPoints {
  const std::vector<kinematics::Observation>& obs;
  Eigen::Index n = 0;
  std::vector<Eigen::Vector3d> nm;
  std::vector<Eigen::Matrix3d> mfp;
  std::vector<const testpieces::FeatureCut*> cut_of_group;
  const testpieces::FeatureCut* CutOf(Eigen::Index i) const {
    return cut_of_group[static_cast<std::size_t>(obs[static_cast<std::size_t>(i)].group)];
  }
};

ProcessPoints MakeProcessPoints(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                const testpieces::MeasuredObservations& mo) {
  const auto& obs = mo.observations;
  const auto n = static_cast<Eigen::Index>(obs.size());
  ProcessPoints p{obs, n, std::vector<Eigen::Vector3d>(static_cast<std::size_t>(n)), {}, {}};
  const kinematics::ErrorState zero(machine);
  p.mfp.resize(static_cast<std::size_t>(n));
  ParallelChunks(static_cast<std::size_t>(n), 8192, [&](std::size_t begin, std::size_t end) {
    kinematics::Workspace ws;
    for (std::size_t i = begin; i < end; ++i) {
      p.mfp[i] = kinematics::MachineFromPart(machine, zero, obs[i].cut.axes, &ws).linear();
      p.nm[i] = p.mfp[i] * obs[i].cut.nominal_normal;
    }
    return true;
  });
  p.cut_of_group.resize(mo.feature_names.size());
  for (std::size_t g = 0; g < mo.feature_names.size(); ++g) p.cut_of_group[g] = piece.Cut(mo.feature_names[g]);
  return p;
}

// Compliance along machine X, Y, Z with a force along the normal, per cut class (turned side
// face, turned bottom face, side-milled wall, end-milled floor): columns n_mx^2, n_my^2, n_mz^2,
// n_mx n_my.
void AddToolDeflection(const ProcessPoints& p, CandidateCatalogue* out) {
  const Eigen::Index n = p.n;
  enum Class { kTurnSide, kTurnFace, kMillSide, kMillFloor, kNumClasses };
  const char* class_names[] = {"turned_side", "turned_face", "milled_wall", "milled_floor"};
  const int per_class = 4;  // xx, yy, zz, xy
  CandidateColumns c{"tool_deflection",
                     "cutting-force deflection: compliance along machine X, Y, Z per cut class, force along the normal",
                     Eigen::MatrixXd::Zero(n, kNumClasses * per_class), {}, {}, {}, {}};
  for (int k = 0; k < kNumClasses; ++k)
    for (const char* comp : {"xx", "yy", "zz", "xy"}) {
      c.parameter_names.push_back(std::string(class_names[k]) + ".c_" + comp);
      c.units.push_back("um");
    }
  for (Eigen::Index i = 0; i < n; ++i) {
    const testpieces::FeatureCut* fc = p.CutOf(i);
    if (!fc) continue;
    int cls = -1;
    if (const auto* t = std::get_if<testpieces::TurnedCut>(&fc->model)) cls = t->radial_feed ? kTurnFace : kTurnSide;
    if (const auto* m = std::get_if<testpieces::PathMillCut>(&fc->model)) cls = m->end_face ? kMillFloor : kMillSide;
    if (cls < 0) continue;
    const Eigen::Vector3d& v = p.nm[static_cast<std::size_t>(i)];
    c.J_dev_effect(i, cls * per_class + 0) = v.x() * v.x();
    c.J_dev_effect(i, cls * per_class + 1) = v.y() * v.y();
    c.J_dev_effect(i, cls * per_class + 2) = v.z() * v.z();
    c.J_dev_effect(i, cls * per_class + 3) = v.x() * v.y();
  }
  DropZeroColumns(&c);
  if (c.J_dev_effect.cols() > 0) out->candidates.push_back(std::move(c));
  else out->not_applicable.push_back({"tool_deflection", "no turned or milled feature is measured"});
}

// A probed point on a reversal (the paper plan's circles have points at 0, 90, 180 and 270 deg)
// is at its glitch's peak whichever side of the reversal its associated position falls: angles
// along the arc within this of a crossing count as at it, and one this short of a full turn as at
// the start. The identify stage's observations put such points 5e-6 to 3e-5 rad either side (the
// measured point's tangential offset, on the turning piece's S_R), which left every glitch column
// zero when they fell before the reversal; 1e-3 rad (0.12 mm on S_R) is far below the plan's
// spacing and changes a glitch decaying over 2 deg or more by under 3 %.
constexpr double kServoOnReversalRad = 1e-3;

double ServoArcAngle(double a) {
  a = Wrap2Pi(a);
  return 2.0 * std::numbers::pi - a < kServoOnReversalRad ? 0.0 : a;
}

// Side-milled circles interpolated in machine X-Y: a triangular glitch (half-width 12 deg) after
// each X (Y) reversal in the direction of travel, outward along that axis, projected on the
// normal; and with lost motion (backlash: half-circle steps along X and Y).
void AddServoReversal(const ProcessPoints& p, CandidateCatalogue* out) {
  const Eigen::Index n = p.n;
  CandidateColumns spikes{"servo_reversal", "quadrant glitches at X and Y reversals of circular interpolation",
                          Eigen::MatrixXd::Zero(n, 2), {"glitch_X", "glitch_Y"}, {"um", "um"}, {}, {}};
  CandidateColumns lost{"servo_reversal", "quadrant glitches and lost motion (backlash) of X and Y",
                        Eigen::MatrixXd::Zero(n, 4), {"glitch_X", "glitch_Y", "backlash_X", "backlash_Y"},
                        {"um", "um", "um", "um"}, {}, {}};
  const double half_width = DegToRad(12.0);
  struct Crossing { double theta; Eigen::Vector3d outward; int axis; };
  const Crossing crossings[4] = {{0.0, Eigen::Vector3d::UnitX(), 0},
                                 {std::numbers::pi, -Eigen::Vector3d::UnitX(), 0},
                                 {0.5 * std::numbers::pi, Eigen::Vector3d::UnitY(), 1},
                                 {1.5 * std::numbers::pi, -Eigen::Vector3d::UnitY(), 1}};
  for (Eigen::Index i = 0; i < n; ++i) {
    const testpieces::FeatureCut* fc = p.CutOf(i);
    if (!fc) continue;
    const auto& o = p.obs[static_cast<std::size_t>(i)];
    auto arc = testpieces::ArcTravelAt(*fc, o.cut.nominal_point_mm, p.mfp[static_cast<std::size_t>(i)]);
    if (!arc) continue;
    const double alpha_p = ServoArcAngle(arc->direction * (arc->theta_rad - arc->theta_start_rad));
    double last_alpha[2] = {-1, -1};
    double last_proj[2] = {0, 0};
    for (const auto& cr : crossings) {
      const double alpha_c = ServoArcAngle(arc->direction * (cr.theta - arc->theta_start_rad));
      if (alpha_c > alpha_p + kServoOnReversalRad || alpha_c > arc->sweep_rad) continue;
      const double phi = std::max(0.0, alpha_p - alpha_c);
      const double proj = p.nm[static_cast<std::size_t>(i)].dot(cr.outward);
      const double tri = std::max(0.0, 1.0 - phi / half_width);
      spikes.J_dev_effect(i, cr.axis) += tri * proj;
      lost.J_dev_effect(i, cr.axis) += tri * proj;
      if (alpha_c > last_alpha[cr.axis]) { last_alpha[cr.axis] = alpha_c; last_proj[cr.axis] = proj; }
    }
    lost.J_dev_effect(i, 2) = last_proj[0];
    lost.J_dev_effect(i, 3) = last_proj[1];
  }
  DropZeroColumns(&spikes);
  DropZeroColumns(&lost);
  if (spikes.J_dev_effect.cols() > 0) out->candidates.push_back(std::move(spikes));
  if (lost.J_dev_effect.cols() > 0) out->candidates.push_back(std::move(lost));
  if (out->candidates.empty() || out->candidates.back().family != "servo_reversal")
    out->not_applicable.push_back({"servo_reversal", "no feature is side-milled on a circle interpolated in machine X-Y"});
}

// +b along every measured normal; and with CMM scale (n . p, part frame).
void AddProbeRadius(const ProcessPoints& p, CandidateCatalogue* out) {
  const Eigen::Index n = p.n;
  CandidateColumns r{"probe_radius", "CMM probe-radius error", Eigen::MatrixXd::Ones(n, 1), {"probe_radius_error"}, {"um"}, {}, {}};
  CandidateColumns rs{"probe_radius", "CMM probe-radius and scale error", Eigen::MatrixXd::Ones(n, 2),
                      {"probe_radius_error", "scale"}, {"um", "ppm"}, {}, {}};
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& o = p.obs[static_cast<std::size_t>(i)];
    rs.J_dev_effect(i, 1) = 1e-3 * o.cut.nominal_normal.dot(o.cut.nominal_point_mm);  // um per ppm
  }
  out->candidates.push_back(std::move(r));
  out->candidates.push_back(std::move(rs));
}

}  // namespace

void AddProcessCandidates(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                          const testpieces::MeasuredObservations& observations, CandidateCatalogue* out) {
  const ProcessPoints p = MakeProcessPoints(piece, machine, observations);
  AddToolDeflection(p, out);
  AddServoReversal(p, out);
  AddProbeRadius(p, out);
}

}  // namespace tpcal::pipeline::diagnosis_internal
