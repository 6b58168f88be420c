// Format dispatch, option validation and small helpers of point_io.h.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "core/ascii.h"
#include "core/input_echo.h"
#include "pipeline/io/dmis_reader.h"
#include "pipeline/io/internal/point_table_header.h"
#include "pipeline/io/point_io.h"
#include "pipeline/io/qif_reader.h"
#include "pipeline/io/xyzijk_reader.h"

namespace tpcal::pipeline {

const char* PointFormatName(PointFormat format) {
  switch (format) {
    case PointFormat::kAuto: return "auto";
    case PointFormat::kCsv: return "csv";
    case PointFormat::kPly: return "ply";
    case PointFormat::kPcd: return "pcd";
    case PointFormat::kXyz: return "xyz";
    case PointFormat::kQif: return "qif";
    case PointFormat::kDmis: return "dmis";
    case PointFormat::kXyzijk: return "xyzijk";
  }
  return "unknown";
}

PointFormat PointFormatFromExtension(const std::string& path) {
  const std::string ext = AsciiLower(std::filesystem::path(path).extension().string());
  if (ext == ".csv" || ext == ".tsv") return PointFormat::kCsv;
  if (ext == ".ply") return PointFormat::kPly;
  if (ext == ".pcd") return PointFormat::kPcd;
  if (ext == ".xyz" || ext == ".txt") return PointFormat::kXyz;
  if (ext == ".qif") return PointFormat::kQif;
  if (ext == ".dmo") return PointFormat::kDmis;
  return PointFormat::kAuto;
}

Status PointReadOptions::Validate() const {
  if (threads < 0)
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("threads = {}: expected 0 (all hardware threads) or more", threads));
  if (!(normal_tolerance >= 0.0 && normal_tolerance < 1.0))
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("normal_tolerance = {}: expected a value in [0, 1)", normal_tolerance));
  for (std::size_t a = 0; a < columns.size(); ++a) {
    const auto& [role, name] = columns[a];
    if (!internal::IsTableRole(role))
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("column role '{}': expected one of feature, x, y, z, i, j, k", EchoInput(role)));
    if (name.empty())
      return Status(StatusCode::kInvalidArgument, fmt::format("column role '{}' has no column name", role));
    for (std::size_t b = 0; b < a; ++b) {
      if (columns[b].first == role)
        return Status(StatusCode::kInvalidArgument, fmt::format("column role '{}' is mapped twice", role));
      if (AsciiLower(columns[b].second) == AsciiLower(name))
        return Status(StatusCode::kInvalidArgument,
                      fmt::format("column '{}' is mapped to both {} and {}", EchoInput(name), columns[b].first, role));
    }
  }
  return Status::Ok();
}

Result<std::vector<std::pair<std::string, std::string>>> ParsePointColumns(const std::vector<std::string>& args) {
  PointReadOptions check;
  for (const std::string& a : args) {
    const std::size_t eq = a.find('=');
    if (eq == std::string::npos)
      return Status(StatusCode::kInvalidArgument,
                    fmt::format("--column '{}': expected ROLE=NAME (e.g. feature=Name, x=X)", EchoInput(a)));
    check.columns.emplace_back(AsciiLower(a.substr(0, eq)), a.substr(eq + 1));
  }
  if (Status s = check.Validate(); !s.ok()) return Status(s.code(), "--column: " + s.message());
  return check.columns;
}

Status PointWriteOptions::Validate() const {
  if (fixed_decimals < -1 || fixed_decimals > 17)
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("fixed_decimals = {}: expected -1 (shortest exact) or 0..17",
                              fixed_decimals));
  if (kind == PointFileKind::kUntagged)
    return Status(StatusCode::kInvalidArgument,
                  "written point files are always tagged: kind must be kPoints or kPlan");
  return Status::Ok();
}

Result<PointFile> ReadPointFile(const std::string& path, const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  PointFormat format = options.format;
  if (format == PointFormat::kAuto) format = PointFormatFromExtension(path);
  if (!options.columns.empty() && format != PointFormat::kCsv && format != PointFormat::kAuto)
    return internal::ColumnMappingNeedsTable(path);
  switch (format) {
    case PointFormat::kCsv: return ReadPointCsv(path, options);
    case PointFormat::kPly: return ReadPointPly(path, options);
    case PointFormat::kPcd: return ReadPointPcd(path, options);
    case PointFormat::kXyz: return IsXyzijkFile(path) ? ReadPointXyzijk(path, options) : ReadPointXyz(path, options);
    case PointFormat::kQif: return ReadPointQif(path, options);
    case PointFormat::kDmis: return ReadPointDmis(path, options);
    case PointFormat::kXyzijk: return ReadPointXyzijk(path, options);
    case PointFormat::kAuto: break;
  }
  return Status(StatusCode::kInvalidArgument,
                fmt::format("unknown point file extension '{}': expected .csv, .tsv, .ply, .pcd, "
                            ".xyz, .txt, .qif or .dmo (or give the format explicitly)",
                            std::filesystem::path(path).extension().string()),
                path);
}

Result<PointSet> ReadPoints(const std::string& path, const PointReadOptions& options) {
  Result<PointFile> file = ReadPointFile(path, options);
  if (!file.ok()) return file.status();
  return std::move(file->points);
}

std::size_t FirstLineOfFeature(const PointSet& points, int feature_index) {
  for (std::size_t i = 0; i < points.feature.size(); ++i)
    if (points.feature[i] == feature_index) return points.LineOf(i);
  return 0;
}

Status AtFeature(const PointSet& points, int feature_index, const Status& status) {
  return status.WithLocation(points.source, FirstLineOfFeature(points, feature_index));
}

}  // namespace tpcal::pipeline
