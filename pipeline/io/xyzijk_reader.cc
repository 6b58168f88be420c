// PC-DMIS XYZIJK text reader (see xyzijk_reader.h).
#include "pipeline/io/xyzijk_reader.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <system_error>
#include <vector>

#include "core/units.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

std::string_view TrimCell(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::string UpperCell(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return out;
}

std::optional<double> CellNumber(std::string_view s) {
  s = TrimCell(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  auto r = fast_float::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Lines with their 1-based numbers.
std::vector<std::pair<std::size_t, std::string_view>> Lines(std::string_view text) {
  std::vector<std::pair<std::size_t, std::string_view>> out;
  std::size_t pos = 0, n = 0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    out.emplace_back(++n, TrimCell(text.substr(pos, eol - pos)));
    pos = eol + 1;
  }
  return out;
}

}  // namespace

bool IsXyzijkText(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const std::size_t eol = text.find('\n');
  return UpperCell(TrimCell(text.substr(0, eol))) == "XYZIJK";
}

bool IsXyzijkFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char buf[64] = {};
  in.read(buf, sizeof buf);
  return IsXyzijkText(std::string_view(buf, static_cast<std::size_t>(in.gcount())));
}

Result<PointFile> ParsePointXyzijk(std::string_view text, const std::string& source_name,
                                   const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  auto error = [&](std::size_t line, std::string what) {
    return Status(StatusCode::kParseError, std::move(what), source_name, line);
  };
  const auto lines = Lines(text);
  if (lines.empty() || UpperCell(lines[0].second) != "XYZIJK")
    return error(1, "expected the first line XYZIJK (PC-DMIS XYZIJK text)");
  PointFile out;
  PointSet& ps = out.points;
  ps.source = source_name;
  double mm_per_unit = options.assumed_units == LengthUnit::kInch ? kMmPerInch : 1.0;
  out.info.source_units = options.assumed_units;
  std::size_t i = 1;
  while (i < lines.size() && lines[i].second.empty()) ++i;
  if (i < lines.size()) {
    const std::string u = UpperCell(lines[i].second);
    if (u == "METRIC" || u == "MM") {
      mm_per_unit = 1.0;
      out.info.source_units = LengthUnit::kMm;
      ++i;
    } else if (u == "INCH" || u == "ENGLISH") {
      mm_per_unit = kMmPerInch;
      out.info.source_units = LengthUnit::kInch;
      ++i;
    } else if (!u.empty() && u.find(',') == std::string::npos && !CellNumber(u)) {
      return error(lines[i].first, fmt::format("unit line '{}': expected METRIC, MM, INCH or ENGLISH", lines[i].second));
    }
  }
  std::size_t columns = 0;  // numbers per line, fixed by the first data line
  bool labelled = false;
  for (; i < lines.size(); ++i) {
    const auto [line_no, line] = lines[i];
    if (line.empty()) continue;
    std::vector<std::string_view> cells;
    std::size_t b = 0;
    for (std::size_t k = 0; k <= line.size(); ++k) {
      if (k == line.size() || line[k] == ',') {
        cells.push_back(TrimCell(line.substr(b, k - b)));
        b = k + 1;
      }
    }
    std::string label;
    const bool has_label = !cells.empty() && !CellNumber(cells[0]);
    if (columns == 0) labelled = has_label;
    if (has_label != labelled)
      return error(line_no, labelled ? "expected a label in the first cell, as on the first data line"
                                     : fmt::format("'{}' is not a number: expected x,y,z[,i,j,k]", cells[0]));
    if (has_label) {
      label = std::string(cells[0]);
      cells.erase(cells.begin());
    }
    if (columns == 0) {
      columns = cells.size();
      if (columns != 3 && columns != 6)
        return error(line_no, fmt::format("{} numbers: expected x,y,z or x,y,z,i,j,k", columns));
    }
    if (cells.size() != columns)
      return error(line_no, fmt::format("{} numbers: expected {} as on the first data line", cells.size(), columns));
    double v[6] = {0, 0, 0, 0, 0, 0};
    for (std::size_t k = 0; k < columns; ++k) {
      auto x = CellNumber(cells[k]);
      if (!x) return error(line_no, fmt::format("'{}' is not a number: expected x,y,z[,i,j,k]", cells[k]));
      v[k] = *x;
    }
    ps.xyz_mm.emplace_back(v[0] * mm_per_unit, v[1] * mm_per_unit, v[2] * mm_per_unit);
    if (columns == 6) {
      const Eigen::Vector3d n(v[3], v[4], v[5]);
      const double len = n.norm();
      if (!(len > 1e-12) || std::abs(len - 1.0) > options.normal_tolerance)
        return error(line_no, fmt::format("vector ({}, {}, {}) has length {:.6g}: expected a unit vector", v[3], v[4],
                                          v[5], len));
      ps.normal.push_back(std::abs(len - 1.0) > 1e-14 ? Eigen::Vector3d(n / len) : n);  // as the CSV reader
    }
    ps.feature.push_back(labelled ? ps.InternFeature(label) : PointSet::kUnlabelled);
    ps.line.push_back(line_no);
  }
  if (ps.empty()) return error(lines.size(), "no points: expected lines x,y,z[,i,j,k] after XYZIJK");
  out.info.format = PointFormat::kXyzijk;
  out.info.bytes = text.size();
  return out;
}

Result<PointFile> ReadPointXyzijk(const std::string& path, const PointReadOptions& options) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParsePointXyzijk(bytes->view(), path, options);
}

}  // namespace tpcal::pipeline
