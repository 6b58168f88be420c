// Post-processor option files (YAML, schema tpcal.gcode/1). Every key is optional; missing keys
// take GcodeOptions::ForDialect(dialect) defaults (the dialect key is read first). Unknown or
// duplicate keys, wrong types and invalid values are errors "file:line: what was expected".
// yaml-cpp stays in the .cc. Example: samples/gcode/fanuc.yaml; keys and meanings:
// gcode/DIALECTS.md ("Options").
//
//   schema: tpcal.gcode/1
//   dialect: fanuc                 # fanuc | linuxcnc | sinumerik | heidenhain
//   program_name: TURNING          # [A-Z0-9_], file stem / PGM / MPF name
//   program_number: 1000           # Fanuc O-number
//   date: "2024-05-01"             # header date; "" or absent: "not recorded"
//   generator: tpcal
//   work_offset: 1                 # G54 / preset 1
//   coolant: flood                 # off | flood | mist
//   block_start: 10
//   block_step: 10
//   linear_decimals: 4
//   rotary_decimals: 4
//   default_tool_length_mm: 100
//   five_axis: joint_inverse_time  # joint_inverse_time | tcp
//   tools: [{piece_tool: 1, number: 12, length_mm: 95.5}]
//   c_spindle: {mode_on_mcode: 250, mode_off_mcode: 251, spindle_number: 2, css: true,
//               max_rpm: 0, orient_mcode: 19, orient_angle_deg: 0, positive_c_mcode: 3,
//               heidenhain_start_mcode: 303, heidenhain_x_diameter: true,
//               linuxcnc_mode_bit: 0, linuxcnc_speed_channel: 0, css_step_mm: 2}
//   safety: {check_strokes: true, check_rapids: true, check_tool_fit: true,
//            rapid_tolerance_mm: 0.01, rapid_sample_mm: 1, tool_fit_tol_mm: 0.001}
//   backplot: {width_px: 1200, arc_segment_deg: 2}
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "gcode/options.h"

namespace tpcal::gcode {

// `source` names the text in messages. Errors: kParseError (syntax, schema, unknown / duplicate
// keys, types: with the line), kInvalidArgument (GcodeOptions::Validate, naming the key).
Result<GcodeOptions> ParseGcodeOptions(std::string_view yaml_text, const std::string& source);
// Reads and parses a file (kIoError if it cannot be read).
Result<GcodeOptions> LoadGcodeOptions(const std::string& path);
// YAML that ParseGcodeOptions reads back to the same options (every key written), for the
// effective configuration the CLI writes beside its outputs.
std::string FormatGcodeOptions(const GcodeOptions& options);

}  // namespace tpcal::gcode
