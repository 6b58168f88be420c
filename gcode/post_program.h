// The one entry point of gcode/ for the CLI (`tpcal gcode`): a test piece and post options in,
// the NC program text, the LinuxCNC tool table and the backplot SVG out, after the safety
// checks (gcode/safety.h) passed.
//
//   auto piece = testpieces::MakeTestPiece(config, machine);
//   auto options = gcode::LoadGcodeOptions("post.yaml");          // or GcodeOptions::ForDialect
//   auto posted = gcode::PostProgram(*piece, *options);
//   write posted->program_file (program_text), posted->tool_table_file (if not empty), the SVG.
#pragma once

#include <string>

#include "core/status.h"
#include "gcode/backplot.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/safety.h"
#include "testpieces/test_piece.h"

namespace tpcal::gcode {

struct PostedProgram {
  Dialect dialect = Dialect::kLinuxCnc;
  std::string program_file;     // "<program_name><ext>", e.g. "TPCAL.ngc"
  std::string program_text;
  std::string tool_table_file;  // LinuxCNC: options.tool_table_file or "<program_name>.tbl"; others: ""
  std::string tool_table_text;  // LinuxCNC tool table in inches (tool_table.h); "" otherwise
  std::string backplot_svg;
  IrProgram ir;                 // what was posted
  PostedText posted;            // labels per IR instruction
  SafetyReport safety;
  BackplotStats backplot;
  // One-paragraph summary for the CLI: blocks, tools, time estimate, minimum rapid clearance.
  std::string Summary() const;
};

// Builds the IR, posts it in options.dialect, checks it (strokes, rapids vs stock, tool fit:
// each can be switched off in options.safety) and draws the backplot. Errors: invalid options
// (naming the YAML key), a safety violation ("N1230: rapid move enters ..."), IR / post errors.
Result<PostedProgram> PostProgram(const testpieces::TestPiece& piece, const GcodeOptions& options);

}  // namespace tpcal::gcode
