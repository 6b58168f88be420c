// Per-dialect checker of the words and statements a control accepts, for the programs the
// posts write: a whitelist of addresses, G / M codes, cycles and keywords per dialect, the block
// syntax (block numbers increasing, Fanuc decimal points, Heidenhain consecutive line numbers
// and signed coordinates, one motion code per block, no G-words in Klartext), the program frame
// (% / O-number, %_N_..._MPF, BEGIN / END PGM). It does not replace the control: it catches a
// post that drifts outside the subset DIALECTS.md documents.
#pragma once

#include <string_view>

#include "core/status.h"
#include "gcode/options.h"

namespace tpcal::gcode {

struct DialectCheckReport {
  int lines = 0;
  int blocks = 0;   // numbered blocks
  int words = 0;    // addresses and statements checked
};

// Errors (kParseError, 1-based line of the program): the first violation, naming the word.
// The C-spindle M-codes configured in `options` are accepted.
Result<DialectCheckReport> CheckDialectSyntax(std::string_view text, const GcodeOptions& options);

}  // namespace tpcal::gcode
