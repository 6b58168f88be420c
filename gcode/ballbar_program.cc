#include "gcode/ballbar_program.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/units.h"
#include "gcode/internal/probe_moves.h"
#include "gcode/nc_format.h"

namespace tpcal::gcode {
namespace {

// Unity builds merge this file with the other gcode sources: every file-local name is prefixed.
Status BarProgramError(const std::string& what) { return {StatusCode::kInvalidArgument, "ball-bar program: " + what}; }

Eigen::Vector3d BarLinear(const kinematics::AxisState& s) { return {s.x_mm, s.y_mm, s.z_mm}; }

kinematics::AxisState BarWithLinear(kinematics::AxisState s, const Eigen::Vector3d& p) {
  s.x_mm = p.x(), s.y_mm = p.y(), s.z_mm = p.z();
  return s;
}

ArcPlane BarArcPlane(kinematics::BallbarPlane p) {
  return p == kinematics::BallbarPlane::kXY ? ArcPlane::kXY : p == kinematics::BallbarPlane::kZX ? ArcPlane::kZX
                                                                                                  : ArcPlane::kYZ;
}

// The plane's first and second linear axis (0 X, 1 Y, 2 Z).
int BarFirstAxis(kinematics::BallbarPlane p) {
  return p == kinematics::BallbarPlane::kXY ? 0 : p == kinematics::BallbarPlane::kYZ ? 1 : 2;
}

Result<kinematics::AxisState> BarCommand(const kinematics::MachineModel& m, const kinematics::BallbarGeometry& g,
                                         double angle_deg) {
  auto c = kinematics::BallbarCommand(m, g, angle_deg);
  if (!c.ok())
    return c.status().WithContext("ball-bar installation " + g.installation.name + " at " +
                                  FormatNumber(angle_deg, 6) + " deg");
  c->t_s = 0.0;
  return c;
}

// A rotary test's commands: the readings and the intermediate steps, in path order; `reading`
// marks the commands where a reading is taken.
struct BarRotaryPath {
  std::vector<kinematics::AxisState> commands;
  std::vector<double> step_deg;  // turned-axis step from the previous command (0 for the first)
  std::vector<bool> reading;
};

Result<BarRotaryPath> BarRotaryCommands(const kinematics::MachineModel& m, const BallbarProgramTest& t,
                                        double max_step_deg) {
  BarRotaryPath p;
  for (std::size_t i = 0; i < t.angles_deg.size(); ++i) {
    const double to = t.angles_deg[i];
    const double from = i == 0 ? to : t.angles_deg[i - 1];
    const int n = i == 0 ? 1 : std::max(1, static_cast<int>(std::ceil(std::abs(to - from) / max_step_deg - 1e-9)));
    for (int k = 1; k <= n; ++k) {
      const double a = k == n ? to : from + (to - from) * k / n;
      auto c = BarCommand(m, t.geometry, a);
      if (!c.ok()) return c.status();
      p.commands.push_back(*c);
      p.step_deg.push_back(std::abs(to - from) / n);
      p.reading.push_back(k == n);
    }
  }
  return p;
}

// The geometry of a circle test in command space (mm): centre, radius, the plane's unit axes, the
// feed arcs' centre and the start (feed arc angle -alpha) and turn-back point (+alpha).
struct BarCircle {
  kinematics::AxisState at_zero;  // the command at path angle 0 (holds included)
  Eigen::Vector3d centre, e1, e2, feed_centre, start, turn;
  double radius_mm = 0.0, feed_radius_mm = 0.0, feed_arc_rad = 0.0;
};

Result<BarCircle> BarCircleOf(const kinematics::MachineModel& m, const BallbarProgramTest& t,
                              const BallbarProgramOptions& bar) {
  BarCircle c;
  auto zero = BarCommand(m, t.geometry, 0.0);
  if (!zero.ok()) return zero.status();
  c.at_zero = *zero;
  const int i1 = BarFirstAxis(t.geometry.installation.plane);
  c.e1 = Eigen::Vector3d::Unit(i1);
  c.e2 = Eigen::Vector3d::Unit((i1 + 1) % 3);
  c.radius_mm = t.geometry.installation.nominal_length_mm;
  c.centre = BarLinear(*zero) - c.radius_mm * c.e1;
  c.feed_arc_rad = DegToRad(bar.feed_arc_deg);
  c.feed_radius_mm = bar.feed_in_mm / (1.0 - std::cos(c.feed_arc_rad));
  if (!(c.feed_radius_mm < 0.5 * c.radius_mm))
    return BarProgramError("installation " + t.geometry.installation.name + ": the feed-in arc (radius " +
                           FormatNumber(c.feed_radius_mm, 4) + " mm) does not fit inside the circle");
  c.feed_centre = c.centre + (c.radius_mm - c.feed_radius_mm) * c.e1;
  const double ca = std::cos(c.feed_arc_rad), sa = std::sin(c.feed_arc_rad);
  c.start = c.feed_centre + c.feed_radius_mm * (ca * c.e1 - sa * c.e2);
  c.turn = c.feed_centre + c.feed_radius_mm * (ca * c.e1 + sa * c.e2);
  return c;
}

std::string BarInstallationText(const BallbarProgramTest& t, std::size_t i, std::size_t n) {
  const kinematics::BallbarInstallation& inst = t.geometry.installation;
  std::string text = "INSTALLATION " + std::to_string(i + 1) + "/" + std::to_string(n) + ": " + inst.name + ", " +
                     kinematics::BallbarKindName(inst.kind) + " ";
  if (inst.kind == kinematics::BallbarKind::kCircle) {
    text += std::string(kinematics::BallbarPlaneName(inst.plane)) + ", radius " +
            FormatNumber(inst.nominal_length_mm, 4) + " mm, ccw then cw";
  } else {
    text += std::string(1, kinematics::AxisLetter(inst.axis)) + ", bar " + FormatNumber(inst.nominal_length_mm, 4) +
            " mm, " + std::to_string(t.angles_deg.size()) + " readings " + FormatNumber(t.angles_deg.front(), 4) +
            " .. " + FormatNumber(t.angles_deg.back(), 4) + " deg";
  }
  return text;
}

class BarIr {
 public:
  BarIr(IrProgram* prog, const BallbarProgramOptions& bar)
      : prog_(prog), bar_(bar),
        b_(prog, {.probe_feed_mm_per_min = bar.approach_feed_mm_per_min,
                  .rapid_mm_per_min = bar.rapid_mm_per_min,
                  .index_deg_per_min = bar.index_deg_per_min}) {}

  internal::ProbeIrBuilder& builder() { return b_; }

  void Feed(const kinematics::AxisState& to, double feed, int op) {
    Instr in;
    in.kind = InstrKind::kLinear;
    in.end = to;
    in.feed_mm_per_min = feed;
    in.duration_s = (BarLinear(to) - BarLinear(b_.current())).norm() / feed * 60.0;
    in.op = op;
    b_.Add(in);
  }

  // A step of the turned axis with the linear axes following.
  void RotaryStep(const kinematics::AxisState& to, double step_deg, int op) {
    Instr in;
    in.kind = InstrKind::kLinear;
    in.end = to;
    in.op = op;
    in.duration_s = std::max(step_deg, 1e-6) / bar_.rotary_feed_deg_per_min * 60.0;
    if ((BarLinear(to) - BarLinear(b_.current())).norm() < 1e-6) {
      in.feed_mm_per_min = bar_.rotary_feed_deg_per_min;  // a rotary-only block: F in deg/min
    } else {
      in.feed_mode = FeedMode::kInverseTime;
    }
    b_.Add(in);
  }

  void Arc(const BarCircle& c, ArcPlane plane, const Eigen::Vector3d& to, const Eigen::Vector3d& centre,
           double radius_mm, double angle_rad, bool clockwise, int op) {
    Instr in;
    in.kind = InstrKind::kArc;
    in.end = BarWithLinear(c.at_zero, to);
    in.arc_center_xy_mm = centre.head<2>();
    in.arc_center_z_mm = centre.z();
    in.arc_plane = plane;
    in.clockwise = clockwise;
    in.arc_angle_rad = angle_rad;
    in.feed_mm_per_min = bar_.feed_mm_per_min;
    in.duration_s = radius_mm * angle_rad / bar_.feed_mm_per_min * 60.0;
    in.op = op;
    b_.Add(in);
  }

  void Dwell(double s, int op) {
    Instr in;
    in.kind = InstrKind::kDwell;
    in.end = b_.current();  // the axes stay
    in.dwell_s = s;
    in.duration_s = s;
    in.op = op;
    b_.Add(in);
  }

  void Stop(const std::string& text, int op) {
    Instr in;
    in.kind = InstrKind::kProgramStop;
    in.end = b_.current();
    in.text = text;
    in.op = op;
    b_.Add(in);
  }

  // Index at safe Z, over the start, down to it; M0 to mount the bar.
  void Approach(const kinematics::AxisState& start, const std::string& name, int op) {
    b_.Index(start, op);
    b_.Rapid(BarLinear(start), internal::kProbeMaskX | internal::kProbeMaskY, op);
    b_.Rapid(BarLinear(start) + bar_.approach_mm * Eigen::Vector3d::UnitZ(), internal::kProbeMaskZ, op);
    Feed(start, bar_.approach_feed_mm_per_min, op);
    Stop("MOUNT THE BALL BAR: " + name, op);
  }

  void Leave(const std::string& name, int op) {
    Stop("REMOVE THE BALL BAR: " + name, op);
    Feed(BarWithLinear(b_.current(), BarLinear(b_.current()) + bar_.approach_mm * Eigen::Vector3d::UnitZ()),
         bar_.approach_feed_mm_per_min, op);
    b_.Rapid(Eigen::Vector3d(0.0, 0.0, prog_->safe_z_mm), internal::kProbeMaskZ, op);
  }

 private:
  IrProgram* prog_;
  BallbarProgramOptions bar_;
  internal::ProbeIrBuilder b_;
};

}  // namespace

Status BallbarProgramOptions::Validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(feed_mm_per_min)) return BarProgramError("feed_mm_per_min must be > 0");
  if (!positive(feed_in_mm)) return BarProgramError("feed_in_mm must be > 0");
  if (!(positive(feed_arc_deg) && feed_arc_deg <= 180.0)) return BarProgramError("feed_arc_deg must be in (0, 180]");
  if (!positive(rotary_feed_deg_per_min)) return BarProgramError("rotary_feed_deg_per_min must be > 0");
  if (!positive(max_step_deg)) return BarProgramError("max_step_deg must be > 0");
  if (!(std::isfinite(dwell_s) && dwell_s >= 0.0)) return BarProgramError("dwell_s must be >= 0");
  if (!positive(approach_mm)) return BarProgramError("approach_mm must be > 0");
  if (!positive(approach_feed_mm_per_min)) return BarProgramError("approach_feed_mm_per_min must be > 0");
  if (!positive(safe_clearance_mm)) return BarProgramError("safe_clearance_mm must be > 0");
  if (!positive(tool_ball_diameter_mm)) return BarProgramError("tool_ball_diameter_mm must be > 0");
  if (!(std::isfinite(tool_length_mm) && tool_length_mm >= 0.0)) return BarProgramError("tool_length_mm must be >= 0");
  if (tool_number < 1) return BarProgramError("tool_number must be >= 1");
  if (!positive(rapid_mm_per_min) || !positive(index_deg_per_min)) return BarProgramError("rates must be > 0");
  return Status::Ok();
}

Result<IrProgram> BuildBallbarIr(const std::vector<BallbarProgramTest>& tests, const kinematics::MachineModel& machine,
                                 const BallbarProgramOptions& bar, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(bar.Validate());
  if (tests.empty()) return BarProgramError("no installation");
  // Every command first: the safe Z is above all of them.
  std::vector<BarRotaryPath> rotary(tests.size());
  std::vector<BarCircle> circle(tests.size());
  double top_mm = -1e300;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const BallbarProgramTest& t = tests[i];
    if (t.geometry.installation.kind == kinematics::BallbarKind::kCircle) {
      auto c = BarCircleOf(machine, t, bar);
      if (!c.ok()) return c.status();
      circle[i] = *c;
      top_mm = std::max({top_mm, c->centre.z() + c->radius_mm * (c->e1.z() + c->e2.z()), c->start.z()});
    } else {
      if (t.angles_deg.empty()) return BarProgramError("installation " + t.geometry.installation.name + ": no angle");
      auto p = BarRotaryCommands(machine, t, bar.max_step_deg);
      if (!p.ok()) return p.status();
      for (const kinematics::AxisState& s : p->commands) top_mm = std::max(top_mm, s.z_mm);
      rotary[i] = std::move(p).value();
    }
  }

  IrProgram prog;
  prog.piece_name = "ball bar";
  prog.instrument = "double ball bar, " + std::to_string(tests.size()) + " installations";
  prog.standard = "seed 003 double-ball-bar test of the rotary axes (Ni et al.) and ISO 230-4 circular tests";
  internal::SetProbingMachine(&prog, machine);
  IrTool tool;
  tool.tool.number = bar.tool_number;
  tool.tool.name = "ball-bar spindle cup, tool ball D" + FormatNumber(bar.tool_ball_diameter_mm, 3);
  tool.tool.kind = testpieces::ToolKind::kTouchProbe;  // a measuring tool, no cutting
  tool.tool.diameter_mm = bar.tool_ball_diameter_mm;
  tool.number = bar.tool_number;
  tool.length_mm = bar.tool_length_mm > 0 ? bar.tool_length_mm : options.default_tool_length_mm;
  prog.tools.push_back(tool);
  prog.safe_z_mm = top_mm + bar.approach_mm + bar.safe_clearance_mm;

  BarIr ir(&prog, bar);
  ir.builder().Preamble(options.work_offset, prog.safe_z_mm);
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const BallbarProgramTest& t = tests[i];
    const std::string& name = t.geometry.installation.name;
    const int op = static_cast<int>(i) + 1;
    const std::string text = BarInstallationText(t, i, tests.size());
    prog.operation_names.push_back(text);
    Instr comment;
    comment.kind = InstrKind::kOperationStart;
    comment.text = text;
    comment.op = op;
    ir.builder().Add(comment);
    if (t.geometry.installation.kind == kinematics::BallbarKind::kCircle) {
      const BarCircle& c = circle[i];
      const ArcPlane plane = BarArcPlane(t.geometry.installation.plane);
      const Eigen::Vector3d at_zero = BarLinear(c.at_zero);
      constexpr double kFull = 2.0 * std::numbers::pi;
      ir.Approach(BarWithLinear(c.at_zero, c.start), name, op);
      ir.Arc(c, plane, at_zero, c.feed_centre, c.feed_radius_mm, c.feed_arc_rad, false, op);
      ir.Arc(c, plane, at_zero, c.centre, c.radius_mm, kFull, false, op);
      ir.Arc(c, plane, c.turn, c.feed_centre, c.feed_radius_mm, c.feed_arc_rad, false, op);
      ir.Dwell(bar.dwell_s, op);
      ir.Arc(c, plane, at_zero, c.feed_centre, c.feed_radius_mm, c.feed_arc_rad, true, op);
      ir.Arc(c, plane, at_zero, c.centre, c.radius_mm, kFull, true, op);
      ir.Arc(c, plane, c.start, c.feed_centre, c.feed_radius_mm, c.feed_arc_rad, true, op);
    } else {
      const BarRotaryPath& p = rotary[i];
      ir.Approach(p.commands.front(), name, op);
      for (std::size_t k = 0; k < p.commands.size(); ++k) {
        if (k > 0) ir.RotaryStep(p.commands[k], p.step_deg[k], op);
        if (p.reading[k]) ir.Dwell(bar.dwell_s, op);
      }
    }
    ir.Leave(name, op);
  }
  ir.builder().Simple(InstrKind::kProgramEnd, 0);
  return prog;
}

Result<PostedInstrumentProgram> PostBallbarProgram(const std::vector<BallbarProgramTest>& tests,
                                                   const kinematics::MachineModel& machine,
                                                   const BallbarProgramOptions& bar, const GcodeOptions& options) {
  auto ir = BuildBallbarIr(tests, machine, bar, options);
  if (!ir.ok()) return ir.status();
  auto posted = internal::PostProbingIr(std::move(ir).value(), machine, options);
  if (!posted.ok()) return posted.status();
  return posted;
}

}  // namespace tpcal::gcode
