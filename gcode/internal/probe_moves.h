// Shared machinery of the measuring programs (not public API): the datum-ball program
// (gcode/datum_ball_program.h) and the probe-artifacts program (gcode/probe_artifacts_program.h),
// which probe with a spindle touch probe, and the ball-bar program (gcode/ballbar_program.h). The IR builder of their moves (rapids by axis mask, rotary
// indexes, probe moves, with the time estimate), the probe tool, the machine fields of the
// program, and the post-and-check step (post, strokes, dialect whitelist, LinuxCNC tool table).
// Implemented in gcode/probe_moves.cc (the library compiles gcode/*.cc only).
#pragma once

#include <string>
#include <utility>

#include <Eigen/Core>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/posted_instrument_program.h"
#include "kinematics/machine_model.h"

namespace tpcal::gcode::internal {

// Instr::axis_mask bits.
constexpr unsigned kProbeMaskX = 0x1, kProbeMaskY = 0x2, kProbeMaskZ = 0x4, kProbeMaskXyz = 0x7,
                   kProbeMaskRotary = 0x38;

// Largest rotary step from `a` to `b` (deg, over A, B, C).
double ProbeRotaryStepDeg(const kinematics::AxisState& a, const kinematics::AxisState& b);

// Rates of the time estimate (header line) and the probe feed of the probe moves.
struct ProbeMoveRates {
  double probe_feed_mm_per_min = 0.0;
  double rapid_mm_per_min = 0.0;
  double index_deg_per_min = 0.0;
};

// Appends instructions to `prog`, tracking where the axes are (all zero at the start) and the
// time estimate (prog->duration_s).
class ProbeIrBuilder {
 public:
  ProbeIrBuilder(IrProgram* prog, const ProbeMoveRates& rates) : prog_(prog), rates_(rates) {}

  // Any instruction: start = the current axes; a probe move's end takes X Y Z from `in.end`, a
  // rapid's or index's the axes in its axis_mask (the others stay); a linear or arc move's end is
  // `in.end` as given, its duration_s the caller's.
  void Add(Instr in);
  void Simple(InstrKind kind, int op);
  // Work offset, tool change of tool 0, rapid Z alone to `safe_z_mm` (op 0).
  void Preamble(int work_offset, double safe_z_mm);
  // Rapid of the axes in `mask` to `target` (the others stay).
  void Rapid(const Eigen::Vector3d& target_mm, unsigned mask, int op);
  // Rotary-only index to the A, B, C of `rotary`.
  void Index(const kinematics::AxisState& rotary, int op);
  // Probe move from the current point to `target_mm` along `direction` (unit); `contact_mm` is
  // the tool reference point at the nominal contact; `result` the touch number (ProbeMove).
  void Probe(const Eigen::Vector3d& target_mm, const Eigen::Vector3d& contact_mm, const Eigen::Vector3d& direction,
             int result, int op);

  const kinematics::AxisState& current() const { return cur_; }

 private:
  IrProgram* prog_;
  ProbeMoveRates rates_;
  kinematics::AxisState cur_;
};

// The machine fields of a probing program: machine_name (the model's name, or its type's),
// machine, has_a / has_b / has_c, uses_rotary = true.
void SetProbingMachine(IrProgram* prog, const kinematics::MachineModel& machine);

// The touch probe as the program's tool: "touch probe, stylus ball D<d>", ToolKind::kTouchProbe,
// posted as T`number` with gauge length `length_mm` (0: options.default_tool_length_mm).
IrTool ProbeTool(int number, double stylus_diameter_mm, double length_mm, const GcodeOptions& options);

// Posts `ir` in options.dialect, checks every rapid / index / probe / linear / arc target (arcs
// also every 5 deg along the way) against the machine's strokes (options.safety.check_strokes; the error names the block and the program file) and the
// dialect whitelist (gcode/dialect_check.h); LinuxCNC: the tool table. Errors: those of PostIr,
// the checks.
Result<PostedInstrumentProgram> PostProbingIr(IrProgram ir, const kinematics::MachineModel& machine,
                                              const GcodeOptions& options);

}  // namespace tpcal::gcode::internal
