// MachineModel: the constant description of a machine's kinematic chain (STYLE habit 8, the
// "Model" of Model/Data). Built from YAML (kinematics/machine_yaml.h) or MakeMachine(). Frames,
// signs and the chain formula: kinematics/conventions.h.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"

namespace tpcal::kinematics {

enum class MachineType {
  kAcTable,      // A swivel about X carrying a C table (seeds 000, 002)
  kBcTable,      // B tilt about Y carrying a C table (seed 001)
  kBheadCtable,  // B swinging head on the tool side, C turntable on the bed (seed 003)
  kXyz,          // 3-axis vertical machining centre (seed 004)
};
const char* MachineTypeName(MachineType t);  // "ac_table", "bc_table", "bhead_ctable", "xyz"
std::optional<MachineType> MachineTypeFromName(std::string_view name);

enum class Branch { kWorkpiece, kTool };

// One axis link of a branch (see the chain formula in conventions.h).
struct AxisLink {
  Axis axis = Axis::kX;
  Branch branch = Branch::kTool;
  // Nominal pivot, mm, in the parent frame at home: a point of the nominal axis line (rotary), or
  // the reference point of the angular error motions (linear). Default: MCS origin.
  Eigen::Vector3d pivot_mm = Eigen::Vector3d::Zero();
  // Stroke, mm or rad. Ignored for a continuous rotary axis.
  double min_position = -1e9;
  double max_position = 1e9;
  bool continuous = false;  // rotary axis without stroke limits (C tables)

  // +1 on the tool branch, -1 on the workpiece branch (ISO 841, conventions.h).
  double motion_sign() const { return branch == Branch::kTool ? 1.0 : -1.0; }
};

struct MachineModel {
  std::string name;  // free text, e.g. "seed 002 A/C swiveling table"
  MachineType type = MachineType::kXyz;
  // All links: first the workpiece branch (bed -> ... -> part), then the tool branch
  // (bed -> ... -> tool), each in chain order. Each axis of the machine appears exactly once.
  std::vector<AxisLink> links;
  int num_workpiece_links = 0;  // links[0, n) are the workpiece branch

  int num_links() const { return static_cast<int>(links.size()); }
  // Index into `links` of an axis, or -1 if the machine has no such axis.
  int LinkIndex(Axis a) const;
  bool HasAxis(Axis a) const { return LinkIndex(a) >= 0; }
  // The rotary axis carrying `a` on the same branch (C on A: A), if any.
  std::optional<Axis> ParentRotary(Axis a) const;

  // Checks the chain for this type: required axes present once, rotary axes on the right branch
  // and in the right order (ac_table: workpiece ..A..C; bc_table: ..B..C; bhead_ctable: C on the
  // workpiece branch, B last on the tool branch; xyz: no rotary axis), strokes ordered.
  Status Validate() const;
};

// Chain layout options for MakeMachine. Empty chains take the type's default.
struct MachineLayout {
  std::vector<Axis> workpiece_chain;  // default: ac_table [A, C]; bc_table [B, C]; bhead_ctable [C]; xyz []
  std::vector<Axis> tool_chain;       // default: [X, Y, Z] (+ B last for bhead_ctable)
};

// A machine of `type` with all pivots at the MCS origin (bhead_ctable: B pivot at
// (0, 0, b_pivot_length_mm) above the tool tip), unlimited strokes and `layout`.
Result<MachineModel> MakeMachine(MachineType type, const MachineLayout& layout = {},
                                 double b_pivot_length_mm = 300.0);

// Stroke check: kInvalidArgument naming the first axis outside its stroke.
Status CheckStrokes(const MachineModel& model, const AxisState& axes);

}  // namespace tpcal::kinematics
