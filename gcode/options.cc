#include "gcode/options.h"

#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

namespace tpcal::gcode {
namespace {

Status BadOption(const std::string& key, const std::string& why) {
  return {StatusCode::kInvalidArgument, key + ": " + why};
}

bool ValidMcode(int m) { return m >= 0 && m <= 999; }

}  // namespace

const char* DialectName(Dialect d) {
  switch (d) {
    case Dialect::kFanuc: return "fanuc";
    case Dialect::kLinuxCnc: return "linuxcnc";
    case Dialect::kSinumerik: return "sinumerik";
    case Dialect::kHeidenhain: return "heidenhain";
  }
  return "?";
}

std::optional<Dialect> DialectFromName(std::string_view name) {
  for (Dialect d : {Dialect::kFanuc, Dialect::kLinuxCnc, Dialect::kSinumerik, Dialect::kHeidenhain}) {
    if (name == DialectName(d)) return d;
  }
  return std::nullopt;
}

const char* DialectTitle(Dialect d) {
  switch (d) {
    case Dialect::kFanuc: return "ISO / Fanuc (M series)";
    case Dialect::kLinuxCnc: return "LinuxCNC RS274NGC";
    case Dialect::kSinumerik: return "Siemens Sinumerik 840D sl";
    case Dialect::kHeidenhain: return "Heidenhain TNC 640 Klartext";
  }
  return "?";
}

const char* ProgramExtension(Dialect d) {
  switch (d) {
    case Dialect::kFanuc: return ".nc";
    case Dialect::kLinuxCnc: return ".ngc";
    case Dialect::kSinumerik: return ".mpf";
    case Dialect::kHeidenhain: return ".h";
  }
  return "";
}

const char* CoolantName(Coolant c) {
  switch (c) {
    case Coolant::kOff: return "off";
    case Coolant::kFlood: return "flood";
    case Coolant::kMist: return "mist";
  }
  return "?";
}

const char* FiveAxisModeName(FiveAxisMode m) {
  return m == FiveAxisMode::kJointInverseTime ? "joint_inverse_time" : "tcp";
}

Status CSpindleOptions::Validate() const {
  if (mode_on_mcode != -1 && !ValidMcode(mode_on_mcode)) return BadOption("c_spindle.mode_on_mcode", "must be -1 or 0..999");
  if (mode_off_mcode != -1 && !ValidMcode(mode_off_mcode)) {
    return BadOption("c_spindle.mode_off_mcode", "must be -1 or 0..999");
  }
  if ((mode_on_mcode == -1) != (mode_off_mcode == -1)) {
    return BadOption("c_spindle.mode_off_mcode", "give both mode_on_mcode and mode_off_mcode, or neither");
  }
  if (spindle_number < 1 || spindle_number > 9) return BadOption("c_spindle.spindle_number", "must be 1..9");
  if (!(std::isfinite(max_rpm) && max_rpm >= 0)) return BadOption("c_spindle.max_rpm", "must be >= 0");
  if (!ValidMcode(orient_mcode)) return BadOption("c_spindle.orient_mcode", "must be 0..999");
  if (!(std::isfinite(orient_angle_deg) && orient_angle_deg >= 0 && orient_angle_deg < 360)) {
    return BadOption("c_spindle.orient_angle_deg", "must be in [0, 360)");
  }
  if (positive_c_mcode != 3 && positive_c_mcode != 4) return BadOption("c_spindle.positive_c_mcode", "must be 3 or 4");
  if (!ValidMcode(heidenhain_start_mcode) || !ValidMcode(heidenhain_start_mcode + 1)) {
    return BadOption("c_spindle.heidenhain_start_mcode", "must be 0..998");
  }
  if (linuxcnc_mode_bit < 0 || linuxcnc_mode_bit > 63) return BadOption("c_spindle.linuxcnc_mode_bit", "must be 0..63");
  if (linuxcnc_speed_channel < 0 || linuxcnc_speed_channel > 63) {
    return BadOption("c_spindle.linuxcnc_speed_channel", "must be 0..63");
  }
  if (!(std::isfinite(css_step_mm) && css_step_mm > 0)) return BadOption("c_spindle.css_step_mm", "must be > 0");
  return Status::Ok();
}

Status SafetyOptions::Validate() const {
  if (!(std::isfinite(rapid_tolerance_mm) && rapid_tolerance_mm >= 0)) {
    return BadOption("safety.rapid_tolerance_mm", "must be >= 0");
  }
  if (!(std::isfinite(rapid_sample_mm) && rapid_sample_mm > 0)) return BadOption("safety.rapid_sample_mm", "must be > 0");
  if (!(std::isfinite(tool_fit_tol_mm) && tool_fit_tol_mm >= 0)) return BadOption("safety.tool_fit_tol_mm", "must be >= 0");
  return Status::Ok();
}

Status BackplotOptions::Validate() const {
  if (!(std::isfinite(width_px) && width_px >= 200)) return BadOption("backplot.width_px", "must be >= 200");
  if (!(std::isfinite(arc_segment_deg) && arc_segment_deg > 0 && arc_segment_deg <= 30)) {
    return BadOption("backplot.arc_segment_deg", "must be in (0, 30]");
  }
  return Status::Ok();
}

GcodeOptions GcodeOptions::ForDialect(Dialect d) {
  GcodeOptions o;
  o.dialect = d;
  switch (d) {
    case Dialect::kFanuc:
      // Builder M-codes switching the table drive between C-axis and spindle mode: no Fanuc
      // standard exists; M250/M251 are common defaults, set c_spindle.mode_on_mcode and
      // mode_off_mcode in the post YAML for the machine (gcode/DIALECTS.md).
      o.c_spindle.mode_on_mcode = 250;
      o.c_spindle.mode_off_mcode = 251;
      o.five_axis = FiveAxisMode::kJointInverseTime;
      break;
    case Dialect::kLinuxCnc:
      o.five_axis = FiveAxisMode::kJointInverseTime;
      break;
    case Dialect::kSinumerik:
      o.five_axis = FiveAxisMode::kToolCenterPoint;  // TRAORI
      break;
    case Dialect::kHeidenhain:
      o.five_axis = FiveAxisMode::kToolCenterPoint;  // M128
      break;
  }
  return o;
}

Status GcodeOptions::Validate() const {
  if (program_name.empty() || program_name.size() > 24 || !std::isupper(static_cast<unsigned char>(program_name[0]))) {
    return BadOption("program_name", "must be 1..24 characters [A-Z0-9_] starting with an upper-case letter");
  }
  for (char ch : program_name) {
    if (!(std::isupper(static_cast<unsigned char>(ch)) || std::isdigit(static_cast<unsigned char>(ch)) || ch == '_')) {
      return BadOption("program_name", "must be 1..24 characters [A-Z0-9_] starting with an upper-case letter");
    }
  }
  if (program_number < 1 || program_number > 9999) return BadOption("program_number", "must be 1..9999");
  if (!date.empty()) {
    const bool shape = date.size() == 10 && date[4] == '-' && date[7] == '-';
    bool digits = shape;
    for (int i : {0, 1, 2, 3, 5, 6, 8, 9}) digits = digits && std::isdigit(static_cast<unsigned char>(date[i]));
    if (!digits) return BadOption("date", "must be YYYY-MM-DD or empty");
  }
  for (char ch : generator) {
    if (ch == '(' || ch == ')' || ch == '\n' || ch == ';') return BadOption("generator", "must not contain ( ) ; or newlines");
  }
  if (work_offset < 1 || work_offset > 6) return BadOption("work_offset", "must be 1..6 (G54..G59 / preset 1..6)");
  if (block_start < 0 || block_start > 99999) return BadOption("block_start", "must be 0..99999");
  if (block_step < 0 || block_step > 1000) return BadOption("block_step", "must be 0..1000");
  if (block_step == 0 && dialect == Dialect::kHeidenhain) {
    return BadOption("block_step", "Heidenhain numbers every line: block_step 0 is not possible");
  }
  if (linear_decimals < 3 || linear_decimals > 6) return BadOption("linear_decimals", "must be 3..6");
  if (rotary_decimals < 3 || rotary_decimals > 6) return BadOption("rotary_decimals", "must be 3..6");
  if (!(std::isfinite(default_tool_length_mm) && default_tool_length_mm > 0)) {
    return BadOption("default_tool_length_mm", "must be > 0");
  }
  std::set<int> pieces, numbers;
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const ToolSetting& t = tools[i];
    const std::string key = "tools[" + std::to_string(i) + "]";
    if (t.piece_tool < 1) return BadOption(key + ".piece_tool", "must be >= 1");
    if (t.number < 0 || t.number > 9999) return BadOption(key + ".number", "must be 0..9999");
    if (!(std::isfinite(t.length_mm) && t.length_mm >= 0)) return BadOption(key + ".length_mm", "must be >= 0");
    if (!pieces.insert(t.piece_tool).second) return BadOption(key + ".piece_tool", "listed twice");
  }
  TPCAL_RETURN_IF_ERROR(c_spindle.Validate());
  if (dialect == Dialect::kLinuxCnc && five_axis == FiveAxisMode::kToolCenterPoint) {
    return BadOption("five_axis", "LinuxCNC (trivial kinematics in rs274) supports only joint_inverse_time");
  }
  TPCAL_RETURN_IF_ERROR(safety.Validate());
  TPCAL_RETURN_IF_ERROR(backplot.Validate());
  return Status::Ok();
}

const ToolSetting* GcodeOptions::FindTool(int piece_tool) const {
  for (const ToolSetting& t : tools) {
    if (t.piece_tool == piece_tool) return &t;
  }
  return nullptr;
}

int GcodeOptions::PostedToolNumber(int piece_tool) const {
  const ToolSetting* t = FindTool(piece_tool);
  return t && t->number > 0 ? t->number : piece_tool;
}

}  // namespace tpcal::gcode
