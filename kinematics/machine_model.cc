#include "kinematics/machine_model.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/units.h"

namespace tpcal::kinematics {

const char* MachineTypeName(MachineType t) {
  switch (t) {
    case MachineType::kAcTable: return "ac_table";
    case MachineType::kBcTable: return "bc_table";
    case MachineType::kBheadCtable: return "bhead_ctable";
    case MachineType::kXyz: return "xyz";
  }
  return "?";
}

std::optional<MachineType> MachineTypeFromName(std::string_view name) {
  for (MachineType t : {MachineType::kAcTable, MachineType::kBcTable, MachineType::kBheadCtable,
                        MachineType::kXyz}) {
    if (name == MachineTypeName(t)) return t;
  }
  return std::nullopt;
}

int MachineModel::LinkIndex(Axis a) const {
  for (int i = 0; i < num_links(); ++i) {
    if (links[i].axis == a) return i;
  }
  return -1;
}

std::optional<Axis> MachineModel::ParentRotary(Axis a) const {
  const int i = LinkIndex(a);
  if (i < 0) return std::nullopt;
  const int begin = links[i].branch == Branch::kWorkpiece ? 0 : num_workpiece_links;
  for (int j = i - 1; j >= begin; --j) {
    if (IsRotary(links[j].axis)) return links[j].axis;
  }
  return std::nullopt;
}

namespace {

std::vector<Axis> BranchAxes(const MachineModel& m, Branch b) {
  std::vector<Axis> out;
  for (const AxisLink& l : m.links) {
    if (l.branch == b) out.push_back(l.axis);
  }
  return out;
}

std::vector<Axis> Rotaries(const std::vector<Axis>& axes) {
  std::vector<Axis> out;
  for (Axis a : axes) {
    if (IsRotary(a)) out.push_back(a);
  }
  return out;
}

std::string AxesString(const std::vector<Axis>& axes) {
  std::string s = "[";
  for (size_t i = 0; i < axes.size(); ++i) {
    if (i) s += ", ";
    s += AxisLetter(axes[i]);
  }
  return s + "]";
}

}  // namespace

Status MachineModel::Validate() const {
  const std::string type_name = MachineTypeName(type);
  if (num_workpiece_links < 0 || num_workpiece_links > num_links()) {
    return Status(StatusCode::kInvalidArgument, "machine model: bad workpiece branch size");
  }
  int count[kNumAxes] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < num_links(); ++i) {
    const AxisLink& l = links[i];
    const Branch expected = i < num_workpiece_links ? Branch::kWorkpiece : Branch::kTool;
    if (l.branch != expected) {
      return Status(StatusCode::kInvalidArgument,
                    "machine model: links must list the workpiece branch first, then the tool branch");
    }
    ++count[AxisIndex(l.axis)];
    if (!l.pivot_mm.allFinite()) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("axis ") + AxisLetter(l.axis) + ": pivot is not finite");
    }
    if (!(l.min_position <= l.max_position)) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("axis ") + AxisLetter(l.axis) + ": stroke minimum exceeds maximum");
    }
    if (l.continuous && !IsRotary(l.axis)) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("axis ") + AxisLetter(l.axis) + ": only rotary axes can be continuous");
    }
  }
  for (int a = 0; a < kNumAxes; ++a) {
    if (count[a] > 1) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("machine model: axis ") + AxisLetter(AxisFromIndex(a)) +
                        " appears more than once");
    }
  }
  for (Axis a : {Axis::kX, Axis::kY, Axis::kZ}) {
    if (count[AxisIndex(a)] != 1) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("machine model: linear axis ") + AxisLetter(a) + " is missing");
    }
  }
  // Rotary axes come after the linear axes of their branch.
  for (Branch b : {Branch::kWorkpiece, Branch::kTool}) {
    const std::vector<Axis> axes = BranchAxes(*this, b);
    bool seen_rotary = false;
    for (Axis a : axes) {
      if (IsRotary(a)) seen_rotary = true;
      if (!IsRotary(a) && seen_rotary) {
        return Status(StatusCode::kInvalidArgument,
                      std::string("machine model: linear axis ") + AxisLetter(a) +
                          " is carried by a rotary axis; put linear axes first in " +
                          (b == Branch::kWorkpiece ? "workpiece_chain " : "tool_chain ") +
                          AxesString(axes));
      }
    }
  }
  const std::vector<Axis> wr = Rotaries(BranchAxes(*this, Branch::kWorkpiece));
  const std::vector<Axis> tr = Rotaries(BranchAxes(*this, Branch::kTool));
  std::vector<Axis> want_w, want_t;
  switch (type) {
    case MachineType::kAcTable: want_w = {Axis::kA, Axis::kC}; break;
    case MachineType::kBcTable: want_w = {Axis::kB, Axis::kC}; break;
    case MachineType::kBheadCtable:
      want_w = {Axis::kC};
      want_t = {Axis::kB};
      break;
    case MachineType::kXyz: break;
  }
  if (wr != want_w || tr != want_t) {
    return Status(StatusCode::kInvalidArgument,
                  "machine type " + type_name + " needs rotary axes " + AxesString(want_w) +
                      " on the workpiece branch and " + AxesString(want_t) +
                      " on the tool branch, got " + AxesString(wr) + " and " + AxesString(tr));
  }
  return Status::Ok();
}

Result<MachineModel> MakeMachine(MachineType type, const MachineLayout& layout,
                                 double b_pivot_length_mm) {
  std::vector<Axis> w = layout.workpiece_chain, t = layout.tool_chain;
  if (w.empty() && t.empty()) {
    switch (type) {
      case MachineType::kAcTable: w = {Axis::kA, Axis::kC}; break;
      case MachineType::kBcTable: w = {Axis::kB, Axis::kC}; break;
      case MachineType::kBheadCtable: w = {Axis::kC}; break;
      case MachineType::kXyz: break;
    }
    t = {Axis::kX, Axis::kY, Axis::kZ};
    if (type == MachineType::kBheadCtable) t.push_back(Axis::kB);
  }
  MachineModel m;
  m.type = type;
  m.name = MachineTypeName(type);
  for (Axis a : w) {
    AxisLink l;
    l.axis = a;
    l.branch = Branch::kWorkpiece;
    l.continuous = a == Axis::kC;
    m.links.push_back(l);
  }
  m.num_workpiece_links = static_cast<int>(w.size());
  for (Axis a : t) {
    AxisLink l;
    l.axis = a;
    l.branch = Branch::kTool;
    if (a == Axis::kB && type == MachineType::kBheadCtable) {
      l.pivot_mm = Eigen::Vector3d(0.0, 0.0, b_pivot_length_mm);
    }
    m.links.push_back(l);
  }
  TPCAL_RETURN_IF_ERROR(m.Validate());
  return m;
}

Status CheckStrokes(const MachineModel& model, const AxisState& axes) {
  for (const AxisLink& l : model.links) {
    if (l.continuous) continue;
    const double q = Position(axes, l.axis);
    if (q < l.min_position || q > l.max_position) {
      const bool rot = IsRotary(l.axis);
      const double k = rot ? 180.0 / kPi : 1.0;
      const char* unit = rot ? "deg" : "mm";
      char buf[200];
      std::snprintf(buf, sizeof(buf), "axis %c at %.4f %s is outside its stroke [%.4f, %.4f] %s",
                    AxisLetter(l.axis), q * k, unit, l.min_position * k, l.max_position * k, unit);
      return Status(StatusCode::kInvalidArgument, buf);
    }
  }
  return Status::Ok();
}

}  // namespace tpcal::kinematics
