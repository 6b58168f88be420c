#include "pipeline/io/probepts_io.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "core/input_echo.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a Probepts prefix: a unity build merges this file with
// ballpos_reader.cc, which has its own Trim, Split, Number, ...

constexpr std::size_t kProbeptsMaxLineBytes = std::size_t{1} << 16;
constexpr double kProbeptsUnitTol = 1e-6;  // |(i, j, k)| - 1, the header's contract

std::string_view ProbeptsTrim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> ProbeptsSplit(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') out.push_back(ProbeptsTrim(line.substr(start, i - start))), start = i + 1;
  return out;
}

std::optional<double> ProbeptsNumber(std::string_view s) {
  double v = 0.0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Shortest text that reads back to the same double (at most 17 significant digits).
std::string ProbeptsFormatNumber(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

// What each column of the header holds.
enum class ProbeptsColumn { kRotary, kArtifact, kFace, kX, kY, kZ, kI, kJ, kK, kTime, kUncertainty };
struct ProbeptsHeaderColumn {
  ProbeptsColumn kind;
  char axis = 0;
};

std::optional<ProbeptsColumn> ProbeptsColumnOf(std::string_view name) {
  struct Named {
    const char* name;
    ProbeptsColumn kind;
  };
  static constexpr Named kNamed[] = {
      {"artifact", ProbeptsColumn::kArtifact}, {"face", ProbeptsColumn::kFace}, {"x", ProbeptsColumn::kX},
      {"y", ProbeptsColumn::kY},               {"z", ProbeptsColumn::kZ},       {"i", ProbeptsColumn::kI},
      {"j", ProbeptsColumn::kJ},               {"k", ProbeptsColumn::kK},       {"t_s", ProbeptsColumn::kTime},
      {"u_um", ProbeptsColumn::kUncertainty}};
  for (const Named& n : kNamed)
    if (name == n.name) return n.kind;
  return std::nullopt;
}

Result<std::vector<ProbeptsHeaderColumn>> ProbeptsParseHeader(std::string_view line, const std::string& source,
                                                              std::size_t line_no, ProbePointFile* file) {
  std::vector<ProbeptsHeaderColumn> cols;
  std::vector<std::string_view> seen;
  for (std::string_view name : ProbeptsSplit(line)) {
    for (auto s : seen)
      if (s == name) return Status(StatusCode::kParseError, "column '" + EchoInput(name) + "' repeated", source, line_no);
    seen.push_back(name);
    if (name == "A_deg" || name == "B_deg" || name == "C_deg") {
      cols.push_back({ProbeptsColumn::kRotary, name[0]});
      file->rotary_axes.push_back(name[0]);
    } else if (const std::optional<ProbeptsColumn> kind = ProbeptsColumnOf(name)) {
      cols.push_back({*kind, 0});
      file->has_t |= *kind == ProbeptsColumn::kTime;
      file->has_u |= *kind == ProbeptsColumn::kUncertainty;
    } else {
      return Status(StatusCode::kParseError,
                    "unknown column '" + EchoInput(name, 40) +
                        "' (expected A_deg, B_deg, C_deg, artifact, face, x, y, z, i, j, k and optionally t_s, u_um)",
                    source, line_no);
    }
  }
  // artifact, face, x, y, z, i, j, k: eight kinds, none repeated, so all present when eight are.
  std::size_t required = 0;
  for (const auto& c : cols)
    if (c.kind != ProbeptsColumn::kRotary && c.kind != ProbeptsColumn::kTime &&
        c.kind != ProbeptsColumn::kUncertainty)
      ++required;
  if (required != 8 || file->rotary_axes.empty())
    return Status(StatusCode::kParseError,
                  "header needs artifact, face, x, y, z, i, j, k and at least one of A_deg, B_deg, C_deg", source,
                  line_no);
  return cols;
}

Status ProbeptsParseRow(std::string_view line, const std::vector<ProbeptsHeaderColumn>& cols,
                        const std::string& source, std::size_t line_no, ProbePointRow* row) {
  const auto fields = ProbeptsSplit(line);
  if (fields.size() != cols.size())
    return Status(StatusCode::kParseError,
                  "expected " + std::to_string(cols.size()) + " fields, got " + std::to_string(fields.size()), source,
                  line_no);
  row->line = line_no;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    if (cols[k].kind == ProbeptsColumn::kArtifact || cols[k].kind == ProbeptsColumn::kFace) {
      const bool artifact = cols[k].kind == ProbeptsColumn::kArtifact;
      if (fields[k].empty())
        return Status(StatusCode::kParseError,
                      "field " + std::to_string(k + 1) + ": empty " + (artifact ? "artifact" : "face") +
                          " (expected a name of the artifact YAML" + (artifact ? ")" : ": +X, -X, +Y, -Y or +Z)"),
                      source, line_no);
      (artifact ? row->artifact : row->face) = std::string(fields[k]);
      continue;
    }
    const auto v = ProbeptsNumber(fields[k]);
    if (!v)
      return Status(StatusCode::kParseError,
                    "field " + std::to_string(k + 1) + ": expected a finite number, got '" + EchoInput(fields[k], 40) +
                        "'",
                    source, line_no);
    switch (cols[k].kind) {
      case ProbeptsColumn::kRotary: row->rotary_deg[cols[k].axis] = *v; break;
      case ProbeptsColumn::kX: row->point_mm.x() = *v; break;
      case ProbeptsColumn::kY: row->point_mm.y() = *v; break;
      case ProbeptsColumn::kZ: row->point_mm.z() = *v; break;
      case ProbeptsColumn::kI: row->approach.x() = *v; break;
      case ProbeptsColumn::kJ: row->approach.y() = *v; break;
      case ProbeptsColumn::kK: row->approach.z() = *v; break;
      case ProbeptsColumn::kTime: row->t_s = *v; break;
      case ProbeptsColumn::kUncertainty: row->u_um = *v; break;
      case ProbeptsColumn::kArtifact:
      case ProbeptsColumn::kFace: break;
    }
  }
  const double norm = row->approach.norm();
  if (!(std::abs(norm - 1.0) <= kProbeptsUnitTol))
    return Status(StatusCode::kParseError,
                  "approach (i, j, k) has length " + ProbeptsFormatNumber(norm) +
                      "; expected a unit vector (to 1e-6) toward the surface",
                  source, line_no);
  if (row->u_um < 0.0)
    return Status(StatusCode::kParseError, "u_um " + ProbeptsFormatNumber(row->u_um) + ": expected >= 0", source,
                  line_no);
  return Status::Ok();
}

}  // namespace

Result<ProbePointFile> ParseProbePoints(std::string_view text, const std::string& source) {
  ProbePointFile file;
  file.source = source;
  std::optional<std::vector<ProbeptsHeaderColumn>> cols;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = ProbeptsTrim(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++line_no;
    if (line_no == 1) {
      if (line != "# tpcal probepts v1")
        return Status(StatusCode::kParseError, "expected '# tpcal probepts v1' on the first line", source, 1);
      continue;
    }
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::string_view body = ProbeptsTrim(line.substr(1));
      if (body.rfind("units:", 0) == 0 && ProbeptsTrim(body.substr(6)) != "mm")
        return Status(StatusCode::kParseError, "units: only mm is supported", source, line_no);
      if (body.rfind("plan:", 0) == 0) file.is_plan = true;
      continue;
    }
    if (!cols) {
      auto h = ProbeptsParseHeader(line, source, line_no, &file);
      if (!h.ok()) return h.status();
      cols = std::move(*h);
      continue;
    }
    ProbePointRow row;
    if (Status s = ProbeptsParseRow(line, *cols, source, line_no, &row); !s.ok()) return s;
    file.rows.push_back(std::move(row));
  }
  if (line_no == 0) return Status(StatusCode::kParseError, "empty file: expected '# tpcal probepts v1'", source, 1);
  if (file.rows.empty()) return Status(StatusCode::kParseError, "no probed points", source, line_no);
  return file;
}

Result<ProbePointFile> ReadProbePoints(const std::string& path) {
  auto bytes = ReadFileBytes(path, kProbeptsMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParseProbePoints(bytes->view(), path);
}

std::string FormatProbePoints(const ProbePointFile& file) {
  std::string out = "# tpcal probepts v1\n# units: mm\n";
  if (file.is_plan) out += "# plan: nominal contact points\n";
  for (char a : file.rotary_axes) out += std::string(1, a) + "_deg,";
  out += "artifact,face,x,y,z,i,j,k";
  if (file.has_t) out += ",t_s";
  if (file.has_u) out += ",u_um";
  out += '\n';
  for (const ProbePointRow& r : file.rows) {
    for (char a : file.rotary_axes) {
      const auto it = r.rotary_deg.find(a);
      out += ProbeptsFormatNumber(it == r.rotary_deg.end() ? 0.0 : it->second) + ",";
    }
    out += r.artifact + "," + r.face;
    for (int c = 0; c < 3; ++c) out += "," + ProbeptsFormatNumber(r.point_mm[c]);
    for (int c = 0; c < 3; ++c) out += "," + ProbeptsFormatNumber(r.approach[c]);
    if (file.has_t) out += "," + ProbeptsFormatNumber(r.t_s);
    if (file.has_u) out += "," + ProbeptsFormatNumber(r.u_um);
    out += '\n';
  }
  return out;
}

}  // namespace tpcal::pipeline
