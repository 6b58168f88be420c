#include "gcode/ir.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::gcode {
namespace {

using kinematics::AxisState;
using testpieces::Move;
using testpieces::MoveKind;
using testpieces::Spindle;
using testpieces::SpindleMode;

constexpr double kSameLinear_mm = 1e-9;
constexpr double kSameRotary_rad = 1e-12;

bool SameSpindle(const Spindle& a, const Spindle& b) {
  return a.mode == b.mode && a.speed_rpm == b.speed_rpm && a.surface_speed_m_per_min == b.surface_speed_m_per_min &&
         a.max_speed_rpm == b.max_speed_rpm && a.clockwise == b.clockwise;
}

// Whether a running table spin serves the next pass unchanged: with constant surface speed the
// speed law and its radius axis, with constant rpm the rpm.
bool SameSpin(const TableSpin& a, const TableSpin& b, bool css_option) {
  const bool css_a = css_option && a.surface_speed_m_per_min > 0 && a.radius_axis_exact;
  const bool css_b = css_option && b.surface_speed_m_per_min > 0 && b.radius_axis_exact;
  if (css_a != css_b || a.positive_c != b.positive_c) return false;
  if (css_a) {
    return a.surface_speed_m_per_min == b.surface_speed_m_per_min && a.max_rpm == b.max_rpm &&
           a.radius_axis == b.radius_axis;
  }
  return a.rpm == b.rpm;
}

bool OnlyZChanges(const AxisState& a, const AxisState& b) {
  return std::abs(a.x_mm - b.x_mm) < kSameLinear_mm && std::abs(a.y_mm - b.y_mm) < kSameLinear_mm &&
         RotaryAxesEqual(a, b);
}

Eigen::Vector3d TipInPart(const kinematics::MachineModel& m, const AxisState& s) {
  return kinematics::NominalToolPointInPart(m, s, Eigen::Vector3d::Zero());
}

// Machine direction (unit) of the radial vector from the part Z (C) axis to the tool reference
// point, and the radius. The nominal map machine XYZ -> part is affine with an orthogonal linear
// part at fixed rotary axes, so J^T maps part directions back exactly.
struct Radial {
  Eigen::Vector3d machine_dir = Eigen::Vector3d::UnitX();
  double radius_mm = 0.0;
};
Radial RadialAt(const kinematics::MachineModel& m, const AxisState& s) {
  const Eigen::Vector3d p = TipInPart(m, s);
  Eigen::Matrix3d J;
  for (int i = 0; i < 3; ++i) {
    AxisState t = s;
    kinematics::SetPosition(&t, kinematics::AxisFromIndex(i), kinematics::Position(s, kinematics::AxisFromIndex(i)) + 1.0);
    J.col(i) = TipInPart(m, t) - p;
  }
  const Eigen::Vector3d r(p.x(), p.y(), 0.0);
  Radial out;
  out.radius_mm = r.norm();
  if (out.radius_mm > 0) out.machine_dir = (J.transpose() * r).normalized();
  return out;
}

class IrBuilder {
 public:
  IrBuilder(const testpieces::TestPiece& piece, const GcodeOptions& options, IrProgram* prog)
      : piece_(piece), options_(options), prog_(*prog) {}

  Status Build() {
    TPCAL_RETURN_IF_ERROR(CollectTools());
    const auto& ops = piece_.operations;
    if (ops.empty() || ops.front().passes.empty() || ops.front().passes.front().moves.empty()) {
      return {StatusCode::kInvalidArgument, "test piece '" + piece_.name + "' has no moves"};
    }
    state_ = ops.front().passes.front().moves.front().start;
    prog_.safe_z_mm = state_.z_mm;
    Instr wo = Make(InstrKind::kWorkOffset, 0);
    wo.work_offset = options_.work_offset;
    Push(wo);
    for (const testpieces::Operation& op : ops) {
      TPCAL_RETURN_IF_ERROR(Operation(op));
    }
    StopAll(static_cast<int>(ops.size()));
    Instr end = Make(InstrKind::kProgramEnd, static_cast<int>(ops.size()));
    Push(end);
    prog_.duration_s = testpieces::ProgramDuration(ops);
    return Status::Ok();
  }

 private:
  Instr Make(InstrKind kind, int op) const {
    Instr in;
    in.kind = kind;
    in.start = state_;
    in.end = state_;
    in.op = op;
    return in;
  }
  void Push(Instr in) { prog_.instrs.push_back(std::move(in)); }

  Status CollectTools() {
    std::map<int, int> by_piece;  // piece tool number -> index
    std::set<int> posted;
    for (const auto& op : piece_.operations) {
      if (by_piece.count(op.tool.number)) continue;
      IrTool t;
      t.tool = op.tool;
      t.number = options_.PostedToolNumber(op.tool.number);
      const ToolSetting* s = options_.FindTool(op.tool.number);
      t.length_mm = s && s->length_mm > 0 ? s->length_mm
                    : op.tool.gauge_length_mm > 0 ? op.tool.gauge_length_mm
                                                  : options_.default_tool_length_mm;
      if (!posted.insert(t.number).second) {
        return {StatusCode::kInvalidArgument, "tools: posted tool number T" + std::to_string(t.number) +
                                                  " is used by two different tools of the piece"};
      }
      by_piece[op.tool.number] = static_cast<int>(prog_.tools.size());
      prog_.tools.push_back(t);
    }
    for (const auto& s : options_.tools) {
      if (!by_piece.count(s.piece_tool)) {
        return {StatusCode::kInvalidArgument, "tools: piece tool " + std::to_string(s.piece_tool) +
                                                  " is not used by test piece '" + piece_.name + "'"};
      }
    }
    tool_index_ = by_piece;
    return Status::Ok();
  }

  // Stops the spindle / table spin / coolant that run (before a tool change or at the end).
  void StopAll(int op) {
    if (table_spinning_) StopSpin(op);
    if (spindle_on_) {
      Push(Make(InstrKind::kSpindleOff, op));
      spindle_on_ = false;
    }
    if (coolant_on_) {
      Push(Make(InstrKind::kCoolantOff, op));
      coolant_on_ = false;
    }
    has_spindle_ = false;
  }
  void StopSpin(int op) {
    Push(Make(InstrKind::kTableSpinStop, op));
    table_spinning_ = false;
  }
  void CoolantOn(int op) {
    if (!coolant_on_ && options_.coolant != Coolant::kOff) {
      Push(Make(InstrKind::kCoolantOn, op));
      coolant_on_ = true;
    }
  }

  TableSpin SpinFor(const testpieces::Pass& pass, int op) const {
    const Spindle& sp = pass.spindle;
    TableSpin t;
    t.surface_speed_m_per_min = sp.surface_speed_m_per_min;
    double clamp = sp.max_speed_rpm;
    if (options_.c_spindle.max_rpm > 0) clamp = clamp > 0 ? std::min(clamp, options_.c_spindle.max_rpm) : options_.c_spindle.max_rpm;
    t.max_rpm = clamp;
    t.positive_c = sp.clockwise;
    bool first = true;
    bool exact = true;
    for (const Move& m : pass.moves) {
      if (m.kind != MoveKind::kLinear || m.feed_mm_per_rev <= 0) continue;
      t.feed_mm_per_rev = m.feed_mm_per_rev;
      t.reference_radius_mm = std::max({t.reference_radius_mm, m.turn_radius_start_mm, m.turn_radius_end_mm});
      for (const AxisState* s : {&m.start, &m.end}) {
        const Radial r = RadialAt(piece_.machine, *s);
        int axis = 0;
        r.machine_dir.cwiseAbs().maxCoeff(&axis);
        if (first) {
          t.radius_axis = kinematics::AxisFromIndex(axis);
          first = false;
        }
        const double value = kinematics::Position(*s, t.radius_axis);
        if (kinematics::AxisIndex(t.radius_axis) != axis || std::abs(std::abs(r.machine_dir[axis]) - 1.0) > 1e-9 ||
            std::abs(std::abs(value) - r.radius_mm) > 1e-6) {
          exact = false;
        }
      }
    }
    t.radius_axis_exact = exact && !first;
    Spindle clamped = sp;
    clamped.max_speed_rpm = clamp;
    t.rpm = clamped.TableRpmAt(t.reference_radius_mm);
    (void)op;
    return t;
  }

  Status Operation(const testpieces::Operation& op) {
    Instr start = Make(InstrKind::kOperationStart, op.number);
    start.tool_index = tool_index_.at(op.tool.number);
    std::ostringstream os;
    os << "OP " << op.number << " " << op.name << ": " << op.description;
    start.text = os.str();
    Push(start);
    prog_.operation_names.push_back(op.name);
    for (std::size_t p = 0; p < op.passes.size(); ++p) {
      const testpieces::Pass& pass = op.passes[p];
      const bool turning = pass.spindle.mode == SpindleMode::kTableTurning;
      bool spindle_pending = !has_spindle_ || !SameSpindle(pass.spindle, spindle_);
      bool spin_checked = false;
      std::vector<Instr> pending_dwell;
      for (std::size_t k = 0; k < pass.moves.size(); ++k) {
        const Move& m = pass.moves[k];
        if (m.kind == MoveKind::kToolChange) {
          StopAll(op.number);
          Instr tc = Make(InstrKind::kToolChange, op.number);
          tc.tool_index = tool_index_.at(op.tool.number);
          tc.pass = static_cast<int>(p);
          tc.move = static_cast<int>(k);
          Push(tc);
          // After the change the machine stands at its tool-change position: go back to the
          // safe Z first, then to where the program was.
          Instr up = Make(InstrKind::kRapid, op.number);
          up.axis_mask = 1u << 2;
          Push(up);
          Instr back = Make(InstrKind::kRapid, op.number);
          Push(back);
          spindle_pending = true;
          continue;
        }
        if (m.kind == MoveKind::kDwell) {
          Instr d = Make(InstrKind::kDwell, op.number);
          d.dwell_s = m.duration_s;
          d.pass = static_cast<int>(p);
          d.move = static_cast<int>(k);
          d.duration_s = m.duration_s;
          if (spindle_pending || (turning && !table_spinning_)) {
            pending_dwell.push_back(d);  // after the spindle start
          } else {
            Push(d);
          }
          continue;
        }
        const bool index = m.kind == MoveKind::kRapid && LinearAxesEqual(m.start, m.end);
        if (index && table_spinning_) {
          StopSpin(op.number);
          spin_checked = false;
        }
        // Milling spindle: start before the first motion of the pass. Table spin: start before
        // the first motion that is not a rotary index (no indexing while the table spins).
        if (spindle_pending && !turning) {
          if (table_spinning_) StopSpin(op.number);
          Instr on = Make(InstrKind::kSpindleOn, op.number);
          on.spindle_rpm = pass.spindle.speed_rpm;
          on.spindle_clockwise = pass.spindle.clockwise;
          on.pass = static_cast<int>(p);
          Push(on);
          spindle_on_ = true;
          CoolantOn(op.number);
          for (auto& d : pending_dwell) Push(d);
          pending_dwell.clear();
          spindle_pending = false;
          spindle_ = pass.spindle;
          has_spindle_ = true;
        }
        if (turning && !index && !spin_checked) {
          // Start the table spin, or re-specify it when this pass needs another radius axis or
          // other speeds (the spin of the previous pass may still run).
          const TableSpin spin = SpinFor(pass, op.number);
          if (!table_spinning_ || !SameSpin(spin, active_spin_, options_.c_spindle.css)) {
            if (spindle_on_) {
              Push(Make(InstrKind::kSpindleOff, op.number));
              spindle_on_ = false;
            }
            Instr on = Make(InstrKind::kTableSpinStart, op.number);
            on.spin = spin;
            on.pass = static_cast<int>(p);
            Push(on);
            table_spinning_ = true;
            active_spin_ = spin;
            CoolantOn(op.number);
          }
          for (auto& d : pending_dwell) Push(d);
          pending_dwell.clear();
          spindle_pending = false;
          spindle_ = pass.spindle;
          has_spindle_ = true;
          spin_checked = true;
        }
        TPCAL_RETURN_IF_ERROR(AddMove(m, op.number, static_cast<int>(p), static_cast<int>(k)));
      }
      for (auto& d : pending_dwell) Push(d);
    }
    if (op.tool.kind == testpieces::ToolKind::kReamer) RecogniseCycles(op.number);
    return Status::Ok();
  }

  Status AddMove(const Move& m, int op, int pass, int k) {
    Instr in = Make(InstrKind::kRapid, op);
    in.start = m.start;
    in.end = m.end;
    in.pass = pass;
    in.move = k;
    in.duration_s = m.duration_s;
    in.cutting = m.cutting;
    switch (m.kind) {
      case MoveKind::kRapid:
        if (LinearAxesEqual(m.start, m.end) && RotaryAxesEqual(m.start, m.end)) return Status::Ok();  // no motion
        in.kind = LinearAxesEqual(m.start, m.end) ? InstrKind::kIndex : InstrKind::kRapid;
        if (in.kind == InstrKind::kIndex || !RotaryAxesEqual(m.start, m.end)) prog_.uses_rotary = true;
        break;
      case MoveKind::kLinear:
        in.kind = InstrKind::kLinear;
        if (m.feed_mm_per_rev > 0) {
          in.feed_mode = FeedMode::kPerRevolution;
          in.feed_mm_per_rev = m.feed_mm_per_rev;
          in.turn_radius_start_mm = m.turn_radius_start_mm;
          in.turn_radius_end_mm = m.turn_radius_end_mm;
          prog_.uses_table_turning = true;
        } else if (!RotaryAxesEqual(m.start, m.end)) {
          if (!(m.duration_s > 0)) {
            return {StatusCode::kInvalidArgument, "operation " + std::to_string(op) +
                                                      ": simultaneous rotary move without a duration"};
          }
          in.feed_mode = FeedMode::kInverseTime;
          in.feed_mm_per_min = m.feed_mm_per_min;
          in.tip_path_mm = (TipInPart(piece_.machine, m.end) - TipInPart(piece_.machine, m.start)).norm();
          prog_.uses_five_axis = true;
          prog_.uses_rotary = true;
        } else {
          in.feed_mode = FeedMode::kPerMinute;
          in.feed_mm_per_min = m.feed_mm_per_min;
        }
        if (LinearAxesEqual(m.start, m.end) && RotaryAxesEqual(m.start, m.end)) return Status::Ok();
        break;
      case MoveKind::kArc:
        in.kind = InstrKind::kArc;
        in.feed_mm_per_min = m.feed_mm_per_min;
        in.arc_center_xy_mm = m.arc_center_xy_mm;
        in.clockwise = m.clockwise;
        in.arc_angle_rad = m.arc_angle_rad;
        if (!RotaryAxesEqual(m.start, m.end) || std::abs(m.start.z_mm - m.end.z_mm) > kSameLinear_mm) {
          return {StatusCode::kInvalidArgument, "operation " + std::to_string(op) + ": arcs must be planar in XY"};
        }
        break;
      case MoveKind::kToolChange:
      case MoveKind::kDwell:
        return Status::Ok();
    }
    if (in.kind != InstrKind::kIndex && !RotaryAxesEqual(in.start, in.end)) prog_.uses_rotary = true;
    state_ = m.end;
    Push(in);
    return Status::Ok();
  }

  // Rapid down to R (Z only), feed to the bottom (Z only, cutting), feed back to R: a cycle.
  void RecogniseCycles(int op) {
    auto& v = prog_.instrs;
    std::vector<Instr> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i].op == op && i + 2 < v.size() && v[i].kind == InstrKind::kRapid && v[i].axis_mask == 0x3F &&
          v[i + 1].kind == InstrKind::kLinear && v[i + 2].kind == InstrKind::kLinear &&
          v[i + 1].feed_mode == FeedMode::kPerMinute && v[i + 2].feed_mode == FeedMode::kPerMinute &&
          OnlyZChanges(v[i].start, v[i].end) && OnlyZChanges(v[i + 1].start, v[i + 1].end) &&
          OnlyZChanges(v[i + 2].start, v[i + 2].end) && v[i].end.z_mm < v[i].start.z_mm &&
          v[i + 1].cutting && !v[i + 2].cutting && v[i + 1].end.z_mm < v[i].end.z_mm &&
          std::abs(v[i + 2].end.z_mm - v[i].end.z_mm) < kSameLinear_mm) {
        Instr c = v[i + 1];
        c.kind = InstrKind::kDrillCycle;
        c.start = v[i].start;
        c.end = v[i].start;  // G98: back at the initial level
        DrillCycle& d = c.drill;
        d.x_mm = v[i].end.x_mm;
        d.y_mm = v[i].end.y_mm;
        d.initial_z_mm = v[i].start.z_mm;
        d.r_z_mm = v[i].end.z_mm;
        d.bottom_z_mm = v[i + 1].end.z_mm;
        d.surface_z_mm = SurfaceZ(v[i + 1]);
        d.feed_mm_per_min = v[i + 1].feed_mm_per_min;
        d.retract_feed_mm_per_min = v[i + 2].feed_mm_per_min;
        d.dwell_s = 0.0;
        c.duration_s = v[i].duration_s + v[i + 1].duration_s + v[i + 2].duration_s;
        // The next rapid straight back up to the initial level is the cycle's own G98 return.
        std::size_t next = i + 3;
        if (next < v.size() && v[next].kind == InstrKind::kRapid && v[next].axis_mask == 0x3F &&
            OnlyZChanges(v[next].start, v[next].end) && std::abs(v[next].end.z_mm - d.initial_z_mm) < kSameLinear_mm) {
          d.return_to_initial = true;
          c.duration_s += v[next].duration_s;
          ++next;
        } else {
          d.return_to_initial = false;
          c.end = v[i].end;
        }
        out.push_back(c);
        i = next - 1;
        continue;
      }
      out.push_back(v[i]);
    }
    v = std::move(out);
  }

  // Machine Z of the hole entry surface of the plunge cut made by `cut_move`.
  double SurfaceZ(const Instr& cut_move) const {
    for (const auto& fc : piece_.cuts) {
      const auto* pc = std::get_if<testpieces::PlungeCut>(&fc.model);
      if (!pc || pc->ref.op != cut_move.op || pc->ref.pass != cut_move.pass || pc->ref.move != cut_move.move) continue;
      const Eigen::Vector3d tip = TipInPart(piece_.machine, cut_move.start);
      const Eigen::Vector3d axis = kinematics::NominalToolAxisInPart(piece_.machine, cut_move.start);
      return cut_move.start.z_mm - (tip - pc->entry_mm).dot(axis);
    }
    return cut_move.start.z_mm;  // no plunge cut recorded: the R plane
  }

  const testpieces::TestPiece& piece_;
  const GcodeOptions& options_;
  IrProgram& prog_;
  std::map<int, int> tool_index_;
  AxisState state_;
  Spindle spindle_;
  bool has_spindle_ = false;
  bool spindle_on_ = false;
  bool table_spinning_ = false;
  TableSpin active_spin_;
  bool coolant_on_ = false;
};

}  // namespace

const char* InstrKindName(InstrKind k) {
  switch (k) {
    case InstrKind::kOperationStart: return "operation_start";
    case InstrKind::kWorkOffset: return "work_offset";
    case InstrKind::kToolChange: return "tool_change";
    case InstrKind::kSpindleOn: return "spindle_on";
    case InstrKind::kSpindleOff: return "spindle_off";
    case InstrKind::kCoolantOn: return "coolant_on";
    case InstrKind::kCoolantOff: return "coolant_off";
    case InstrKind::kRapid: return "rapid";
    case InstrKind::kIndex: return "index";
    case InstrKind::kLinear: return "linear";
    case InstrKind::kArc: return "arc";
    case InstrKind::kDrillCycle: return "drill_cycle";
    case InstrKind::kTableSpinStart: return "table_spin_start";
    case InstrKind::kTableSpinStop: return "table_spin_stop";
    case InstrKind::kDwell: return "dwell";
    case InstrKind::kProbe: return "probe";
    case InstrKind::kProgramStop: return "program_stop";
    case InstrKind::kProgramEnd: return "program_end";
  }
  return "?";
}

bool LinearAxesEqual(const AxisState& a, const AxisState& b) {
  return std::abs(a.x_mm - b.x_mm) < kSameLinear_mm && std::abs(a.y_mm - b.y_mm) < kSameLinear_mm &&
         std::abs(a.z_mm - b.z_mm) < kSameLinear_mm;
}

bool RotaryAxesEqual(const AxisState& a, const AxisState& b) {
  return std::abs(a.a_rad - b.a_rad) < kSameRotary_rad && std::abs(a.b_rad - b.b_rad) < kSameRotary_rad &&
         std::abs(a.c_rad - b.c_rad) < kSameRotary_rad;
}

std::string StandardClause(testpieces::PieceKind kind) {
  switch (kind) {
    case testpieces::PieceKind::kTurning:
      return "Ibaraki, Yoshida, Asano (seed 002): sec. 2.1 machining procedure, sec. 4.1 and Table 3 conditions";
    case testpieces::PieceKind::kContourM1:
      return "ISO 10791-7:2020 test piece M1 (contouring), dimensions per testpieces/README.md";
    case testpieces::PieceKind::kFaceMillingM2:
      return "ISO 10791-7:2020 test piece M2 (face milling), dimensions per testpieces/README.md";
    case testpieces::PieceKind::kConeFrustum:
      return "ISO 10791-7:2020 / NAS 979 cone frustum, simultaneous five-axis flank milling";
  }
  return "?";
}

Result<IrProgram> BuildIr(const testpieces::TestPiece& piece, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  IrProgram prog;
  prog.piece_name = piece.name;
  prog.kind = piece.kind();
  prog.standard = StandardClause(piece.kind());
  prog.machine_name = piece.machine.name.empty() ? kinematics::MachineTypeName(piece.machine.type) : piece.machine.name;
  prog.machine = piece.machine;
  prog.has_a = piece.machine.HasAxis(kinematics::Axis::kA);
  prog.has_b = piece.machine.HasAxis(kinematics::Axis::kB);
  prog.has_c = piece.machine.HasAxis(kinematics::Axis::kC);
  IrBuilder b(piece, options, &prog);
  TPCAL_RETURN_IF_ERROR(b.Build());
  return prog;
}

}  // namespace tpcal::gcode
