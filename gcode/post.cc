#include "gcode/post.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/units.h"
#include "gcode/internal/post_base.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::gcode {
namespace internal {

namespace {
constexpr int kMaxBlockNumber = 99999;  // Fanuc N5 (and LinuxCNC); Heidenhain numbers lines
}

PostBase::PostBase(const IrProgram& prog, const GcodeOptions& options, NumberStyle style)
    : prog_(prog), o_(options), style_(style) {
  next_n_ = options.block_start;
  out_.instr_labels.resize(prog.instrs.size());
}

Result<PostedText> PostBase::Run() {
  Begin();
  for (index_ = 0; index_ < prog_.instrs.size(); ++index_) {
    Emit(prog_.instrs[index_]);
    if (!error_.ok()) return error_;
  }
  index_ = prog_.instrs.size();
  End();
  if (!error_.ok()) return error_;
  return std::move(out_);
}

std::string PostBase::Numbered(int n, const std::string& body) const {
  return "N" + std::to_string(n) + " " + body;
}

std::string PostBase::Block(const std::string& body) {
  std::string label;
  if (NumbersEveryLine()) {
    label = std::to_string(line_);
    out_.text += Numbered(line_, body) + "\n";
    ++line_;
  } else if (o_.block_step > 0) {
    if (next_n_ > kMaxBlockNumber) {
      Fail({StatusCode::kInvalidArgument, "block numbers exceed N" + std::to_string(kMaxBlockNumber) +
                                              ": lower block_start / block_step"});
    }
    label = "N" + std::to_string(next_n_);
    out_.text += Numbered(next_n_, body) + "\n";
    next_n_ += o_.block_step;
  } else {
    out_.text += body + "\n";
  }
  ++out_.block_count;
  if (index_ < out_.instr_labels.size() && !label.empty()) out_.instr_labels[index_].push_back(label);
  return label;
}

void PostBase::Plain(const std::string& line) {
  if (NumbersEveryLine()) {
    out_.text += Numbered(line_, line) + "\n";
    ++line_;
  } else {
    out_.text += line + "\n";
  }
}

std::string PostBase::Deg(double rad) const { return FormatNumber(RadToDeg(rad), o_.rotary_decimals, style_); }

std::string PostBase::Rpm(double rpm) const {
  return FormatNumber(std::round(rpm), 0, NumberStyle::kPlain);  // whole rpm, no point (Fanuc S, T)
}

std::array<double, 6> PostBase::ProgramValues(const kinematics::AxisState& s) const {
  std::array<double, 6> v = {s.x_mm, s.y_mm, s.z_mm, RadToDeg(s.a_rad), RadToDeg(s.b_rad), RadToDeg(s.c_rad)};
  if (tcp_) {
    const Eigen::Vector3d tip = kinematics::NominalToolPointInPart(prog_.machine, s, Eigen::Vector3d::Zero());
    v[0] = tip.x();
    v[1] = tip.y();
    v[2] = tip.z();
  }
  v[0] *= x_scale_;
  return v;
}

std::string PostBase::AxisWord(int axis, double value) const {
  static const char kLetters[] = "XYZABC";
  const int decimals = axis < 3 ? o_.linear_decimals : o_.rotary_decimals;
  return std::string(1, kLetters[axis]) + FormatNumber(value, decimals, style_);
}

std::string PostBase::AxisWords(const kinematics::AxisState& s, unsigned mask, bool force) {
  const std::array<double, 6> v = ProgramValues(s);
  const bool has[6] = {true, true, true, prog_.has_a, prog_.has_b, prog_.has_c};
  std::string words;
  for (int i = 0; i < 6; ++i) {
    if (!(mask & (1u << i)) || !has[i]) continue;
    const std::string w = AxisWord(i, v[i]);
    if (force || !known_[i] || w != last_[i]) {
      if (!words.empty()) words += ' ';
      words += w;
      last_[i] = w;
      known_[i] = true;
    }
  }
  return words;
}

void PostBase::ForgetAxes(unsigned mask) {
  for (int i = 0; i < 6; ++i) {
    if (mask & (1u << i)) known_[i] = false;
  }
}

std::string PostBase::FeedWord(const std::string& letter, double value, int decimals, bool force) {
  const std::string w = letter + FormatNumber(value, decimals, style_ == NumberStyle::kSigned ? NumberStyle::kPlain : style_);
  if (!force && w == last_feed_) return "";
  last_feed_ = w;
  return w;
}

double PostBase::SpinRpmAt(const TableSpin& spin, double radius_mm) const {
  if (!(spin.surface_speed_m_per_min > 0) || !o_.c_spindle.css) return spin.rpm;
  double n = spin.surface_speed_m_per_min * 1000.0 / (2.0 * kPi * std::max(radius_mm, 1e-9));
  if (spin.max_rpm > 0) n = std::min(n, spin.max_rpm);
  return n;
}

bool PostBase::InFiveAxisPass(std::size_t index) const {
  const Instr& in = prog_.instrs[index];
  if (in.pass < 0) return false;
  for (const Instr& other : prog_.instrs) {
    if (other.op == in.op && other.pass == in.pass && other.feed_mode == FeedMode::kInverseTime &&
        other.kind == InstrKind::kLinear) {
      return true;
    }
  }
  return false;
}

double PostBase::NextSpindleRpm(std::size_t index) const {
  for (std::size_t i = index; i < prog_.instrs.size(); ++i) {
    if (prog_.instrs[i].kind == InstrKind::kSpindleOn) return prog_.instrs[i].spindle_rpm;
    if (prog_.instrs[i].kind == InstrKind::kTableSpinStart || prog_.instrs[i].kind == InstrKind::kToolChange) {
      if (i != index) return 0.0;
    }
  }
  return 0.0;
}

}  // namespace internal

std::vector<std::string> HeaderLines(const IrProgram& prog, const GcodeOptions& o) {
  std::vector<std::string> h;
  auto num = [](double v, int d) { return FormatNumber(v, d); };
  h.push_back("TPCAL NC PROGRAM " + o.program_name);
  if (prog.instrument.empty()) {
    h.push_back("TEST PIECE: " + prog.piece_name + " [" + testpieces::PieceKindName(prog.kind) + "]");
  } else {
    h.push_back("INSTRUMENT: " + prog.instrument);
  }
  h.push_back("STANDARD: " + prog.standard);
  h.push_back("MACHINE: " + prog.machine_name + " [" + kinematics::MachineTypeName(prog.machine.type) + "]");
  h.push_back(std::string("CONTROL: ") + DialectTitle(o.dialect));
  h.push_back("UNITS: MM; FEED MM/MIN, TURNING FEED MM/REV, CUTTING SPEED M/MIN; ANGLES DEG; TIME S");
  const char* origin = prog.machine.type == kinematics::MachineType::kXyz
                           ? "part frame origin of the test piece"
                       : prog.has_b ? "nominal intersection of the rotary axes [MCS origin, part frame at B=C=0]"
                                    : "nominal intersection of the rotary axes [MCS origin, part frame at A=C=0]";
  h.push_back("WORK OFFSET " + std::to_string(o.work_offset) + ": " + origin);
  h.push_back("DATE: " + (o.date.empty() ? std::string("not recorded") : o.date));
  h.push_back("GENERATED BY: " + o.generator);
  h.push_back("PROGRAM TIME ESTIMATE S: " + num(prog.duration_s, 0));
  h.push_back("TOOLS:");
  for (const IrTool& t : prog.tools) {
    std::ostringstream os;
    os << "T" << t.number << " " << t.tool.name << ": " << testpieces::ToolKindName(t.tool.kind);
    if (t.tool.kind == testpieces::ToolKind::kTouchProbe) {
      os << ", STYLUS BALL D " << num(t.tool.diameter_mm, 3);
    } else if (t.tool.kind == testpieces::ToolKind::kTurningInsert) {
      os << ", NOSE R " << num(t.tool.corner_radius_mm, 3) << ", " << num(t.tool.included_angle_deg, 1) << " DEG";
    } else {
      os << ", D " << num(t.tool.diameter_mm, 3);
      if (t.tool.corner_radius_mm > 0) os << ", CORNER R " << num(t.tool.corner_radius_mm, 3);
      os << ", " << t.tool.teeth << " TEETH";
    }
    os << ", LENGTH " << num(t.length_mm, 3);
    if (!t.tool.material.empty()) os << ", " << t.tool.material;
    h.push_back(os.str());
  }
  if (prog.uses_table_turning) {
    std::ostringstream os;
    os << "C TABLE AS TURNING SPINDLE: " << (o.c_spindle.css ? "constant surface speed" : "constant rpm")
       << ", tool spindle oriented M" << o.c_spindle.orient_mcode << " at " << num(o.c_spindle.orient_angle_deg, 3)
       << " DEG, +C = M" << o.c_spindle.positive_c_mcode;
    if (o.c_spindle.mode_on_mcode >= 0) {
      os << ", C spindle mode M" << o.c_spindle.mode_on_mcode << " / M" << o.c_spindle.mode_off_mcode;
    }
    h.push_back(os.str());
  }
  if (prog.uses_five_axis) h.push_back(std::string("FIVE-AXIS MODE: ") + FiveAxisModeName(o.five_axis));
  return h;
}

std::string LabelOf(const PostedText& posted, int instr_index) {
  for (int i = std::min<int>(instr_index, static_cast<int>(posted.instr_labels.size()) - 1); i >= 0; --i) {
    if (!posted.instr_labels[i].empty()) return posted.instr_labels[i].front();
  }
  return "";
}

Result<PostedText> PostIr(const IrProgram& prog, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  std::unique_ptr<internal::PostBase> post;
  switch (options.dialect) {
    case Dialect::kFanuc: post = internal::MakeFanucPost(prog, options); break;
    case Dialect::kLinuxCnc: post = internal::MakeLinuxCncPost(prog, options); break;
    case Dialect::kSinumerik: post = internal::MakeSinumerikPost(prog, options); break;
    case Dialect::kHeidenhain: post = internal::MakeHeidenhainPost(prog, options); break;
  }
  return post->Run();
}

}  // namespace tpcal::gcode
