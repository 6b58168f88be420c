#include "gcode/datum_ball_program.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/units.h"
#include "gcode/dialect_check.h"
#include "gcode/nc_format.h"
#include "gcode/tool_table.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"

namespace tpcal::gcode {
namespace {

constexpr unsigned kMaskX = 0x1, kMaskY = 0x2, kMaskZ = 0x4, kMaskXyz = 0x7, kMaskRotary = 0x38;

Status BallOptionError(const std::string& what) { return {StatusCode::kInvalidArgument, "datum-ball probing: " + what}; }

// Rotary commands of `s` only (linear members zero).
kinematics::AxisState RotaryOf(const kinematics::AxisState& s) {
  kinematics::AxisState r;
  r.a_rad = s.a_rad, r.b_rad = s.b_rad, r.c_rad = s.c_rad;
  return r;
}

double RotaryStepDeg(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return RadToDeg(std::max({std::abs(b.a_rad - a.a_rad), std::abs(b.b_rad - a.b_rad), std::abs(b.c_rad - a.c_rad)}));
}

// Appends instructions, tracking where the axes are and the time estimate.
class BallIrBuilder {
 public:
  BallIrBuilder(IrProgram* prog, const DatumBallProbeOptions& probe) : prog_(prog), probe_(probe) {}

  void Add(Instr in) {
    in.start = cur_;
    if (in.kind == InstrKind::kProbe) in.end = MergeMasked(cur_, in.end, kMaskXyz);
    else if (in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex) in.end = MergeMasked(cur_, in.end, in.axis_mask);
    const Eigen::Vector3d d(in.end.x_mm - cur_.x_mm, in.end.y_mm - cur_.y_mm, in.end.z_mm - cur_.z_mm);
    if (in.kind == InstrKind::kProbe) in.duration_s = d.norm() / probe_.probe_feed_mm_per_min * 60.0;
    if (in.kind == InstrKind::kRapid) in.duration_s = d.norm() / probe_.rapid_mm_per_min * 60.0;
    if (in.kind == InstrKind::kIndex) in.duration_s = RotaryStepDeg(cur_, in.end) / probe_.index_deg_per_min * 60.0;
    prog_->duration_s += in.duration_s;
    if (in.kind == InstrKind::kProbe || in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex) cur_ = in.end;
    prog_->instrs.push_back(std::move(in));
  }

  void Simple(InstrKind kind, int op) {
    Instr in;
    in.kind = kind;
    in.op = op;
    Add(std::move(in));
  }

  // Rapid of the axes in `mask` to `target` (the others stay).
  void Rapid(const Eigen::Vector3d& target_mm, unsigned mask, int op) {
    Instr in;
    in.kind = InstrKind::kRapid;
    in.axis_mask = mask;
    in.end = cur_;
    in.end.x_mm = target_mm.x(), in.end.y_mm = target_mm.y(), in.end.z_mm = target_mm.z();
    in.op = op;
    Add(std::move(in));
  }

  void Index(const kinematics::AxisState& rotary, int op) {
    Instr in;
    in.kind = InstrKind::kIndex;
    in.axis_mask = kMaskRotary;
    in.end = cur_;
    in.end.a_rad = rotary.a_rad, in.end.b_rad = rotary.b_rad, in.end.c_rad = rotary.c_rad;
    in.op = op;
    Add(std::move(in));
  }

  void Probe(const Eigen::Vector3d& target_mm, const Eigen::Vector3d& contact_mm,
             const Eigen::Vector3d& direction, int result, int op) {
    Instr in;
    in.kind = InstrKind::kProbe;
    in.end = cur_;
    in.end.x_mm = target_mm.x(), in.end.y_mm = target_mm.y(), in.end.z_mm = target_mm.z();
    in.feed_mm_per_min = probe_.probe_feed_mm_per_min;
    in.probe.direction = direction;
    in.probe.contact_mm = contact_mm;
    in.probe.result = result;
    in.op = op;
    Add(std::move(in));
  }

  const kinematics::AxisState& current() const { return cur_; }

 private:
  static kinematics::AxisState MergeMasked(const kinematics::AxisState& from, const kinematics::AxisState& to,
                                           unsigned mask) {
    kinematics::AxisState s = from;
    if (mask & kMaskX) s.x_mm = to.x_mm;
    if (mask & kMaskY) s.y_mm = to.y_mm;
    if (mask & kMaskZ) s.z_mm = to.z_mm;
    if (mask & 0x8) s.a_rad = to.a_rad;
    if (mask & 0x10) s.b_rad = to.b_rad;
    if (mask & 0x20) s.c_rad = to.c_rad;
    return s;
  }

  IrProgram* prog_;
  const DatumBallProbeOptions& probe_;
  kinematics::AxisState cur_;
};

// Highest centring-command Z over the positions and the index sweeps between them (from the
// all-zero rotary state to the first position, then position to position), sampled every degree.
Result<double> HighestCentreZ(const kinematics::MachineModel& m, const kinematics::ErrorState& zero,
                              const testpieces::DatumBallPlan& plan) {
  double top = -1e300;
  kinematics::AxisState prev;
  for (const kinematics::AxisState& next : plan.positions) {
    const int n = std::max(1, static_cast<int>(std::ceil(RotaryStepDeg(prev, next))));
    for (int k = 0; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      kinematics::AxisState s;
      s.a_rad = prev.a_rad + f * (next.a_rad - prev.a_rad);
      s.b_rad = prev.b_rad + f * (next.b_rad - prev.b_rad);
      s.c_rad = prev.c_rad + f * (next.c_rad - prev.c_rad);
      auto c = kinematics::BallCentreCommand(m, zero, s, plan.ball_part_mm);
      if (!c.ok()) return c.status();
      top = std::max(top, c->z());
    }
    prev = RotaryOf(next);
  }
  return top;
}

std::string PositionText(const testpieces::DatumBallPlan& plan, std::size_t i, const Eigen::Vector3d& c_mm) {
  const kinematics::AxisState& p = plan.positions[i];
  const char tilt = plan.tilt_axis == kinematics::Axis::kA ? 'A' : 'B';
  const double tilt_rad = plan.tilt_axis == kinematics::Axis::kA ? p.a_rad : p.b_rad;
  return "POSITION " + std::to_string(i + 1) + "/" + std::to_string(plan.positions.size()) + ": " + tilt +
         FormatNumber(RadToDeg(tilt_rad), 4) + " C" + FormatNumber(RadToDeg(p.c_rad), 4) +
         ", nominal ball centre command X" + FormatNumber(c_mm.x(), 4) + " Y" + FormatNumber(c_mm.y(), 4) + " Z" +
         FormatNumber(c_mm.z(), 4) + ", 5 touches";
}

}  // namespace

Status DatumBallProbeOptions::Validate() const {
  if (!(stylus_diameter_mm > 0)) return BallOptionError("stylus_diameter_mm must be > 0");
  if (!(probe_length_mm >= 0)) return BallOptionError("probe_length_mm must be >= 0");
  if (probe_tool_number < 1) return BallOptionError("probe_tool_number must be >= 1");
  if (!(approach_mm > 0)) return BallOptionError("approach_mm must be > 0");
  if (!(overtravel_mm > 0)) return BallOptionError("overtravel_mm must be > 0");
  if (!(probe_feed_mm_per_min > 0)) return BallOptionError("probe_feed_mm_per_min must be > 0");
  if (!(safe_clearance_mm > 0)) return BallOptionError("safe_clearance_mm must be > 0");
  if (!(rapid_mm_per_min > 0) || !(index_deg_per_min > 0)) return BallOptionError("rates must be > 0");
  return Status::Ok();
}

Result<IrProgram> BuildDatumBallIr(const testpieces::DatumBallPlan& plan, const kinematics::MachineModel& machine,
                                   const DatumBallProbeOptions& probe, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(probe.Validate());
  if (plan.positions.empty()) return BallOptionError("the plan has no position");
  if (!(plan.ball_diameter_mm > 0)) return BallOptionError("the ball diameter must be > 0");
  IrProgram prog;
  prog.piece_name = "datum ball";
  prog.instrument = "datum ball, D " + FormatNumber(plan.ball_diameter_mm, 3) + " mm, nominal centre (part frame) X" +
                    FormatNumber(plan.ball_part_mm.x(), 4) + " Y" + FormatNumber(plan.ball_part_mm.y(), 4) + " Z" +
                    FormatNumber(plan.ball_part_mm.z(), 4) + ", " + std::to_string(plan.positions.size()) +
                    " rotary positions";
  prog.standard = "seed 001 datum-ball test: the ball centred by a spindle touch probe at each rotary position "
                  "(as Heidenhain KinematicsOpt cycle 451, Siemens CYCLE996, Renishaw AxiSet)";
  prog.machine_name = machine.name.empty() ? kinematics::MachineTypeName(machine.type) : machine.name;
  prog.machine = machine;
  prog.has_a = machine.HasAxis(kinematics::Axis::kA);
  prog.has_b = machine.HasAxis(kinematics::Axis::kB);
  prog.has_c = machine.HasAxis(kinematics::Axis::kC);
  prog.uses_rotary = true;

  IrTool tool;
  tool.tool.number = probe.probe_tool_number;
  tool.tool.name = "touch probe, stylus ball D" + FormatNumber(probe.stylus_diameter_mm, 3);
  tool.tool.kind = testpieces::ToolKind::kTouchProbe;
  tool.tool.diameter_mm = probe.stylus_diameter_mm;
  tool.number = probe.probe_tool_number;
  tool.length_mm = probe.probe_length_mm > 0 ? probe.probe_length_mm : options.default_tool_length_mm;
  prog.tools.push_back(tool);

  const kinematics::ErrorState zero(machine);
  auto top = HighestCentreZ(machine, zero, plan);
  if (!top.ok()) return top.status();
  const double contact_mm = 0.5 * (plan.ball_diameter_mm + probe.stylus_diameter_mm);  // R + r
  prog.safe_z_mm = *top + contact_mm + probe.safe_clearance_mm;

  BallIrBuilder b(&prog, probe);
  {
    Instr wo;
    wo.kind = InstrKind::kWorkOffset;
    wo.work_offset = options.work_offset;
    b.Add(wo);
    Instr tc;
    tc.kind = InstrKind::kToolChange;
    tc.tool_index = 0;
    b.Add(tc);
  }
  b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), kMaskZ, 0);

  // Outward directions of the touches (from the centre to the stylus), in touch order.
  const std::array<Eigen::Vector3d, 5> outward = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                                   -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                                   -Eigen::Vector3d::UnitY()};
  auto centres = testpieces::NominalCentringCommands(machine, plan);
  if (!centres.ok()) return centres.status();
  for (std::size_t i = 0; i < plan.positions.size(); ++i) {
    const int op = static_cast<int>(i) + 1;
    const Eigen::Vector3d* c = &(*centres)[i];
    const std::string text = PositionText(plan, i, *c);
    prog.operation_names.push_back(text);
    Instr comment;
    comment.kind = InstrKind::kOperationStart;
    comment.text = text;
    comment.op = op;
    b.Add(comment);
    b.Index(plan.positions[i], op);
    const double above_z = c->z() + contact_mm + probe.approach_mm;  // clears the ball everywhere
    for (std::size_t t = 0; t < outward.size(); ++t) {
      const Eigen::Vector3d& d = outward[t];
      const Eigen::Vector3d start = *c + (contact_mm + probe.approach_mm) * d;
      if (t == 0) {
        b.Rapid(Eigen::Vector3d(start.x(), start.y(), 0.0), kMaskX | kMaskY, op);
      } else {
        b.Rapid(Eigen::Vector3d(start.x(), start.y(), above_z), kMaskX | kMaskY, op);
      }
      b.Rapid(start, kMaskZ, op);
      b.Probe(*c + (contact_mm - probe.overtravel_mm) * d, *c + contact_mm * d, -d, static_cast<int>(t) + 1, op);
      b.Rapid(start, kMaskXyz, op);
      b.Rapid(Eigen::Vector3d(0.0, 0.0, above_z), kMaskZ, op);
    }
    b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), kMaskZ, op);
  }
  b.Simple(InstrKind::kProgramEnd, 0);
  return prog;
}

Result<PostedDatumBall> PostDatumBallProgram(const testpieces::DatumBallPlan& plan,
                                             const kinematics::MachineModel& machine,
                                             const DatumBallProbeOptions& probe, const GcodeOptions& options) {
  auto ir = BuildDatumBallIr(plan, machine, probe, options);
  if (!ir.ok()) return ir.status();
  PostedDatumBall out;
  out.ir = std::move(ir).value();
  auto posted = PostIr(out.ir, options);
  if (!posted.ok()) return posted.status();
  out.posted = std::move(posted).value();
  out.program_file = options.program_name + ProgramExtension(options.dialect);
  if (options.safety.check_strokes) {
    for (std::size_t i = 0; i < out.ir.instrs.size(); ++i) {
      const Instr& in = out.ir.instrs[i];
      if (in.kind != InstrKind::kRapid && in.kind != InstrKind::kIndex && in.kind != InstrKind::kProbe) continue;
      if (Status s = kinematics::CheckStrokes(machine, in.end); !s.ok()) {
        return Status(StatusCode::kInvalidArgument, LabelOf(out.posted, static_cast<int>(i)) + ": " +
                                                         InstrKindName(in.kind) + " target outside the machine's travel: " +
                                                         s.message())
            .WithContext(out.program_file);
      }
    }
  }
  auto syntax = CheckDialectSyntax(out.posted.text, options);
  if (!syntax.ok()) return syntax.status().WithContext(out.program_file + " (dialect check)");
  out.program_text = out.posted.text;
  if (options.dialect == Dialect::kLinuxCnc) {
    out.tool_table_file = options.tool_table_file.empty() ? options.program_name + ".tbl" : options.tool_table_file;
    out.tool_table_text = LinuxCncToolTable(out.ir);
  }
  return out;
}

}  // namespace tpcal::gcode
