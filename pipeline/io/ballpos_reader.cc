#include "pipeline/io/ballpos_reader.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

constexpr std::size_t kMaxLineBytes = std::size_t{1} << 16;

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> Split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') out.push_back(Trim(line.substr(start, i - start))), start = i + 1;
  return out;
}

std::optional<double> Number(std::string_view s) {
  double v = 0.0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// What each column of the header holds.
enum class Column { kRotary, kX, kY, kZ, kBall, kTime, kUncertainty };
struct HeaderColumn {
  Column kind;
  char axis = 0;
};

Result<std::vector<HeaderColumn>> ParseHeader(std::string_view line, const std::string& source, std::size_t line_no,
                                              BallPositionFile* file) {
  std::vector<HeaderColumn> cols;
  std::vector<std::string_view> seen;
  for (std::string_view name : Split(line)) {
    for (auto s : seen)
      if (s == name) return Status(StatusCode::kParseError, "column '" + std::string(name) + "' repeated", source, line_no);
    seen.push_back(name);
    if (name == "A_deg" || name == "B_deg" || name == "C_deg") {
      cols.push_back({Column::kRotary, name[0]});
      file->rotary_axes.push_back(name[0]);
    } else if (name == "x" || name == "y" || name == "z") {
      cols.push_back({name == "x" ? Column::kX : name == "y" ? Column::kY : Column::kZ});
    } else if (name == "ball" || name == "t_s" || name == "u_um") {
      cols.push_back({name == "ball" ? Column::kBall : name == "t_s" ? Column::kTime : Column::kUncertainty});
    } else {
      return Status(StatusCode::kParseError,
                    "unknown column '" + std::string(name.substr(0, 40)) +
                        "' (expected A_deg, B_deg, C_deg, x, y, z and optionally ball, t_s, u_um)",
                    source, line_no);
    }
  }
  bool x = false, y = false, z = false;
  for (const auto& c : cols) x |= c.kind == Column::kX, y |= c.kind == Column::kY, z |= c.kind == Column::kZ;
  if (!x || !y || !z || file->rotary_axes.empty())
    return Status(StatusCode::kParseError, "header needs x, y, z and at least one of A_deg, B_deg, C_deg", source,
                  line_no);
  return cols;
}

Status ParseRow(std::string_view line, const std::vector<HeaderColumn>& cols, const std::string& source,
                std::size_t line_no, BallPositionRow* row) {
  const auto fields = Split(line);
  if (fields.size() != cols.size())
    return Status(StatusCode::kParseError,
                  "expected " + std::to_string(cols.size()) + " fields, got " + std::to_string(fields.size()), source,
                  line_no);
  row->line = line_no;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    if (cols[k].kind == Column::kBall) {
      row->ball = std::string(fields[k].substr(0, 64));
      continue;
    }
    const auto v = Number(fields[k]);
    if (!v)
      return Status(StatusCode::kParseError,
                    "field " + std::to_string(k + 1) + ": expected a finite number, got '" +
                        std::string(fields[k].substr(0, 40)) + "'",
                    source, line_no);
    switch (cols[k].kind) {
      case Column::kRotary: row->rotary_deg[cols[k].axis] = *v; break;
      case Column::kX: row->centre_mm.x() = *v; break;
      case Column::kY: row->centre_mm.y() = *v; break;
      case Column::kZ: row->centre_mm.z() = *v; break;
      case Column::kTime: row->t_s = *v; break;
      case Column::kUncertainty: row->u_um = *v; break;
      case Column::kBall: break;
    }
  }
  return Status::Ok();
}

}  // namespace

Result<BallPositionFile> ParseBallPositions(std::string_view text, const std::string& source) {
  BallPositionFile file;
  file.source = source;
  std::optional<std::vector<HeaderColumn>> cols;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = Trim(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++line_no;
    if (line_no == 1) {
      if (line != "# tpcal ballpos v1")
        return Status(StatusCode::kParseError, "expected '# tpcal ballpos v1' on the first line", source, 1);
      continue;
    }
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::string_view body = Trim(line.substr(1));
      if (body.rfind("units:", 0) == 0 && Trim(body.substr(6)) != "mm")
        return Status(StatusCode::kParseError, "units: only mm is supported", source, line_no);
      continue;
    }
    if (!cols) {
      auto h = ParseHeader(line, source, line_no, &file);
      if (!h.ok()) return h.status();
      cols = std::move(*h);
      continue;
    }
    BallPositionRow row;
    if (Status s = ParseRow(line, *cols, source, line_no, &row); !s.ok()) return s;
    file.rows.push_back(std::move(row));
  }
  if (line_no == 0) return Status(StatusCode::kParseError, "empty file: expected '# tpcal ballpos v1'", source, 1);
  if (file.rows.empty()) return Status(StatusCode::kParseError, "no ball positions", source, line_no);
  return file;
}

Result<BallPositionFile> ReadBallPositions(const std::string& path) {
  auto bytes = ReadFileBytes(path, kMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParseBallPositions(bytes->view(), path);
}

}  // namespace tpcal::pipeline
