#include "testpieces/program.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

constexpr double kSecondsPerMinute = 60.0;

double LinearDistance(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return std::sqrt((a.x_mm - b.x_mm) * (a.x_mm - b.x_mm) + (a.y_mm - b.y_mm) * (a.y_mm - b.y_mm) +
                   (a.z_mm - b.z_mm) * (a.z_mm - b.z_mm));
}

double MaxLinearTravel(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return std::max({std::abs(a.x_mm - b.x_mm), std::abs(a.y_mm - b.y_mm), std::abs(a.z_mm - b.z_mm)});
}

double MaxRotaryTravel(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return std::max({std::abs(a.a_rad - b.a_rad), std::abs(a.b_rad - b.b_rad), std::abs(a.c_rad - b.c_rad)});
}

// Antiderivative over the radius r of 1 / n(r) (min per rev), for Spindle::TableRpmAt.
double InverseSpeedIntegral(const Spindle& s, double r) {
  if (s.surface_speed_m_per_min <= 0) return r / s.speed_rpm;
  const double k = s.surface_speed_m_per_min * 1000.0 / (2.0 * kPi);  // n = k / r (rpm, r in mm)
  const double n_max = s.max_speed_rpm > 0 ? s.max_speed_rpm : std::numeric_limits<double>::infinity();
  const double r_c = k / n_max;  // below r_c the speed is clamped
  if (r <= r_c) return r / n_max;
  return r_c / n_max + (r * r - r_c * r_c) / (2.0 * k);
}

// Minutes to feed `length` mm at f mm/rev while the radius goes linearly r0 -> r(sigma).
double TurningMinutes(const Spindle& s, double length_mm, double f_mm_per_rev, double r0, double r1, double sigma) {
  if (length_mm <= 0) return 0.0;
  if (std::abs(r1 - r0) < 1e-12) return length_mm * sigma / (f_mm_per_rev * s.TableRpmAt(r0));
  const double r = r0 + (r1 - r0) * sigma;
  return length_mm / (f_mm_per_rev * (r1 - r0)) * (InverseSpeedIntegral(s, r) - InverseSpeedIntegral(s, r0));
}

}  // namespace

const char* ToolKindName(ToolKind k) {
  switch (k) {
    case ToolKind::kEndMill: return "end_mill";
    case ToolKind::kFaceMill: return "face_mill";
    case ToolKind::kReamer: return "reamer";
    case ToolKind::kTurningInsert: return "turning_insert";
    case ToolKind::kTouchProbe: return "touch_probe";
  }
  return "?";
}

const char* SpindleModeName(SpindleMode m) {
  switch (m) {
    case SpindleMode::kOff: return "off";
    case SpindleMode::kMilling: return "milling";
    case SpindleMode::kTableTurning: return "table_turning";
  }
  return "?";
}

const char* MoveKindName(MoveKind k) {
  switch (k) {
    case MoveKind::kRapid: return "rapid";
    case MoveKind::kLinear: return "linear";
    case MoveKind::kArc: return "arc";
    case MoveKind::kToolChange: return "tool_change";
    case MoveKind::kDwell: return "dwell";
  }
  return "?";
}

double Spindle::TableRpmAt(double radius_mm) const {
  if (surface_speed_m_per_min <= 0) return speed_rpm;
  const double n = surface_speed_m_per_min * 1000.0 / (2.0 * kPi * std::max(radius_mm, 1e-9));
  return max_speed_rpm > 0 ? std::min(n, max_speed_rpm) : n;
}

Status ProcessModel::Validate() const {
  if (!(rapid_mm_per_min > 0)) return {StatusCode::kInvalidArgument, "process.rapid_mm_per_min must be > 0"};
  if (!(rotary_rapid_deg_per_s > 0)) {
    return {StatusCode::kInvalidArgument, "process.rotary_rapid_deg_per_s must be > 0"};
  }
  if (!(tool_change_s >= 0)) return {StatusCode::kInvalidArgument, "process.tool_change_s must be >= 0"};
  if (!(spindle_start_s >= 0)) return {StatusCode::kInvalidArgument, "process.spindle_start_s must be >= 0"};
  return Status::Ok();
}

ProgramBuilder::ProgramBuilder(const ProcessModel& process) : process_(process) {}

void ProgramBuilder::BeginOperation(const std::string& name, const std::string& description, const Tool& tool) {
  Operation op;
  op.number = static_cast<int>(ops_.size()) + 1;
  op.name = name;
  op.description = description;
  op.tool = tool;
  op.start_time_s = state_.t_s;
  ops_.push_back(std::move(op));
  state_.op = ops_.back().number;
}

void ProgramBuilder::BeginPass(const std::string& name, const Spindle& spindle, std::vector<std::string> features) {
  assert(!ops_.empty());
  Operation& op = ops_.back();
  const bool first_pass = op.passes.empty();
  Spindle previous;
  if (!first_pass) previous = op.passes.back().spindle;
  Pass pass;
  pass.name = name;
  pass.spindle = spindle;
  pass.features = std::move(features);
  pass.start_time_s = state_.t_s;
  op.passes.push_back(std::move(pass));
  if (first_pass && op.tool.number != current_tool_) {
    Move m;
    m.kind = MoveKind::kToolChange;
    m.duration_s = process_.tool_change_s;
    m.end = state_;
    Append(m);
    current_tool_ = op.tool.number;
  }
  const bool spindle_changed = first_pass || previous.mode != spindle.mode ||
                               previous.speed_rpm != spindle.speed_rpm ||
                               previous.surface_speed_m_per_min != spindle.surface_speed_m_per_min;
  if (spindle.mode != SpindleMode::kOff && spindle_changed) Dwell(process_.spindle_start_s);
}

void ProgramBuilder::Append(Move m) {
  assert(!ops_.empty() && !ops_.back().passes.empty());
  m.start_time_s = state_.t_s;
  m.start = state_;
  state_ = m.end;
  state_.t_s = m.start_time_s + m.duration_s;
  state_.op = ops_.back().number;
  m.end = state_;
  ops_.back().passes.back().moves.push_back(m);
}

void ProgramBuilder::Rapid(const kinematics::AxisState& target) {
  Move m;
  m.kind = MoveKind::kRapid;
  m.end = target;
  const double linear_s = MaxLinearTravel(state_, target) / process_.rapid_mm_per_min * kSecondsPerMinute;
  const double rotary_s = RadToDeg(MaxRotaryTravel(state_, target)) / process_.rotary_rapid_deg_per_s;
  m.duration_s = std::max(linear_s, rotary_s);
  Append(m);
}

void ProgramBuilder::Linear(const kinematics::AxisState& target, double feed_mm_per_min, bool cutting,
                            double path_length_mm) {
  assert(feed_mm_per_min > 0);
  Move m;
  m.kind = MoveKind::kLinear;
  m.end = target;
  m.feed_mm_per_min = feed_mm_per_min;
  m.cutting = cutting;
  const double length = path_length_mm > 0 ? path_length_mm : LinearDistance(state_, target);
  m.duration_s = length / feed_mm_per_min * kSecondsPerMinute;
  Append(m);
}

void ProgramBuilder::TurnLinear(const kinematics::AxisState& target, double feed_mm_per_rev,
                                double start_radius_mm, double end_radius_mm, bool cutting) {
  assert(feed_mm_per_rev > 0);
  const Spindle& spindle = ops_.back().passes.back().spindle;
  Move m;
  m.kind = MoveKind::kLinear;
  m.end = target;
  m.feed_mm_per_rev = feed_mm_per_rev;
  m.turn_radius_start_mm = start_radius_mm;
  m.turn_radius_end_mm = end_radius_mm;
  m.cutting = cutting;
  const double length = LinearDistance(state_, target);
  m.duration_s = TurningMinutes(spindle, length, feed_mm_per_rev, start_radius_mm, end_radius_mm, 1.0) *
                 kSecondsPerMinute;
  Append(m);
}

void ProgramBuilder::Arc(const Eigen::Vector2d& center_xy_mm, double angle_rad, bool clockwise,
                         double feed_mm_per_min, bool cutting) {
  assert(feed_mm_per_min > 0 && angle_rad > 0);
  Move m;
  m.kind = MoveKind::kArc;
  m.arc_center_xy_mm = center_xy_mm;
  m.clockwise = clockwise;
  m.arc_angle_rad = angle_rad;
  m.feed_mm_per_min = feed_mm_per_min;
  m.cutting = cutting;
  const Eigen::Vector2d r0(state_.x_mm - center_xy_mm.x(), state_.y_mm - center_xy_mm.y());
  const double signed_angle = clockwise ? -angle_rad : angle_rad;
  const Eigen::Vector2d r1 = Eigen::Rotation2Dd(signed_angle) * r0;
  m.end = state_;
  m.end.x_mm = center_xy_mm.x() + r1.x();
  m.end.y_mm = center_xy_mm.y() + r1.y();
  m.duration_s = r0.norm() * angle_rad / feed_mm_per_min * kSecondsPerMinute;
  Append(m);
}

void ProgramBuilder::Dwell(double seconds) {
  Move m;
  m.kind = MoveKind::kDwell;
  m.end = state_;
  m.duration_s = seconds;
  Append(m);
}

int ProgramBuilder::last_move_index() const {
  return static_cast<int>(ops_.back().passes.back().moves.size()) - 1;
}

int ProgramBuilder::current_pass_index() const { return static_cast<int>(ops_.back().passes.size()) - 1; }

std::vector<Operation> ProgramBuilder::Finish() {
  for (Operation& op : ops_) {
    for (Pass& pass : op.passes) {
      if (!pass.moves.empty()) {
        pass.start_time_s = pass.moves.front().start_time_s;
        pass.end_time_s = pass.moves.back().end.t_s;
      }
    }
    if (!op.passes.empty()) {
      op.start_time_s = op.passes.front().start_time_s;
      op.end_time_s = op.passes.back().end_time_s;
    }
  }
  return std::move(ops_);
}

double TimeAtFraction(const Move& move, double f, const Spindle& spindle) {
  f = std::clamp(f, 0.0, 1.0);
  if (move.kind == MoveKind::kLinear && move.feed_mm_per_rev > 0 && move.duration_s > 0) {
    const double full = TurningMinutes(spindle, 1.0, move.feed_mm_per_rev, move.turn_radius_start_mm,
                                       move.turn_radius_end_mm, 1.0);
    const double part = TurningMinutes(spindle, 1.0, move.feed_mm_per_rev, move.turn_radius_start_mm,
                                       move.turn_radius_end_mm, f);
    return move.start_time_s + move.duration_s * (full > 0 ? part / full : f);
  }
  return move.start_time_s + f * move.duration_s;
}

double ProgramDuration(const std::vector<Operation>& ops) { return ops.empty() ? 0.0 : ops.back().end_time_s; }

}  // namespace tpcal::testpieces
