// LinuxCNC tool table written beside a LinuxCNC program (PROGRAM.tbl), so that
// `rs274 -g PROGRAM.ngc -t PROGRAM.tbl` runs the program as it is.
//
// Units: INCHES. LinuxCNC's standalone interpreter reads tool tables in inches whatever the INI
// or the program says (checked here: a Z1.0 entry gives USE_TOOL_LENGTH_OFFSET 25.4 in a G21
// program; gcode/DIALECTS.md), so mm values are divided by 25.4 and written with 8 decimals
// (1e-8 in = 0.25 nm).
#pragma once

#include <string>

#include "gcode/ir.h"

namespace tpcal::gcode {

// One line per tool: "T<n> P<n> Z<length in> D<diameter in> ;<name> [mm values]". A turning
// insert's D is its nose diameter (2 x nose radius), as LinuxCNC lathe tools.
std::string LinuxCncToolTable(const IrProgram& prog);

}  // namespace tpcal::gcode
