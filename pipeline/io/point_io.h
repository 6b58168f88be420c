// Point-cloud input and output: the `tpcal points v1` / `tpcal plan v1` CSV files of the
// formats docs/formats/points.md and docs/formats/probing_plan.md, PLY and PCD through PCL,
// plain `x y z [i j k]` text. Every PointSet returned is in mm
// (inch files are converted on read) with unit normals (or none).
//
// CSV dialect (decisions this reader makes where the contract is silent):
//  * A line whose first non-blank character is `#` is a comment, anywhere in the file. Blank
//    lines (and lines holding only commas and blanks, as spreadsheets export) are skipped.
//    LF or CRLF line ends; a UTF-8 byte-order mark is skipped; bare-CR files are rejected.
//  * Directives in comments before the header: `# units: mm` | `# units: in` (keyword and value
//    case-insensitive, the colon optional; a comment whose first word is `units` is always a
//    directive, so a misspelt unit is an error, never silently mm); `# tpcal points v1` or
//    `# tpcal plan v1` (any other `# tpcal <kind> v<n>` tag is an error). Two different units
//    directives, or a units directive after the header, are errors.
//  * Header names are matched case-insensitively after trimming blanks, so `X` is `x`; unknown
//    columns keep their spelling as attribute names. Duplicate names (case-insensitive) are an
//    error. `feature,x,y,z` are required, `i,j,k` optional but all three or none. An empty name
//    is an error except as the very last column (a trailing comma), which is then ignored.
//  * Other software's tables (internal/point_table_header.h): the separator is ',' unless only
//    ';' or a tab gives the header its required columns; ';' and tab tables also take decimal
//    commas; `name`, `label`, ... stand for `feature` and `nx,ny,nz` for `i,j,k` when the
//    contract names are absent. `.tsv` files are read as CSV.
//  * Cells are trimmed of blanks. A cell may be enclosed in double quotes (separators inside are
//    kept); doubled quotes inside a quoted cell and quotes spanning lines are not supported.
//  * Numbers: decimal or scientific, optional leading `+`, parsed with fast_float (correctly
//    rounded). NaN, inf and out-of-range values are errors in x,y,z,i,j,k.
//  * Normals: zero length (< 1e-12) is an error; a length within `normal_tolerance` (default
//    1e-3) of 1 is normalised (CMM exports print 4-6 decimals); any other length is an error.
//  * Labels: the `feature` cell, trimmed. Empty = unlabelled (PointSet::kUnlabelled); a file
//    whose labels are all empty is a raw scan. Mixed files are allowed (empty rows unlabelled).
//  * Attributes (unknown columns): numeric if every cell parses as a finite number, otherwise
//    the whole column is kept as text. Attributes are never unit-converted.
//  * Every row must have exactly as many cells as the header.
// Errors are kParseError statuses carrying the file name and the 1-based line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"

namespace tpcal::pipeline {

enum class PointFormat { kAuto, kCsv, kPly, kPcd, kXyz, kQif, kDmis, kXyzijk };
enum class LengthUnit { kMm, kInch };
// Which tag the file carried: `# tpcal points v1`, `# tpcal plan v1`, or none.
enum class PointFileKind { kUntagged, kPoints, kPlan };

const char* PointFormatName(PointFormat format);
// Format from the file extension (case-insensitive): .csv/.tsv, .ply, .pcd, .xyz/.txt, .qif
// (qif_reader.h), .dmo (dmis_reader.h); else kAuto. A .xyz/.txt file whose first line is
// `XYZIJK` is read as PC-DMIS XYZIJK text (dmis_reader.h).
PointFormat PointFormatFromExtension(const std::string& path);

struct PointReadOptions {
  PointFormat format = PointFormat::kAuto;  // kAuto: choose by extension (error if unknown)
  // Text chunks parsed in parallel on the shared pool: 0 = one per thread (core/parallel.h), 1 = serial.
  // The text is split into that many chunks at line boundaries.
  int threads = 0;
  // Do not make chunks smaller than this (bytes); small files are parsed serially.
  std::size_t min_chunk_bytes = std::size_t{1} << 20;
  // Normals whose length is within this of 1 are normalised; others are errors.
  double normal_tolerance = 1e-3;
  // Units of PLY, PCD and xyz files that carry no `# units:` directive (CSV default is mm
  // by the contract and is not affected).
  LengthUnit assumed_units = LengthUnit::kMm;
  // PLY/PCD only: drop points with a NaN/inf coordinate (organised scans use NaN for "no
  // return") instead of failing.
  bool skip_nonfinite_points = false;
  // CSV/TSV tables only: the header's name of a column for a role (feature, x, y, z, i, j, k),
  // over the contract names and their aliases (docs/formats/points.md, "Column mapping"). Names
  // match case-insensitively. Set from `--column ROLE=NAME` (ParsePointColumns) or a pipeline's
  // `columns:`.
  std::vector<std::pair<std::string, std::string>> columns;

  // Errors (kInvalidArgument): threads < 0, normal_tolerance outside [0, 1), a column role that
  // is not one of the seven, a role or a name given twice, an empty name.
  Status Validate() const;
};

// `--column` values (ROLE=NAME each) as PointReadOptions::columns. kInvalidArgument naming the
// value when it has no '=', an unknown role, an empty name, or a role given twice.
Result<std::vector<std::pair<std::string, std::string>>> ParsePointColumns(const std::vector<std::string>& args);

struct PointFileInfo {
  PointFormat format = PointFormat::kAuto;
  PointFileKind kind = PointFileKind::kUntagged;
  LengthUnit source_units = LengthUnit::kMm;  // units of the file (data returned in mm)
  std::uint64_t bytes = 0;                     // size of the source file
  int chunks = 1;  // text chunks parsed in parallel (1 = serial)
};

struct PointFile {
  PointSet points;
  PointFileInfo info;
};

// Reads any supported point file; the format comes from options.format or the extension.
// PointSet::source is set to `path`.
Result<PointFile> ReadPointFile(const std::string& path, const PointReadOptions& options = {});
Result<PointSet> ReadPoints(const std::string& path, const PointReadOptions& options = {});

// CSV (docs/formats/points.md, docs/formats/probing_plan.md) from a file or from text already in memory; `source_name`
// is used in errors and as PointSet::source.
Result<PointFile> ReadPointCsv(const std::string& path, const PointReadOptions& options = {});
Result<PointFile> ParsePointCsv(std::string_view text, const std::string& source_name,
                                const PointReadOptions& options = {});

// Plain text: one point per line, `x y z` or `x y z i j k`, separated by blanks and/or commas;
// `#` comments (with the same `# units:` directive as CSV). The first data line fixes the
// column count (3 or 6); every line must match it. All points unlabelled.
Result<PointFile> ReadPointXyz(const std::string& path, const PointReadOptions& options = {});
Result<PointFile> ParsePointXyz(std::string_view text, const std::string& source_name,
                                const PointReadOptions& options = {});

// PLY / PCD through PCL (pcl::io::loadPLYFile / loadPCDFile into a PCLPointCloud2, so double
// properties keep double precision). Fields x,y,z required; normal_x/y/z (PLY nx/ny/nz) used
// as normals when all three are present; other single-valued numeric fields become numeric
// attributes. No labels (raw scan). PCL's console output is silenced during the call.
Result<PointFile> ReadPointPly(const std::string& path, const PointReadOptions& options = {});
Result<PointFile> ReadPointPcd(const std::string& path, const PointReadOptions& options = {});

struct PointWriteOptions {
  PointFileKind kind = PointFileKind::kPoints;  // tag line; kPlan requires normals
  // Number format for x,y,z,i,j,k and numeric attributes. -1 (default): shortest text that
  // reads back to the identical double (std::to_chars), so write->read is bit-exact.
  // n >= 0: fixed with n decimals (6 = 1 nm for mm), smaller files, not bit-exact.
  int fixed_decimals = -1;
  bool binary = true;  // PLY/PCD: binary (exact doubles) or ASCII

  Status Validate() const;
};

// The contract CSV: `# tpcal points v1` (or plan), `# units: mm`, header
// `feature,x,y,z[,i,j,k][,attributes...]`, one row per point. Text cells that contain a
// comma, start with `#` or have outer blanks are quoted; a cell containing `"`, CR or LF
// cannot be represented and is a kInvalidArgument error.
Result<std::string> FormatPointCsv(const PointSet& points, const PointWriteOptions& options = {});
// Same, written atomically (temp file + rename, see atomic_file.h).
Status WritePointCsv(const std::string& path, const PointSet& points,
                     const PointWriteOptions& options = {});

// PLY / PCD, atomically: x,y,z, normals (PLY: nx,ny,nz; PCD: normal_x,y,z) and numeric
// attributes as float64 fields, so write -> read is bit-exact. Binary PLY and both PCD
// flavours are written by PCL; ASCII PLY by tpcal (PCL 1.13 prints doubles to 6 digits).
// Feature labels and text attributes are not representable and are dropped.
Status WritePointPly(const std::string& path, const PointSet& points,
                     const PointWriteOptions& options = {});
Status WritePointPcd(const std::string& path, const PointSet& points,
                     const PointWriteOptions& options = {});

// ---- helpers for later stages ----------------------------------------------------------
// 1-based source line of the first point labelled `feature_index`, or 0 if none/unknown
// (PLY/PCD points have no lines). For errors such as "feature S4 has 2 points, a plane
// needs 3" to cite a line.
std::size_t FirstLineOfFeature(const PointSet& points, int feature_index);
// `status` located at points.source and the first line of that feature.
Status AtFeature(const PointSet& points, int feature_index, const Status& status);

}  // namespace tpcal::pipeline
