#include "gcode/datum_ball_program.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/units.h"
#include "gcode/internal/probe_moves.h"
#include "gcode/nc_format.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"

namespace tpcal::gcode {
namespace {

using internal::kProbeMaskX;
using internal::kProbeMaskXyz;
using internal::kProbeMaskY;
using internal::kProbeMaskZ;

Status BallOptionError(const std::string& what) { return {StatusCode::kInvalidArgument, "datum-ball probing: " + what}; }

// Rotary commands of `s` only (linear members zero).
kinematics::AxisState RotaryOf(const kinematics::AxisState& s) {
  kinematics::AxisState r;
  r.a_rad = s.a_rad, r.b_rad = s.b_rad, r.c_rad = s.c_rad;
  return r;
}

// Highest centring-command Z over the positions and the index sweeps between them (from the
// all-zero rotary state to the first position, then position to position), sampled every degree.
Result<double> HighestCentreZ(const kinematics::MachineModel& m, const kinematics::ErrorState& zero,
                              const testpieces::DatumBallPlan& plan) {
  double top = -1e300;
  kinematics::AxisState prev;
  for (const kinematics::AxisState& next : plan.positions) {
    const int n = std::max(1, static_cast<int>(std::ceil(internal::ProbeRotaryStepDeg(prev, next))));
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
  internal::SetProbingMachine(&prog, machine);
  prog.tools.push_back(
      internal::ProbeTool(probe.probe_tool_number, probe.stylus_diameter_mm, probe.probe_length_mm, options));

  const kinematics::ErrorState zero(machine);
  auto top = HighestCentreZ(machine, zero, plan);
  if (!top.ok()) return top.status();
  const double contact_mm = 0.5 * (plan.ball_diameter_mm + probe.stylus_diameter_mm);  // R + r
  prog.safe_z_mm = *top + contact_mm + probe.safe_clearance_mm;

  internal::ProbeIrBuilder b(&prog, {.probe_feed_mm_per_min = probe.probe_feed_mm_per_min,
                                     .rapid_mm_per_min = probe.rapid_mm_per_min,
                                     .index_deg_per_min = probe.index_deg_per_min});
  b.Preamble(options.work_offset, prog.safe_z_mm);

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
        b.Rapid(Eigen::Vector3d(start.x(), start.y(), 0.0), kProbeMaskX | kProbeMaskY, op);
      } else {
        b.Rapid(Eigen::Vector3d(start.x(), start.y(), above_z), kProbeMaskX | kProbeMaskY, op);
      }
      b.Rapid(start, kProbeMaskZ, op);
      b.Probe(*c + (contact_mm - probe.overtravel_mm) * d, *c + contact_mm * d, -d, static_cast<int>(t) + 1, op);
      b.Rapid(start, kProbeMaskXyz, op);
      b.Rapid(Eigen::Vector3d(0.0, 0.0, above_z), kProbeMaskZ, op);
    }
    b.Rapid(Eigen::Vector3d(0.0, 0.0, prog.safe_z_mm), kProbeMaskZ, op);
  }
  b.Simple(InstrKind::kProgramEnd, 0);
  return prog;
}

Result<PostedInstrumentProgram> PostDatumBallProgram(const testpieces::DatumBallPlan& plan,
                                                     const kinematics::MachineModel& machine,
                                                     const DatumBallProbeOptions& probe, const GcodeOptions& options) {
  auto ir = BuildDatumBallIr(plan, machine, probe, options);
  if (!ir.ok()) return ir.status();
  auto posted = internal::PostProbingIr(std::move(ir).value(), machine, options);
  if (!posted.ok()) return posted.status();
  return posted;
}

}  // namespace tpcal::gcode
