// Internal to tpcal::pipeline: the checks of a PLY or PCD file that run before PCL reads it, so
// PCL is never handed a file it could crash on or that would make it allocate more than the
// file holds (a header declaring 10^8 points over 10 real ones). Header grammar, types and
// counts are checked line by line; binary data must hold every declared point (lists walked,
// LZF-compressed PCD data decompressed once), ASCII data rows must hold the declared values.
// Accepted: what PCL and common scanners write (docs/formats/points.md, "PLY and PCD").
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/status.h"

namespace tpcal::pipeline::internal {

// What the checks saw that the reader reports later (point errors after PCL has read the file).
struct CloudNotes {
  // ASCII data: the line of the first point row whose x, y or z is NaN or infinite (or beyond a
  // 4-byte float's range in a float field); 0: none, or binary data.
  std::size_t first_nonfinite_xyz_line = 0;
};

// OK if `bytes`, the whole file `path`, is a PCD file tpcal hands to PCL; else kParseError at
// the 1-based line at fault (a header line or an ASCII data row; 0 for binary data). `notes`
// (optional) receives CloudNotes.
Status CheckPcdBytes(std::string_view bytes, const std::string& path, CloudNotes* notes = nullptr);

// Same for PLY (the rows of element vertex).
Status CheckPlyBytes(std::string_view bytes, const std::string& path, CloudNotes* notes = nullptr);

}  // namespace tpcal::pipeline::internal
