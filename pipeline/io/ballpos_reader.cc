#include "pipeline/io/ballpos_reader.h"

#include "pipeline/io/file_bytes.h"
#include "pipeline/io/internal/instrument_csv.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a Ballpos prefix: a unity build merges this file with the other readers
// of pipeline/io.

enum BallposColumn { kBallposX, kBallposY, kBallposZ, kBallposBall, kBallposTime, kBallposUncertainty };

// Column names and fields are quoted as they are, cut at max_bytes (not through EchoInput).
std::string BallposEcho(std::string_view bytes, std::size_t max_bytes) {
  return std::string(bytes.substr(0, max_bytes));
}

const internal::InstrumentCsvFormat& BallposFormat() {
  static const internal::InstrumentCsvFormat kFormat{"# tpcal ballpos v1",
                                                     {{"x", kBallposX, true, false},
                                                      {"y", kBallposY, true, false},
                                                      {"z", kBallposZ, true, false},
                                                      {"ball", kBallposBall, false, true},
                                                      {"t_s", kBallposTime, false, false},
                                                      {"u_um", kBallposUncertainty, false, false}},
                                                     true,
                                                     "A_deg, B_deg, C_deg, x, y, z and optionally ball, t_s, u_um",
                                                     "header needs x, y, z and at least one of A_deg, B_deg, C_deg",
                                                     "no ball positions",
                                                     BallposEcho};
  return kFormat;
}

}  // namespace

Result<BallPositionFile> ParseBallPositions(std::string_view text, const std::string& source) {
  BallPositionFile file;
  file.source = source;
  internal::InstrumentCsvRows rows;
  rows.begin = [&](std::size_t line) { file.rows.emplace_back().line = line; };
  rows.text = [&](const internal::InstrumentCsvHeaderColumn&, std::string_view field) {
    file.rows.back().ball = std::string(field.substr(0, 64));
    return Status::Ok();
  };
  rows.number = [&](const internal::InstrumentCsvHeaderColumn& column, double v) {
    BallPositionRow& row = file.rows.back();
    switch (column.id) {
      case internal::kInstrumentCsvRotary: row.rotary_deg[column.axis] = v; break;
      case kBallposX: row.centre_mm.x() = v; break;
      case kBallposY: row.centre_mm.y() = v; break;
      case kBallposZ: row.centre_mm.z() = v; break;
      case kBallposTime: row.t_s = v; break;
      case kBallposUncertainty: row.u_um = v; break;
    }
  };
  rows.end = [] { return Status::Ok(); };
  auto header = internal::ReadInstrumentCsv(text, source, BallposFormat(), rows);
  if (!header.ok()) return header.status();
  file.rotary_axes = header->rotary_axes;
  return file;
}

Result<BallPositionFile> ReadBallPositions(const std::string& path) {
  auto bytes = ReadFileBytes(path, internal::kInstrumentCsvMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParseBallPositions(bytes->view(), path);
}

}  // namespace tpcal::pipeline
