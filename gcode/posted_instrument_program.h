// An instrument test's posted NC program (datum ball, probing of artifacts, ball bar): the text
// in the dialect, LinuxCNC's tool table and the IR it was posted from. One type for every
// instrument, built by internal::PostProbingIr (gcode/internal/probe_moves.h).
#pragma once

#include <string>

#include "gcode/ir.h"
#include "gcode/post.h"

namespace tpcal::gcode {

struct PostedInstrumentProgram {
  std::string program_file;     // "<program_name><ext>"
  std::string program_text;
  std::string tool_table_file;  // LinuxCNC only (inches, gcode/tool_table.h)
  std::string tool_table_text;
  IrProgram ir;
  PostedText posted;            // labels per IR instruction
};

}  // namespace tpcal::gcode
