// Small per-dialect readers of the programs the posts write: NC text back into the moves a
// control executes (rapid, feed, arc; canned / defined cycles expanded; tool centre point
// blocks marked `tcp`; Heidenhain turning-mode X diameters halved). They read the subset the
// posts emit (and reject anything else with the line), which is what the round-trip tests
// need: the same IR posted to LinuxCNC and to a dialect gives the same path.
#pragma once

#include <string_view>

#include "core/status.h"
#include "gcode/nc_path.h"
#include "gcode/options.h"

namespace tpcal::gcode {

// Starts at the origin (like rs274). Errors (kParseError, 1-based line): unknown statements,
// words without numbers, arcs without centre, cycles with missing parameters.
Result<NcPath> ReadNcProgram(std::string_view text, const GcodeOptions& options);

}  // namespace tpcal::gcode
