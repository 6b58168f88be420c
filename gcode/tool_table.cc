#include "gcode/tool_table.h"

#include <sstream>

#include "core/units.h"
#include "gcode/nc_format.h"

namespace tpcal::gcode {

std::string LinuxCncToolTable(const IrProgram& prog) {
  std::ostringstream os;
  for (const IrTool& t : prog.tools) {
    const bool insert = t.tool.kind == testpieces::ToolKind::kTurningInsert;
    const double diameter_mm = insert ? 2.0 * t.tool.corner_radius_mm : t.tool.diameter_mm;
    os << "T" << t.number << " P" << t.number << " Z" << FormatNumber(t.length_mm / kMmPerInch, 8) << " D"
       << FormatNumber(diameter_mm / kMmPerInch, 8) << " ;" << SanitizeComment(t.tool.name) << " [mm: length "
       << FormatNumber(t.length_mm, 4) << ", " << (insert ? "nose diameter " : "diameter ")
       << FormatNumber(diameter_mm, 4) << "]\n";
  }
  return os.str();
}

}  // namespace tpcal::gcode
