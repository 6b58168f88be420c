#include "pipeline/io/ballbar_io.h"

#include "core/input_echo.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/internal/instrument_csv.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a Ballbar prefix: a unity build merges this file with the other readers
// of pipeline/io.

enum BallbarColumn { kBallbarSetup, kBallbarAngle, kBallbarDl, kBallbarDirection, kBallbarTime };

const internal::InstrumentCsvFormat& BallbarFormat() {
  static const internal::InstrumentCsvFormat kFormat{"# tpcal ballbar v1",
                                                     {{"setup", kBallbarSetup, true, true},
                                                      {"angle_deg", kBallbarAngle, true, false},
                                                      {"dl_um", kBallbarDl, true, false},
                                                      {"direction", kBallbarDirection, false, true},
                                                      {"t_s", kBallbarTime, false, false}},
                                                     false,
                                                     "setup, angle_deg, dl_um and optionally direction, t_s",
                                                     "header needs setup, angle_deg and dl_um",
                                                     "no readings",
                                                     EchoInput};
  return kFormat;
}

}  // namespace

Result<BallbarFile> ParseBallbar(std::string_view text, const std::string& source) {
  BallbarFile file;
  file.source = source;
  internal::InstrumentCsvRows rows;
  rows.begin = [&](std::size_t line) { file.rows.emplace_back().line = line; };
  rows.text = [&](const internal::InstrumentCsvHeaderColumn& column, std::string_view field) -> Status {
    BallbarRow& row = file.rows.back();
    if (column.id == kBallbarSetup) {
      if (field.empty())
        return Status(StatusCode::kParseError, "empty setup (expected an installation of the set-up YAML)");
      if (field.front() == '#')
        return Status(StatusCode::kParseError,
                      "setup '" + EchoInput(field, 40) + "' starts with '#' (a line so written is a comment)");
      row.setup = std::string(field);
    } else if (field == "cw") {
      row.direction = BallbarDirection::kCw;
    } else if (field == "ccw") {
      row.direction = BallbarDirection::kCcw;
    } else {
      return Status(StatusCode::kParseError, "direction '" + EchoInput(field, 40) + "': expected cw or ccw");
    }
    return Status::Ok();
  };
  rows.number = [&](const internal::InstrumentCsvHeaderColumn& column, double v) {
    BallbarRow& row = file.rows.back();
    if (column.id == kBallbarAngle) row.angle_deg = v;
    if (column.id == kBallbarDl) row.dl_um = v;
    if (column.id == kBallbarTime) row.t_s = v;
  };
  rows.end = [] { return Status::Ok(); };
  auto header = internal::ReadInstrumentCsv(text, source, BallbarFormat(), rows);
  if (!header.ok()) return header.status();
  file.has_direction = header->Has(kBallbarDirection);
  file.has_t = header->Has(kBallbarTime);
  return file;
}

Result<BallbarFile> ReadBallbar(const std::string& path) {
  auto bytes = ReadFileBytes(path, internal::kInstrumentCsvMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParseBallbar(bytes->view(), path);
}

std::string FormatBallbar(const BallbarFile& file) {
  std::string out = "# tpcal ballbar v1\n# units: mm\nsetup,angle_deg,dl_um";
  if (file.has_direction) out += ",direction";
  if (file.has_t) out += ",t_s";
  out += '\n';
  for (const BallbarRow& r : file.rows) {
    out += r.setup + "," + internal::FormatCsvNumber(r.angle_deg) + "," + internal::FormatCsvNumber(r.dl_um);
    if (file.has_direction) out += std::string(",") + (r.direction == BallbarDirection::kCw ? "cw" : "ccw");
    if (file.has_t) out += "," + internal::FormatCsvNumber(r.t_s);
    out += '\n';
  }
  return out;
}

}  // namespace tpcal::pipeline
