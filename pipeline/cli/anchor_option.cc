// --anchor FEATURE@X,Y,Z: see anchor_option.h.
#include "pipeline/cli/anchor_option.h"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

namespace tpcal::cli {

void AddAnchorOption(CLI::App* sub, std::string* anchor) {
  sub->add_option("--anchor", *anchor,
                  "FEATURE@X,Y,Z: for a raw scan of a symmetric piece, choose the labelling placing FEATURE nearest "
                  "the point X,Y,Z (mm, scan frame), e.g. H1@120,-80,40; without it the first scanned points decide");
}

namespace {

// A whole, finite number (surrounding blanks allowed).
bool ParseNumber(std::string_view s, double* value) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *value);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(*value);
}

}  // namespace

Result<pipeline::RawScanLabelingOptions> ParseAnchor(const std::string& text) {
  pipeline::RawScanLabelingOptions options;
  if (text.empty()) return options;
  const Status bad(StatusCode::kInvalidArgument, "--anchor: expected FEATURE@X,Y,Z (mm), got '" + text + "'");
  const auto at = text.find('@');
  if (at == std::string::npos || at == 0) return bad;
  const std::string_view coords = std::string_view(text).substr(at + 1);
  double xyz[3];
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = i < 2 ? coords.find(',', start) : coords.size();
    if (comma == std::string_view::npos) return bad;
    if (!ParseNumber(coords.substr(start, comma - start), &xyz[i])) return bad;
    start = comma + 1;
  }
  options.anchor_feature = text.substr(0, at);
  options.anchor_near_mm = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
  return options;
}

}  // namespace tpcal::cli
