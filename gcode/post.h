// The dialect posts: IrProgram -> NC text. One post per dialect (post_fanuc.cc,
// post_linuxcnc.cc, post_sinumerik.cc, post_heidenhain.cc); their choices are in DIALECTS.md.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"

namespace tpcal::gcode {

struct PostedText {
  std::string text;  // the program, '\n' line ends, ends with a newline
  // Per IR instruction (same index as IrProgram::instrs): the labels of the blocks it produced,
  // as the control names them ("N120"; Heidenhain: the line number "37"). Empty when an
  // instruction produced no block (e.g. a rapid whose words are all modal repeats).
  std::vector<std::vector<std::string>> instr_labels;
  int block_count = 0;  // numbered blocks
};

// Posts `prog` in options.dialect. Errors: options invalid; a block number beyond the dialect's
// limit (Fanuc N99999); a five-axis move in a dialect/mode that cannot express it.
Result<PostedText> PostIr(const IrProgram& prog, const GcodeOptions& options);

// The lines of the comment header every program starts with: test piece, standard clause,
// machine, control, units, work offset, date, generator, tools, C spindle and five-axis modes.
std::vector<std::string> HeaderLines(const IrProgram& prog, const GcodeOptions& options);

// First label of an instruction's blocks, or the nearest earlier one ("" if none), for messages.
std::string LabelOf(const PostedText& posted, int instr_index);

}  // namespace tpcal::gcode
