// Internal to tpcal::pipeline: the chunked, multi-threaded text parser shared by the CSV
// reader (contract dialect, see point_io.h) and the plain xyz reader.
//
// The text after the preamble (comments, directives, header) is split into chunks at line
// boundaries; each chunk is parsed on its own thread with fast_float into chunk-local
// arrays with chunk-local line numbers and feature ids; the merge renumbers lines and
// features (first appearance in file order) and copies the chunks into the PointSet in file
// order. The result is bit-identical to a serial parse; the first error in file order wins.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/status.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline::internal {

// Longest line of a text point file (CSV or xyz); longer is an error at that line.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

enum class TextDialect {
  kCsv,  // contract CSV: header line, comma separated, optional quotes
  kXyz,  // no header; blanks and/or commas separate `x y z [i j k]`
};

Result<PointFile> ParsePointText(std::string_view text, const std::string& source,
                                 TextDialect dialect, const PointReadOptions& options);

}  // namespace tpcal::pipeline::internal
