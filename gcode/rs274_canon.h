// Reader of the canonical-machining-function listing printed by LinuxCNC's standalone
// interpreter `rs274 -g PROGRAM -t TOOLTABLE` (checked on linuxcnc-uspace 2.9.0~pre1 here):
//
//      25 N70    ARC_FEED(100.0000, 0.0000, 0.0000, 0.0000, 1, 10.0000, 0.0000, 0.0000, 0.0000)
//      22 N50    STRAIGHT_TRAVERSE(100.0000, 0.0000, 50.0000, 0.0000, 0.0000, 0.0000)
//
// one call per line: a sequence number, the block's N number ("N....." when the block has
// none), the call. Positions are in the PROGRAM's length units (mm after G21), rotary axes in
// degrees, work offsets applied, the tool length offset NOT applied (it is reported by
// USE_TOOL_LENGTH_OFFSET). STRAIGHT_TRAVERSE / STRAIGHT_FEED / STRAIGHT_PROBE (G38.2: without a
// probe the move reaches its target) print X, Y, Z, A, B, C; ARC_FEED
// prints (first_end, second_end, first_axis, second_axis, rotation, axis_end_point, A, B, C) in
// the active plane's axes: XY as (X, Y), XZ as (Z, X), YZ as (Y, Z). The interpreter has no
// error line format on stdout: errors go to stderr and stop the run (rc 1) unless `-n 0`, which
// continues silently with rc 0, so Rs274Errors() also looks at what is missing (PROGRAM_END).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "gcode/nc_path.h"

namespace tpcal::gcode {

struct Rs274Listing {
  NcPath path;                               // moves with their N labels
  std::vector<std::string> comments;         // COMMENT("...") texts
  std::vector<double> tool_length_offsets_mm;  // Z of every USE_TOOL_LENGTH_OFFSET
  std::vector<std::pair<std::string, std::string>> calls;  // (label, call) of every line
  std::vector<PathMove> probes;              // STRAIGHT_PROBE targets (also in `path`, as feeds)
  bool program_end = false;                  // PROGRAM_END() seen
  int dwells = 0;
};

// Parses the stdout of rs274. Errors (kParseError, line number of the listing) for a line that
// is not "<seq> <label> NAME(args)" or a motion call with the wrong argument count.
Result<Rs274Listing> ParseRs274Listing(std::string_view stdout_text);

// Interpreter errors of a run: a non-zero exit status, any stderr text other than the
// "executing" banner, or a listing that never reaches PROGRAM_END. Returns "" when clean,
// else the error text (with rs274's own message and offending block when it printed them).
std::string Rs274Errors(int exit_status, std::string_view stdout_text, std::string_view stderr_text);

}  // namespace tpcal::gcode
