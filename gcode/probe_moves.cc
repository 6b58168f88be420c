// The shared probing-program machinery of gcode/internal/probe_moves.h.
#include "gcode/internal/probe_moves.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/units.h"
#include "gcode/dialect_check.h"
#include "gcode/nc_format.h"
#include "gcode/tool_table.h"

namespace tpcal::gcode::internal {
namespace {

// Unity builds merge this file with the other gcode sources: file-local names are prefixed.
kinematics::AxisState ProbeMergeMasked(const kinematics::AxisState& from, const kinematics::AxisState& to,
                                       unsigned mask) {
  kinematics::AxisState s = from;
  if (mask & kProbeMaskX) s.x_mm = to.x_mm;
  if (mask & kProbeMaskY) s.y_mm = to.y_mm;
  if (mask & kProbeMaskZ) s.z_mm = to.z_mm;
  if (mask & 0x8) s.a_rad = to.a_rad;
  if (mask & 0x10) s.b_rad = to.b_rad;
  if (mask & 0x20) s.c_rad = to.c_rad;
  return s;
}

// The axes `swept_rad` along arc `in` from its start (the plane's two axes turned about the centre).
kinematics::AxisState ProbeArcPoint(const Instr& in, double swept_rad) {
  const Eigen::Vector3d c(in.arc_center_xy_mm.x(), in.arc_center_xy_mm.y(), in.arc_center_z_mm);
  const Eigen::Vector3d p(in.start.x_mm, in.start.y_mm, in.start.z_mm);
  const int i1 = in.arc_plane == ArcPlane::kXY ? 0 : in.arc_plane == ArcPlane::kZX ? 2 : 1, i2 = (i1 + 1) % 3;
  const double a = (in.clockwise ? -1.0 : 1.0) * swept_rad;
  const double u = p(i1) - c(i1), v = p(i2) - c(i2);
  Eigen::Vector3d q = p;
  q(i1) = c(i1) + std::cos(a) * u - std::sin(a) * v;
  q(i2) = c(i2) + std::sin(a) * u + std::cos(a) * v;
  kinematics::AxisState s = in.start;
  s.x_mm = q.x(), s.y_mm = q.y(), s.z_mm = q.z();
  return s;
}

}  // namespace

double ProbeRotaryStepDeg(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return RadToDeg(std::max({std::abs(b.a_rad - a.a_rad), std::abs(b.b_rad - a.b_rad), std::abs(b.c_rad - a.c_rad)}));
}

void ProbeIrBuilder::Add(Instr in) {
  in.start = cur_;
  if (in.kind == InstrKind::kProbe) in.end = ProbeMergeMasked(cur_, in.end, kProbeMaskXyz);
  else if (in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex) in.end = ProbeMergeMasked(cur_, in.end, in.axis_mask);
  const Eigen::Vector3d d(in.end.x_mm - cur_.x_mm, in.end.y_mm - cur_.y_mm, in.end.z_mm - cur_.z_mm);
  if (in.kind == InstrKind::kProbe) in.duration_s = d.norm() / rates_.probe_feed_mm_per_min * 60.0;
  if (in.kind == InstrKind::kRapid) in.duration_s = d.norm() / rates_.rapid_mm_per_min * 60.0;
  if (in.kind == InstrKind::kIndex) in.duration_s = ProbeRotaryStepDeg(cur_, in.end) / rates_.index_deg_per_min * 60.0;
  prog_->duration_s += in.duration_s;
  if (in.kind == InstrKind::kProbe || in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex ||
      in.kind == InstrKind::kLinear || in.kind == InstrKind::kArc)
    cur_ = in.end;
  prog_->instrs.push_back(std::move(in));
}

void ProbeIrBuilder::Simple(InstrKind kind, int op) {
  Instr in;
  in.kind = kind;
  in.op = op;
  Add(std::move(in));
}

void ProbeIrBuilder::Preamble(int work_offset, double safe_z_mm) {
  Instr wo;
  wo.kind = InstrKind::kWorkOffset;
  wo.work_offset = work_offset;
  Add(wo);
  Instr tc;
  tc.kind = InstrKind::kToolChange;
  tc.tool_index = 0;
  Add(tc);
  Rapid(Eigen::Vector3d(0.0, 0.0, safe_z_mm), kProbeMaskZ, 0);
}

void ProbeIrBuilder::Rapid(const Eigen::Vector3d& target_mm, unsigned mask, int op) {
  Instr in;
  in.kind = InstrKind::kRapid;
  in.axis_mask = mask;
  in.end = cur_;
  in.end.x_mm = target_mm.x(), in.end.y_mm = target_mm.y(), in.end.z_mm = target_mm.z();
  in.op = op;
  Add(std::move(in));
}

void ProbeIrBuilder::Index(const kinematics::AxisState& rotary, int op) {
  Instr in;
  in.kind = InstrKind::kIndex;
  in.axis_mask = kProbeMaskRotary;
  in.end = cur_;
  in.end.a_rad = rotary.a_rad, in.end.b_rad = rotary.b_rad, in.end.c_rad = rotary.c_rad;
  in.op = op;
  Add(std::move(in));
}

void ProbeIrBuilder::Probe(const Eigen::Vector3d& target_mm, const Eigen::Vector3d& contact_mm,
                           const Eigen::Vector3d& direction, int result, int op) {
  Instr in;
  in.kind = InstrKind::kProbe;
  in.end = cur_;
  in.end.x_mm = target_mm.x(), in.end.y_mm = target_mm.y(), in.end.z_mm = target_mm.z();
  in.feed_mm_per_min = rates_.probe_feed_mm_per_min;
  in.probe.direction = direction;
  in.probe.contact_mm = contact_mm;
  in.probe.result = result;
  in.op = op;
  Add(std::move(in));
}

void SetProbingMachine(IrProgram* prog, const kinematics::MachineModel& machine) {
  prog->machine_name = machine.name.empty() ? kinematics::MachineTypeName(machine.type) : machine.name;
  prog->machine = machine;
  prog->has_a = machine.HasAxis(kinematics::Axis::kA);
  prog->has_b = machine.HasAxis(kinematics::Axis::kB);
  prog->has_c = machine.HasAxis(kinematics::Axis::kC);
  prog->uses_rotary = true;
}

IrTool ProbeTool(int number, double stylus_diameter_mm, double length_mm, const GcodeOptions& options) {
  IrTool tool;
  tool.tool.number = number;
  tool.tool.name = "touch probe, stylus ball D" + FormatNumber(stylus_diameter_mm, 3);
  tool.tool.kind = testpieces::ToolKind::kTouchProbe;
  tool.tool.diameter_mm = stylus_diameter_mm;
  tool.number = number;
  tool.length_mm = length_mm > 0 ? length_mm : options.default_tool_length_mm;
  return tool;
}

Result<PostedInstrumentProgram> PostProbingIr(IrProgram ir, const kinematics::MachineModel& machine,
                                              const GcodeOptions& options) {
  PostedInstrumentProgram out;
  out.ir = std::move(ir);
  auto posted = PostIr(out.ir, options);
  if (!posted.ok()) return posted.status();
  out.posted = std::move(posted).value();
  out.program_file = options.program_name + ProgramExtension(options.dialect);
  if (options.safety.check_strokes) {
    for (std::size_t i = 0; i < out.ir.instrs.size(); ++i) {
      const Instr& in = out.ir.instrs[i];
      if (in.kind != InstrKind::kRapid && in.kind != InstrKind::kIndex && in.kind != InstrKind::kProbe &&
          in.kind != InstrKind::kLinear && in.kind != InstrKind::kArc)
        continue;
      Status s = kinematics::CheckStrokes(machine, in.end);
      if (in.kind == InstrKind::kArc)
        for (int k = 1; s.ok() && k * 5.0 < RadToDeg(in.arc_angle_rad); ++k)
          s = kinematics::CheckStrokes(machine, ProbeArcPoint(in, DegToRad(5.0 * k)));
      if (!s.ok()) {
        return Status(StatusCode::kInvalidArgument, LabelOf(out.posted, static_cast<int>(i)) + ": " +
                                                         InstrKindName(in.kind) +
                                                         " target outside the machine's travel: " + s.message())
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

}  // namespace tpcal::gcode::internal
