#include "gcode/probe_artifacts_program.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"
#include "gcode/dialect_check.h"
#include "gcode/nc_format.h"
#include "gcode/tool_table.h"

namespace tpcal::gcode {
namespace {

// Unity builds merge this file with datum_ball_program.cc: every file-local name is prefixed.
constexpr unsigned kArtMaskX = 0x1, kArtMaskY = 0x2, kArtMaskZ = 0x4, kArtMaskXyz = 0x7, kArtMaskRotary = 0x38;

constexpr std::size_t kArtCommentMaxChars = 200;  // pose comment, before the dialect's delimiters

Status ArtifactProgramError(const std::string& what) {
  return {StatusCode::kInvalidArgument, "probe-artifacts probing: " + what};
}

double ArtifactRotaryStepDeg(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return RadToDeg(std::max({std::abs(b.a_rad - a.a_rad), std::abs(b.b_rad - a.b_rad), std::abs(b.c_rad - a.c_rad)}));
}

bool ArtifactSamePose(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return a.a_rad == b.a_rad && a.b_rad == b.b_rad && a.c_rad == b.c_rad;
}

// Appends instructions, tracking where the axes are and the time estimate (as the datum-ball
// program's builder).
class ArtifactIrBuilder {
 public:
  ArtifactIrBuilder(IrProgram* prog, const ProbeArtifactsProbeOptions& probe) : prog_(prog), probe_(probe) {}

  void Add(Instr in) {
    in.start = cur_;
    if (in.kind == InstrKind::kProbe) in.end = Merge(cur_, in.end, kArtMaskXyz);
    else if (in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex) in.end = Merge(cur_, in.end, in.axis_mask);
    const Eigen::Vector3d d(in.end.x_mm - cur_.x_mm, in.end.y_mm - cur_.y_mm, in.end.z_mm - cur_.z_mm);
    if (in.kind == InstrKind::kProbe) in.duration_s = d.norm() / probe_.probe_feed_mm_per_min * 60.0;
    if (in.kind == InstrKind::kRapid) in.duration_s = d.norm() / probe_.rapid_mm_per_min * 60.0;
    if (in.kind == InstrKind::kIndex) in.duration_s = ArtifactRotaryStepDeg(cur_, in.end) / probe_.index_deg_per_min * 60.0;
    prog_->duration_s += in.duration_s;
    if (in.kind == InstrKind::kProbe || in.kind == InstrKind::kRapid || in.kind == InstrKind::kIndex) cur_ = in.end;
    prog_->instrs.push_back(std::move(in));
  }

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
    in.axis_mask = kArtMaskRotary;
    in.end = cur_;
    in.end.a_rad = rotary.a_rad, in.end.b_rad = rotary.b_rad, in.end.c_rad = rotary.c_rad;
    in.op = op;
    Add(std::move(in));
  }

  void Probe(const Eigen::Vector3d& target_mm, const Eigen::Vector3d& centre_at_contact_mm,
             const Eigen::Vector3d& direction, int result, int op) {
    Instr in;
    in.kind = InstrKind::kProbe;
    in.end = cur_;
    in.end.x_mm = target_mm.x(), in.end.y_mm = target_mm.y(), in.end.z_mm = target_mm.z();
    in.feed_mm_per_min = probe_.probe_feed_mm_per_min;
    in.probe.direction = direction;
    in.probe.contact_mm = centre_at_contact_mm;
    in.probe.result = result;
    in.op = op;
    Add(std::move(in));
  }

 private:
  static kinematics::AxisState Merge(const kinematics::AxisState& from, const kinematics::AxisState& to, unsigned mask) {
    kinematics::AxisState s = from;
    if (mask & kArtMaskX) s.x_mm = to.x_mm;
    if (mask & kArtMaskY) s.y_mm = to.y_mm;
    if (mask & kArtMaskZ) s.z_mm = to.z_mm;
    if (mask & 0x8) s.a_rad = to.a_rad;
    if (mask & 0x10) s.b_rad = to.b_rad;
    if (mask & 0x20) s.c_rad = to.c_rad;
    return s;
  }

  IrProgram* prog_;
  const ProbeArtifactsProbeOptions& probe_;
  kinematics::AxisState cur_;
};

// Highest machine Z of any box corner at the indexed poses and over the index sweeps between
// them (from the all-zero rotary state to the first, then pose to pose), sampled every degree.
double ArtifactHighestCornerZ(const kinematics::MachineModel& m, const kinematics::ArtifactSet& artifacts,
                              const std::vector<kinematics::AxisState>& indexed) {
  std::vector<Eigen::Vector3d> corners;
  for (const kinematics::ArtifactBox& b : artifacts.boxes) {
    const double rot = DegToRad(b.rotation_deg);
    const Eigen::Vector3d ex(std::cos(rot), std::sin(rot), 0.0), ey(-std::sin(rot), std::cos(rot), 0.0);
    for (int sx : {-1, 1})
      for (int sy : {-1, 1})
        for (double z : {0.0, b.size_mm.z()})
          corners.push_back(b.base_centre_mm + 0.5 * sx * b.size_mm.x() * ex + 0.5 * sy * b.size_mm.y() * ey +
                            z * Eigen::Vector3d::UnitZ());
  }
  double top = -1e300;
  kinematics::AxisState prev;
  for (const kinematics::AxisState& next : indexed) {
    const int n = std::max(1, static_cast<int>(std::ceil(ArtifactRotaryStepDeg(prev, next))));
    for (int k = 0; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      kinematics::AxisState s;
      s.a_rad = prev.a_rad + f * (next.a_rad - prev.a_rad);
      s.b_rad = prev.b_rad + f * (next.b_rad - prev.b_rad);
      s.c_rad = prev.c_rad + f * (next.c_rad - prev.c_rad);
      const Rigid3 machine_from_table = kinematics::NominalMachineFromTable(m, s);
      for (const Eigen::Vector3d& p : corners) top = std::max(top, (machine_from_table * p).z());
    }
    prev = next;
  }
  return top;
}

std::string ArtifactPoseText(const testpieces::ProbeArtifactsPlan& plan, std::size_t i,
                             const std::vector<const testpieces::PlannedTouch*>& touches, std::size_t skipped) {
  const kinematics::AxisState& p = plan.poses[i];
  std::string text = "POSE " + std::to_string(i + 1) + "/" + std::to_string(plan.poses.size()) + ": A" +
                     FormatNumber(RadToDeg(p.a_rad), 4) + " C" + FormatNumber(RadToDeg(p.c_rad), 4) + ", " +
                     std::to_string(touches.size()) + " touches, " + std::to_string(skipped) + " skipped";
  // Q1.. in order, as "<artifact name><face>" (LinuxCNC reads lines of at most 255 characters).
  for (std::size_t t = 0; t < touches.size(); ++t) {
    const std::string item = std::string(t == 0 ? ", Q1..: " : " ") +
                             plan.artifacts.boxes[touches[t]->artifact].name + kinematics::BoxFaceName(touches[t]->face);
    if (text.size() + item.size() > kArtCommentMaxChars - 4) {
      text += " ...";
      break;
    }
    text += item;
  }
  return text;
}

}  // namespace

Status ProbeArtifactsProbeOptions::Validate() const {
  if (!(probe_length_mm >= 0)) return ArtifactProgramError("probe_length_mm must be >= 0");
  if (probe_tool_number < 1) return ArtifactProgramError("probe_tool_number must be >= 1");
  if (!(approach_mm > 0)) return ArtifactProgramError("approach_mm must be > 0");
  if (!(overtravel_mm > 0)) return ArtifactProgramError("overtravel_mm must be > 0");
  if (!(probe_feed_mm_per_min > 0)) return ArtifactProgramError("probe_feed_mm_per_min must be > 0");
  if (!(safe_clearance_mm > 0)) return ArtifactProgramError("safe_clearance_mm must be > 0");
  if (!(rapid_mm_per_min > 0) || !(index_deg_per_min > 0)) return ArtifactProgramError("rates must be > 0");
  return Status::Ok();
}

Result<IrProgram> BuildProbeArtifactsIr(const testpieces::ProbeArtifactsPlan& plan,
                                        const kinematics::MachineModel& machine,
                                        const ProbeArtifactsProbeOptions& probe, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(probe.Validate());
  if (plan.poses.empty()) return ArtifactProgramError("the plan has no pose");
  if (plan.touches.empty()) return ArtifactProgramError("the plan has no touch");
  if (!(plan.probe_radius_mm > 0)) return ArtifactProgramError("the plan's probe radius must be > 0");
  for (const testpieces::PlannedTouch& t : plan.touches)
    if (t.artifact < 0 || t.artifact >= static_cast<int>(plan.artifacts.boxes.size()))
      return ArtifactProgramError("a touch names artifact index " + std::to_string(t.artifact) +
                                  ", the plan holds " + std::to_string(plan.artifacts.boxes.size()));
  const double r = plan.probe_radius_mm;

  // The touches of each pose (the plan lists them pose by pose).
  std::vector<std::vector<const testpieces::PlannedTouch*>> by_pose(plan.poses.size());
  std::vector<std::size_t> skipped(plan.poses.size(), 0);
  std::vector<kinematics::AxisState> indexed;
  for (std::size_t i = 0; i < plan.poses.size(); ++i) {
    for (const testpieces::PlannedTouch& t : plan.touches)
      if (ArtifactSamePose(t.rotary, plan.poses[i])) by_pose[i].push_back(&t);
    for (const testpieces::SkippedTouch& s : plan.skipped) skipped[i] += ArtifactSamePose(s.rotary, plan.poses[i]);
    if (!by_pose[i].empty()) indexed.push_back(plan.poses[i]);
  }

  IrProgram prog;
  prog.piece_name = "probe artifacts";
  prog.instrument = "probe artifacts, " + std::to_string(plan.artifacts.boxes.size()) + " boxes, " +
                    std::to_string(plan.poses.size()) + " rotary poses, " + std::to_string(plan.touches.size()) +
                    " touches (" + std::to_string(plan.skipped.size()) + " skipped)";
  prog.standard = "seed 000 on-machine probing of artifacts: one touch per reachable face centre at each "
                  "indexed A/C pose";
  prog.machine_name = machine.name.empty() ? kinematics::MachineTypeName(machine.type) : machine.name;
  prog.machine = machine;
  prog.has_a = machine.HasAxis(kinematics::Axis::kA);
  prog.has_b = machine.HasAxis(kinematics::Axis::kB);
  prog.has_c = machine.HasAxis(kinematics::Axis::kC);
  prog.uses_rotary = true;

  IrTool tool;
  tool.tool.number = probe.probe_tool_number;
  tool.tool.name = "touch probe, stylus ball D" + FormatNumber(2.0 * r, 3);
  tool.tool.kind = testpieces::ToolKind::kTouchProbe;
  tool.tool.diameter_mm = 2.0 * r;
  tool.number = probe.probe_tool_number;
  tool.length_mm = probe.probe_length_mm > 0 ? probe.probe_length_mm : options.default_tool_length_mm;
  prog.tools.push_back(tool);

  double top = ArtifactHighestCornerZ(machine, plan.artifacts, indexed) + r;
  for (const testpieces::PlannedTouch& t : plan.touches)
    top = std::max(top, (t.contact_mm - (r + probe.approach_mm) * t.approach).z());
  prog.safe_z_mm = top + probe.safe_clearance_mm;

  ArtifactIrBuilder b(&prog, probe);
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
  b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), kArtMaskZ, 0);

  for (std::size_t i = 0; i < plan.poses.size(); ++i) {
    const int op = static_cast<int>(i) + 1;
    const std::string text = ArtifactPoseText(plan, i, by_pose[i], skipped[i]);
    prog.operation_names.push_back(text);
    Instr comment;
    comment.kind = InstrKind::kOperationStart;
    comment.text = text;
    comment.op = op;
    b.Add(comment);
    if (by_pose[i].empty()) continue;
    b.Index(plan.poses[i], op);
    for (std::size_t k = 0; k < by_pose[i].size(); ++k) {
      const testpieces::PlannedTouch& t = *by_pose[i][k];
      const Eigen::Vector3d n = -t.approach;
      const Eigen::Vector3d start = t.contact_mm + (r + probe.approach_mm) * n;
      b.Rapid(Eigen::Vector3d(start.x(), start.y(), 0.0), kArtMaskX | kArtMaskY, op);
      b.Rapid(start, kArtMaskZ, op);
      b.Probe(t.contact_mm + (r - probe.overtravel_mm) * n, t.contact_mm + r * n, t.approach, static_cast<int>(k) + 1, op);
      b.Rapid(start, kArtMaskXyz, op);
      b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), kArtMaskZ, op);
    }
  }
  Instr end;
  end.kind = InstrKind::kProgramEnd;
  b.Add(end);
  return prog;
}

Result<PostedProbeArtifacts> PostProbeArtifactsProgram(const testpieces::ProbeArtifactsPlan& plan,
                                                       const kinematics::MachineModel& machine,
                                                       const ProbeArtifactsProbeOptions& probe,
                                                       const GcodeOptions& options) {
  auto ir = BuildProbeArtifactsIr(plan, machine, probe, options);
  if (!ir.ok()) return ir.status();
  PostedProbeArtifacts out;
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

}  // namespace tpcal::gcode
