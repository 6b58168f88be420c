#include "gcode/probe_artifacts_program.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"
#include "gcode/internal/probe_moves.h"
#include "gcode/nc_format.h"

namespace tpcal::gcode {
namespace {

// Unity builds merge this file with datum_ball_program.cc: every file-local name is prefixed.
constexpr std::size_t kArtCommentMaxChars = 200;  // pose comment, before the dialect's delimiters

Status ArtifactProgramError(const std::string& what) {
  return {StatusCode::kInvalidArgument, "probe-artifacts probing: " + what};
}

bool ArtifactSamePose(const kinematics::AxisState& a, const kinematics::AxisState& b) {
  return a.a_rad == b.a_rad && a.b_rad == b.b_rad && a.c_rad == b.c_rad;
}

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
    const int n = std::max(1, static_cast<int>(std::ceil(internal::ProbeRotaryStepDeg(prev, next))));
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
  std::size_t grouped = 0;
  for (const auto& touches : by_pose) grouped += touches.size();
  if (grouped != plan.touches.size())
    return ArtifactProgramError(std::to_string(plan.touches.size() - grouped) +
                                " touches at a rotary position that is not one of the plan's poses");

  IrProgram prog;
  prog.piece_name = "probe artifacts";
  prog.instrument = "probe artifacts, " + std::to_string(plan.artifacts.boxes.size()) + " boxes, " +
                    std::to_string(plan.poses.size()) + " rotary poses, " + std::to_string(plan.touches.size()) +
                    " touches (" + std::to_string(plan.skipped.size()) + " skipped)";
  prog.standard = "seed 000 on-machine probing of artifacts: one touch per reachable face centre at each "
                  "indexed A/C pose";
  internal::SetProbingMachine(&prog, machine);
  prog.tools.push_back(internal::ProbeTool(probe.probe_tool_number, 2.0 * r, probe.probe_length_mm, options));

  double top = ArtifactHighestCornerZ(machine, plan.artifacts, indexed) + r;
  for (const testpieces::PlannedTouch& t : plan.touches)
    top = std::max(top, (t.contact_mm - (r + probe.approach_mm) * t.approach).z());
  prog.safe_z_mm = top + probe.safe_clearance_mm;

  internal::ProbeIrBuilder b(&prog, {.probe_feed_mm_per_min = probe.probe_feed_mm_per_min,
                                     .rapid_mm_per_min = probe.rapid_mm_per_min,
                                     .index_deg_per_min = probe.index_deg_per_min});
  b.Preamble(options.work_offset, prog.safe_z_mm);

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
      b.Rapid(Eigen::Vector3d(start.x(), start.y(), 0.0), internal::kProbeMaskX | internal::kProbeMaskY, op);
      b.Rapid(start, internal::kProbeMaskZ, op);
      b.Probe(t.contact_mm + (r - probe.overtravel_mm) * n, t.contact_mm + r * n, t.approach, static_cast<int>(k) + 1, op);
      b.Rapid(start, internal::kProbeMaskXyz, op);
      b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), internal::kProbeMaskZ, op);
    }
  }
  b.Simple(InstrKind::kProgramEnd, 0);
  return prog;
}

Result<PostedInstrumentProgram> PostProbeArtifactsProgram(const testpieces::ProbeArtifactsPlan& plan,
                                                          const kinematics::MachineModel& machine,
                                                          const ProbeArtifactsProbeOptions& probe,
                                                          const GcodeOptions& options) {
  auto ir = BuildProbeArtifactsIr(plan, machine, probe, options);
  if (!ir.ok()) return ir.status();
  auto posted = internal::PostProbingIr(std::move(ir).value(), machine, options);
  if (!posted.ok()) return posted.status();
  return posted;
}

}  // namespace tpcal::gcode
