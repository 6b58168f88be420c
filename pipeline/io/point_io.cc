// Format dispatch, option validation and small helpers of point_io.h.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "core/ascii.h"
#include "pipeline/io/dmis_reader.h"
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
  return Status::Ok();
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
