#include "pipeline/io/probepts_io.h"

#include <cmath>

#include "core/input_echo.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/internal/instrument_csv.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a Probepts prefix: a unity build merges this file with the other readers
// of pipeline/io.

constexpr double kProbeptsUnitTol = 1e-6;  // |(i, j, k)| - 1, the header's contract

enum ProbeptsColumn { kProbeptsArtifact, kProbeptsFace, kProbeptsX, kProbeptsY, kProbeptsZ, kProbeptsI, kProbeptsJ,
                      kProbeptsK, kProbeptsTime, kProbeptsUncertainty };

const internal::InstrumentCsvFormat& ProbeptsFormat() {
  static const internal::InstrumentCsvFormat kFormat{
      "# tpcal probepts v1",
      {{"artifact", kProbeptsArtifact, true, true},
       {"face", kProbeptsFace, true, true},
       {"x", kProbeptsX, true, false},
       {"y", kProbeptsY, true, false},
       {"z", kProbeptsZ, true, false},
       {"i", kProbeptsI, true, false},
       {"j", kProbeptsJ, true, false},
       {"k", kProbeptsK, true, false},
       {"t_s", kProbeptsTime, false, false},
       {"u_um", kProbeptsUncertainty, false, false}},
      true,
      "A_deg, B_deg, C_deg, artifact, face, x, y, z, i, j, k and optionally t_s, u_um",
      "header needs artifact, face, x, y, z, i, j, k and at least one of A_deg, B_deg, C_deg",
      "no probed points",
      EchoInput};
  return kFormat;
}

}  // namespace

Result<ProbePointFile> ParseProbePoints(std::string_view text, const std::string& source) {
  ProbePointFile file;
  file.source = source;
  internal::InstrumentCsvRows rows;
  rows.begin = [&](std::size_t line) { file.rows.emplace_back().line = line; };
  rows.text = [&](const internal::InstrumentCsvHeaderColumn& column, std::string_view field) -> Status {
    const bool artifact = column.id == kProbeptsArtifact;
    if (field.empty())
      return Status(StatusCode::kParseError, std::string("empty ") + (artifact ? "artifact" : "face") +
                                                 " (expected a name of the artifact YAML" +
                                                 (artifact ? ")" : ": +X, -X, +Y, -Y or +Z)"));
    (artifact ? file.rows.back().artifact : file.rows.back().face) = std::string(field);
    return Status::Ok();
  };
  rows.number = [&](const internal::InstrumentCsvHeaderColumn& column, double v) {
    ProbePointRow& row = file.rows.back();
    switch (column.id) {
      case internal::kInstrumentCsvRotary: row.rotary_deg[column.axis] = v; break;
      case kProbeptsX: row.point_mm.x() = v; break;
      case kProbeptsY: row.point_mm.y() = v; break;
      case kProbeptsZ: row.point_mm.z() = v; break;
      case kProbeptsI: row.approach.x() = v; break;
      case kProbeptsJ: row.approach.y() = v; break;
      case kProbeptsK: row.approach.z() = v; break;
      case kProbeptsTime: row.t_s = v; break;
      case kProbeptsUncertainty: row.u_um = v; break;
    }
  };
  rows.end = [&]() -> Status {
    const ProbePointRow& row = file.rows.back();
    const double norm = row.approach.norm();
    if (!(std::abs(norm - 1.0) <= kProbeptsUnitTol))
      return Status(StatusCode::kParseError, "approach (i, j, k) has length " + internal::FormatCsvNumber(norm) +
                                                 "; expected a unit vector (to 1e-6) toward the surface");
    if (row.u_um < 0.0)
      return Status(StatusCode::kParseError, "u_um " + internal::FormatCsvNumber(row.u_um) + ": expected >= 0");
    return Status::Ok();
  };
  auto header = internal::ReadInstrumentCsv(text, source, ProbeptsFormat(), rows);
  if (!header.ok()) return header.status();
  file.rotary_axes = header->rotary_axes;
  file.has_t = header->Has(kProbeptsTime);
  file.has_u = header->Has(kProbeptsUncertainty);
  file.is_plan = header->plan;
  return file;
}

Result<ProbePointFile> ReadProbePoints(const std::string& path) {
  auto bytes = ReadFileBytes(path, internal::kInstrumentCsvMaxLineBytes);
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
      out += internal::FormatCsvNumber(it == r.rotary_deg.end() ? 0.0 : it->second) + ",";
    }
    out += r.artifact + "," + r.face;
    for (int c = 0; c < 3; ++c) out += "," + internal::FormatCsvNumber(r.point_mm[c]);
    for (int c = 0; c < 3; ++c) out += "," + internal::FormatCsvNumber(r.approach[c]);
    if (file.has_t) out += "," + internal::FormatCsvNumber(r.t_s);
    if (file.has_u) out += "," + internal::FormatCsvNumber(r.u_um);
    out += '\n';
  }
  return out;
}

}  // namespace tpcal::pipeline
