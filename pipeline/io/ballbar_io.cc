#include "pipeline/io/ballbar_io.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "core/input_echo.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a Ballbar prefix: a unity build merges this file with the other readers
// of pipeline/io (probepts_io.cc, ballpos_reader.cc), which have their own Trim, Split, Number.

constexpr std::size_t kBallbarMaxLineBytes = std::size_t{1} << 16;

std::string_view BallbarTrim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> BallbarSplit(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') out.push_back(BallbarTrim(line.substr(start, i - start))), start = i + 1;
  return out;
}

std::optional<double> BallbarNumber(std::string_view s) {
  double v = 0.0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string BallbarFormatNumber(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

enum class BallbarColumn { kSetup, kAngle, kDl, kDirection, kTime };

std::optional<BallbarColumn> BallbarColumnOf(std::string_view name) {
  if (name == "setup") return BallbarColumn::kSetup;
  if (name == "angle_deg") return BallbarColumn::kAngle;
  if (name == "dl_um") return BallbarColumn::kDl;
  if (name == "direction") return BallbarColumn::kDirection;
  if (name == "t_s") return BallbarColumn::kTime;
  return std::nullopt;
}

Result<std::vector<BallbarColumn>> BallbarParseHeader(std::string_view line, const std::string& source,
                                                      std::size_t line_no, BallbarFile* file) {
  std::vector<BallbarColumn> cols;
  for (std::string_view name : BallbarSplit(line)) {
    const std::optional<BallbarColumn> kind = BallbarColumnOf(name);
    if (!kind)
      return Status(StatusCode::kParseError,
                    "unknown column '" + EchoInput(name, 40) +
                        "' (expected setup, angle_deg, dl_um and optionally direction, t_s)",
                    source, line_no);
    for (BallbarColumn c : cols)
      if (c == *kind) return Status(StatusCode::kParseError, "column '" + EchoInput(name) + "' repeated", source, line_no);
    cols.push_back(*kind);
    file->has_direction |= *kind == BallbarColumn::kDirection;
    file->has_t |= *kind == BallbarColumn::kTime;
  }
  // setup, angle_deg, dl_um: three kinds, none repeated, so all present when three are.
  std::size_t required = 0;
  for (BallbarColumn c : cols) required += c == BallbarColumn::kSetup || c == BallbarColumn::kAngle || c == BallbarColumn::kDl;
  if (required != 3)
    return Status(StatusCode::kParseError, "header needs setup, angle_deg and dl_um", source, line_no);
  return cols;
}

Status BallbarParseRow(std::string_view line, const std::vector<BallbarColumn>& cols, const std::string& source,
                       std::size_t line_no, BallbarRow* row) {
  const auto fields = BallbarSplit(line);
  if (fields.size() != cols.size())
    return Status(StatusCode::kParseError,
                  "expected " + std::to_string(cols.size()) + " fields, got " + std::to_string(fields.size()), source,
                  line_no);
  row->line = line_no;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const std::string field_no = "field " + std::to_string(k + 1);
    if (cols[k] == BallbarColumn::kSetup) {
      if (fields[k].empty())
        return Status(StatusCode::kParseError, field_no + ": empty setup (expected an installation of the set-up YAML)",
                      source, line_no);
      if (fields[k].front() == '#')
        return Status(StatusCode::kParseError, field_no + ": setup '" + EchoInput(fields[k], 40) +
                                                   "' starts with '#' (a line so written is a comment)",
                      source, line_no);
      row->setup = std::string(fields[k]);
      continue;
    }
    if (cols[k] == BallbarColumn::kDirection) {
      if (fields[k] == "cw") {
        row->direction = BallbarDirection::kCw;
      } else if (fields[k] == "ccw") {
        row->direction = BallbarDirection::kCcw;
      } else {
        return Status(StatusCode::kParseError,
                      field_no + ": direction '" + EchoInput(fields[k], 40) + "': expected cw or ccw", source, line_no);
      }
      continue;
    }
    const auto v = BallbarNumber(fields[k]);
    if (!v)
      return Status(StatusCode::kParseError,
                    field_no + ": expected a finite number, got '" + EchoInput(fields[k], 40) + "'", source, line_no);
    if (cols[k] == BallbarColumn::kAngle) row->angle_deg = *v;
    if (cols[k] == BallbarColumn::kDl) row->dl_um = *v;
    if (cols[k] == BallbarColumn::kTime) row->t_s = *v;
  }
  return Status::Ok();
}

}  // namespace

Result<BallbarFile> ParseBallbar(std::string_view text, const std::string& source) {
  BallbarFile file;
  file.source = source;
  std::optional<std::vector<BallbarColumn>> cols;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = BallbarTrim(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++line_no;
    if (line_no == 1) {
      if (line != "# tpcal ballbar v1")
        return Status(StatusCode::kParseError, "expected '# tpcal ballbar v1' on the first line", source, 1);
      continue;
    }
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::string_view body = BallbarTrim(line.substr(1));
      if (body.rfind("units:", 0) == 0 && BallbarTrim(body.substr(6)) != "mm")
        return Status(StatusCode::kParseError, "units: only mm is supported", source, line_no);
      continue;
    }
    if (!cols) {
      auto h = BallbarParseHeader(line, source, line_no, &file);
      if (!h.ok()) return h.status();
      cols = std::move(*h);
      continue;
    }
    BallbarRow row;
    if (Status s = BallbarParseRow(line, *cols, source, line_no, &row); !s.ok()) return s;
    file.rows.push_back(std::move(row));
  }
  if (line_no == 0) return Status(StatusCode::kParseError, "empty file: expected '# tpcal ballbar v1'", source, 1);
  if (file.rows.empty()) return Status(StatusCode::kParseError, "no readings", source, line_no);
  return file;
}

Result<BallbarFile> ReadBallbar(const std::string& path) {
  auto bytes = ReadFileBytes(path, kBallbarMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParseBallbar(bytes->view(), path);
}

std::string FormatBallbar(const BallbarFile& file) {
  std::string out = "# tpcal ballbar v1\n# units: mm\nsetup,angle_deg,dl_um";
  if (file.has_direction) out += ",direction";
  if (file.has_t) out += ",t_s";
  out += '\n';
  for (const BallbarRow& r : file.rows) {
    out += r.setup + "," + BallbarFormatNumber(r.angle_deg) + "," + BallbarFormatNumber(r.dl_um);
    if (file.has_direction) out += std::string(",") + (r.direction == BallbarDirection::kCw ? "cw" : "ccw");
    if (file.has_t) out += "," + BallbarFormatNumber(r.t_s);
    out += '\n';
  }
  return out;
}

}  // namespace tpcal::pipeline
