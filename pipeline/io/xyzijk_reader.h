// PC-DMIS XYZIJK text (docs/formats/dmis.md, "XYZIJK"): first line `XYZIJK`, then optionally a
// unit line `METRIC` / `MM` or `INCH` / `ENGLISH` (absent: PointReadOptions::assumed_units),
// then one point per line, comma-separated `x,y,z[,i,j,k]`; a first cell that is not a number
// is the point's feature label. Blank lines are skipped; every data line must have the column
// count of the first. Errors: kParseError `file:line: what was expected`.
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {

// True if `text` starts (after a UTF-8 byte-order mark and blanks) with the line `XYZIJK`.
bool IsXyzijkText(std::string_view text);
// The same for the first bytes of a file (false if it cannot be read).
bool IsXyzijkFile(const std::string& path);

Result<PointFile> ParsePointXyzijk(std::string_view text, const std::string& source_name,
                                   const PointReadOptions& options = {});
Result<PointFile> ReadPointXyzijk(const std::string& path, const PointReadOptions& options = {});

}  // namespace tpcal::pipeline
