#include "gcode/post_program.h"

#include <sstream>

#include "gcode/nc_format.h"
#include "gcode/stock.h"
#include "gcode/tool_table.h"

namespace tpcal::gcode {

std::string PostedProgram::Summary() const {
  std::ostringstream os;
  os << program_file << ": " << DialectTitle(dialect) << ", " << posted.block_count << " blocks, " << ir.tools.size()
     << " tools, " << ir.operation_names.size() << " operations, time estimate " << FormatNumber(ir.duration_s, 0)
     << " s; safety: " << safety.rapids_checked << " rapids checked";
  if (safety.rapids_checked > 0) {
    os << " (" << safety.rapid_samples << " samples), smallest rapid clearance "
       << FormatNumber(safety.min_rapid_clearance_mm, 3) << " mm";
    if (!safety.min_rapid_block.empty()) os << " at " << safety.min_rapid_block;
  }
  os << ", " << safety.tool_fits_checked << " tool fits checked";
  if (!tool_table_file.empty()) os << "; tool table " << tool_table_file << " (inches)";
  return os.str();
}

Result<PostedProgram> PostProgram(const testpieces::TestPiece& piece, const GcodeOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  PostedProgram out;
  out.dialect = options.dialect;
  auto ir = BuildIr(piece, options);
  if (!ir.ok()) return ir.status();
  out.ir = std::move(ir).value();
  auto stock = StockOf(piece);
  if (!stock.ok()) return stock.status();
  out.ir.stock_min_mm = stock->min_mm;
  out.ir.stock_max_mm = stock->max_mm;
  auto posted = PostIr(out.ir, options);
  if (!posted.ok()) return posted.status();
  out.posted = std::move(posted).value();
  auto safety = CheckProgram(piece, out.ir, out.posted, *stock, options.safety);
  if (!safety.ok()) return safety.status().WithContext(options.program_name + ProgramExtension(options.dialect));
  out.safety = *safety;
  out.program_text = out.posted.text;
  out.program_file = options.program_name + ProgramExtension(options.dialect);
  if (options.dialect == Dialect::kLinuxCnc) {
    out.tool_table_file = options.tool_table_file.empty() ? options.program_name + ".tbl" : options.tool_table_file;
    out.tool_table_text = LinuxCncToolTable(out.ir);
  }
  const std::string title = piece.name + " - " + DialectTitle(options.dialect) + " - " + out.program_file;
  out.backplot_svg = BackplotSvg(out.ir, options.backplot, title, &out.backplot);
  return out;
}

}  // namespace tpcal::gcode
