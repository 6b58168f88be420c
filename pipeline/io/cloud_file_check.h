// Internal to tpcal::pipeline: the checks of a PLY or PCD file that run before PCL reads it, so
// PCL is never handed a file it could crash on or that would make it allocate more than the
// file holds (a header declaring 10^8 points over 10 real ones). Header grammar, types and
// counts are checked line by line; binary data must hold every declared point (lists walked,
// LZF-compressed PCD data decompressed once), ASCII data rows must hold the declared values.
// Accepted: what PCL and common scanners write (docs/formats/points.md, "PLY and PCD").
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"

namespace tpcal::pipeline::internal {

// OK if `bytes`, the whole file `path`, is a PCD file tpcal hands to PCL; else kParseError at
// the 1-based line at fault (a header line or an ASCII data row; 0 for binary data).
Status CheckPcdBytes(std::string_view bytes, const std::string& path);

// Same for PLY.
Status CheckPlyBytes(std::string_view bytes, const std::string& path);

}  // namespace tpcal::pipeline::internal
