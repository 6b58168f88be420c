#include "testpieces/process_effects.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::testpieces {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

double Wrap2Pi(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

Eigen::Vector3d Horizontal(const Eigen::Vector3d& v, const Eigen::Vector3d& axis) { return v - v.dot(axis) * axis; }

// The path element of a milled face that left point p (part frame): for arcs the wall lies at
// centre distance radius +- tool radius; for lines at tool radius from the segment.
const PathElement* NearestElement(const PathMillCut& cut, const Eigen::Vector3d& p) {
  const PathElement* best = nullptr;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& e : cut.elements) {
    double d = 0;
    if (e.arc) {
      const double r = Horizontal(p - e.center_mm, cut.tool_axis).norm();
      d = std::min(std::abs(r - (e.radius_mm + cut.tool_radius_mm)), std::abs(r - (e.radius_mm - cut.tool_radius_mm)));
      if (cut.end_face) d = std::max(0.0, r - e.radius_mm - cut.tool_radius_mm);
    } else {
      const Eigen::Vector3d a = Horizontal(e.start_tip_mm, cut.tool_axis), b = Horizontal(e.end_tip_mm, cut.tool_axis);
      const Eigen::Vector3d q = Horizontal(p, cut.tool_axis);
      const double len2 = (b - a).squaredNorm();
      const double t = len2 > 0 ? std::clamp((q - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
      d = std::abs((q - (a + t * (b - a))).norm() - (cut.end_face ? 0.0 : cut.tool_radius_mm));
    }
    if (d < best_d) { best_d = d; best = &e; }
  }
  return best;
}

// Unit feed direction of the tool along element e at point p (part frame).
Eigen::Vector3d PathTangent(const PathMillCut& cut, const PathElement& e, const Eigen::Vector3d& p) {
  if (!e.arc) {
    const Eigen::Vector3d d = Horizontal(e.end_tip_mm - e.start_tip_mm, cut.tool_axis);
    return d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d radial = Horizontal(p - e.center_mm, cut.tool_axis).normalized();
  const Eigen::Vector3d ccw = cut.tool_axis.cross(radial);
  return e.clockwise ? Eigen::Vector3d(-ccw) : ccw;
}

// Cutting force on the tool (N, part frame).
Eigen::Vector3d ForceOnTool(const TestPiece& piece, const FeatureCut& fc, const PlanPoint& pp,
                            const ToolDeflectionModel& m) {
  const Eigen::Vector3d& n = pp.normal_part;
  const Eigen::Vector3d& p = pp.point_part_mm;
  const TurningPieceParams* turning = std::get_if<TurningPieceParams>(&piece.config.params);
  if (const auto* t = std::get_if<TurnedCut>(&fc.model)) {
    double area_mm2 = 0.16;
    if (turning) area_mm2 = turning->turning_depth_of_cut_mm * turning->turning_feed_mm_per_rev;
    const double fcut = m.specific_force_n_per_mm2 * area_mm2;
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d radial = Horizontal(p, z);
    radial = radial.norm() > 0 ? Eigen::Vector3d(radial.normalized()) : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d spin = z.cross(radial);
    const Eigen::Vector3d feed_reaction = t->radial_feed ? radial : z;
    return fcut * spin + m.passive_ratio * fcut * n + m.feed_ratio * fcut * feed_reaction;
  }
  if (const auto* c = std::get_if<PathMillCut>(&fc.model)) {
    if (c->end_face) return m.passive_ratio * m.specific_force_n_per_mm2 * m.floor_axial_area_mm2 * n;
    const PathElement* e = NearestElement(*c, p);
    if (!e) return Eigen::Vector3d::Zero();
    double ae = 0.2, ap = 5.0, fz = 0.019, dia = 2.0 * c->tool_radius_mm;
    if (turning) {
      ae = turning->groove_finish_stock_mm;
      ap = turning->groove_depth_mm;
      fz = turning->wall_feed_per_tooth_mm;
    }
    const double hm = fz * std::sqrt(std::max(ae, 0.0) / std::max(dia, 1e-9));
    const double fcut = m.specific_force_n_per_mm2 * ap * hm;
    return m.passive_ratio * fcut * n - m.feed_ratio * fcut * PathTangent(*c, *e, p);
  }
  return Eigen::Vector3d::Zero();  // reamed holes, flank-milled cones
}

// Servo displacement of the tool (um, machine frame) at a point of a circular path.
Eigen::Vector3d ServoDisplacementUm(const ArcTravel& a, const ServoReversalModel& m) {
  const double alpha_p = Wrap2Pi(a.direction * (a.theta_rad - a.theta_start_rad));
  const double decay_rad = DegToRad(m.decay_deg);
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  struct Crossing { double theta; Eigen::Vector3d outward; bool x_axis; };
  const Crossing crossings[4] = {{0.0, Eigen::Vector3d::UnitX(), true},
                                 {std::numbers::pi, -Eigen::Vector3d::UnitX(), true},
                                 {0.5 * std::numbers::pi, Eigen::Vector3d::UnitY(), false},
                                 {1.5 * std::numbers::pi, -Eigen::Vector3d::UnitY(), false}};
  double last_alpha[2] = {-1.0, -1.0};
  Eigen::Vector3d last_outward[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (const auto& cr : crossings) {
    const double alpha_c = Wrap2Pi(a.direction * (cr.theta - a.theta_start_rad));
    if (alpha_c > alpha_p || alpha_c > a.sweep_rad) continue;
    const double phi = alpha_p - alpha_c;
    const double h = cr.x_axis ? m.spike_x_um : m.spike_y_um;
    d += h * std::exp(-phi / decay_rad) * cr.outward;
    const int k = cr.x_axis ? 0 : 1;
    if (alpha_c > last_alpha[k]) { last_alpha[k] = alpha_c; last_outward[k] = cr.outward; }
  }
  d += 0.5 * m.backlash_x_um * last_outward[0] + 0.5 * m.backlash_y_um * last_outward[1];
  return d;
}

}  // namespace

std::optional<ArcTravel> ArcTravelAt(const FeatureCut& fc, const Eigen::Vector3d& point_part_mm,
                                     const Eigen::Matrix3d& machine_from_part) {
  const auto* c = std::get_if<PathMillCut>(&fc.model);
  if (!c || c->end_face) return std::nullopt;
  const PathElement* e = NearestElement(*c, point_part_mm);
  if (!e || !e->arc) return std::nullopt;
  const Eigen::Vector3d axis_m = machine_from_part * c->tool_axis;
  if (std::abs(axis_m.z()) < 1.0 - 1e-6) return std::nullopt;  // not an X-Y interpolation
  const Eigen::Vector3d radial_m =
      machine_from_part * Horizontal(point_part_mm - e->center_mm, c->tool_axis).normalized();
  const Eigen::Vector3d start_m = machine_from_part * e->start_dir;
  ArcTravel a;
  a.direction = ((!e->clockwise) == (axis_m.z() > 0)) ? 1.0 : -1.0;
  a.theta_rad = std::atan2(radial_m.y(), radial_m.x());
  a.theta_start_rad = std::atan2(start_m.y(), start_m.x());
  a.sweep_rad = e->angle_rad;
  return a;
}

Status ToolDeflectionModel::Validate() const {
  if (!(specific_force_n_per_mm2 >= 0) || !(passive_ratio >= 0) || !(feed_ratio >= 0) || !(floor_axial_area_mm2 >= 0))
    return {StatusCode::kInvalidArgument, "tool deflection: force coefficients must be >= 0"};
  if (!(compliance_um_per_n.array() >= 0).all() || !compliance_um_per_n.allFinite())
    return {StatusCode::kInvalidArgument, "tool deflection: compliance_um_per_n must be >= 0 and finite"};
  if (!std::isfinite(scale)) return {StatusCode::kInvalidArgument, "tool deflection: scale must be finite"};
  return {};
}

Status ServoReversalModel::Validate() const {
  if (!std::isfinite(spike_x_um) || !std::isfinite(spike_y_um) || !std::isfinite(backlash_x_um) ||
      !std::isfinite(backlash_y_um))
    return {StatusCode::kInvalidArgument, "servo reversal: spike and backlash values must be finite"};
  if (!(decay_deg > 0)) return {StatusCode::kInvalidArgument, "servo reversal: decay_deg must be > 0"};
  return {};
}

Status ProcessEffects::Validate() const {
  if (deflection) TPCAL_RETURN_IF_ERROR(deflection->Validate());
  if (servo) TPCAL_RETURN_IF_ERROR(servo->Validate());
  return {};
}

Result<double> ProcessDeviationMm(const TestPiece& piece, const kinematics::MachineModel& machine,
                                  const PlanPoint& pp, const ProcessEffects& effects) {
  TPCAL_RETURN_IF_ERROR(effects.Validate());
  if (effects.empty()) return 0.0;
  const FeatureCut* fc = piece.Cut(pp.feature);
  if (!fc) return Status(StatusCode::kInvalidArgument, "feature '" + pp.feature + "' has no cut");
  const kinematics::ErrorState zero(machine);
  kinematics::Workspace ws;
  const Eigen::Matrix3d machine_from_part = kinematics::MachineFromPart(machine, zero, pp.cut.axes, &ws).linear();
  Eigen::Vector3d d_machine_um = Eigen::Vector3d::Zero();
  if (effects.deflection) {
    const Eigen::Vector3d f_machine = machine_from_part * ForceOnTool(piece, *fc, pp, *effects.deflection);
    d_machine_um += effects.deflection->scale * effects.deflection->compliance_um_per_n.cwiseProduct(f_machine);
  }
  if (effects.servo) {
    if (auto arc = ArcTravelAt(*fc, pp.point_part_mm, machine_from_part))
      d_machine_um += ServoDisplacementUm(*arc, *effects.servo);
  }
  const Eigen::Vector3d d_part_um = machine_from_part.transpose() * d_machine_um;
  return UmToMm(pp.normal_part.dot(d_part_um));
}

}  // namespace tpcal::testpieces
