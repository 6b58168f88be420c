// DMIS 5.x output files (`.dmo`, docs/formats/dmis.md): the point actuals
// `FA(label)=FEAT/POINT,CART,x,y,z,i,j,k` and `FEAT/POINT,POL,r,a,h,i,j,k` (in the WKPLAN work
// plane) become points (mm, unit normals), labelled by the feature the label names.
//
// Label -> feature: tpcal's DMIS program (testpieces/dmis_program.h) names the k-th planned
// point of feature F `F_k`, so one trailing `_<digits>` is stripped (`S_R_12` -> `S_R`,
// `H1_3` -> `H1`); a label without that suffix is the feature itself.
// Statements: `$$` starts a comment (outside quotes), a line ending in `$` continues on the
// next; keywords are case-insensitive (labels keep their case); blanks outside quotes are
// ignored. `UNITS/MM|CM|METER|INCH|FEET,ANGDEC|ANGDMS|ANGRAD[,...]` sets the length and angle
// units of the statements after it (default mm, degrees), `WKPLAN/XYPLAN|YZPLAN|ZXPLAN` the plane
// of polar points; `FILNAM/'name',version` is recorded. Feature actuals of
// other types (`FEAT/CIRCLE`, `PLANE`, `CYLNDR`, ...) are skipped and counted: tpcal fits its
// features from the points. Other statements (MEAS, PTMEAS, OUTPUT, ...) are ignored.
// Errors are kParseError `file:line: what was expected` at the statement's first line: a
// point actual with fewer or more than six numbers, a polar point under ANGDMS or in a work
// plane other than XYPLAN/YZPLAN/ZXPLAN, an unknown unit, a label
// not in DmisReadOptions::known_features, a `$` continuation at the end of the file.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {

struct DmisReadOptions {
  // The features a label may name (e.g. a piece's plan); empty: any label is accepted.
  std::vector<std::string> known_features;
  double normal_tolerance = 1e-3;  // as PointReadOptions::normal_tolerance
};

struct DmisReport {
  std::string filnam;                             // FILNAM name, if any
  LengthUnit units = LengthUnit::kMm;             // the last UNITS seen
  std::map<std::string, std::size_t> skipped_actuals;  // FEAT type -> count (CIRCLE, PLANE, ...)
};

struct DmisFile {
  PointFile file;
  DmisReport report;
};

// The feature a DMIS point label belongs to (one trailing `_<digits>` stripped).
std::string DmisFeatureOfLabel(std::string_view label);

// From text in memory (the fuzz entry point); `source_name` is used in errors and as
// PointSet::source.
Result<DmisFile> ParseDmisOutput(std::string_view text, const std::string& source_name,
                                 const DmisReadOptions& dmis_options = {});

// The point_io.h dispatch entry points (no known_features check).
Result<PointFile> ParsePointDmis(std::string_view text, const std::string& source_name,
                                 const PointReadOptions& options = {});
Result<PointFile> ReadPointDmis(const std::string& path, const PointReadOptions& options = {});

}  // namespace tpcal::pipeline
