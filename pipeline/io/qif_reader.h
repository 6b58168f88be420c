// QIF 3.0 measurement results (docs/formats/qif.md): the measured points of every
// <MeasuredPointSet>, labelled by the feature whose measurement's <PointList> refers to them
// (<FeatureItemId> -> the feature item's <FeatureName>), in mm. Parsed with libxml2's SAX2
// parser, so a scan of 10^6 points is never held as a DOM and its <Points> text is read in place.
//
// Rules (docs/formats/qif.md states each):
//  * Units from <FileUnits><PrimaryUnits><LinearUnit>: <UnitConversion><Factor> (to metres)
//    when given, else a known <UnitName> (mm, cm, m, inch, ft, um). No linear unit, an unknown
//    unit name or a non-metre SI unit is an error.
//  * <PointList>: <WholePointSetId> (all points), <RangePointSetId range="a b"> (points a..b,
//    1-based, inclusive), <SinglePointSetId index="k"> (point k). Points are emitted in the
//    order of the feature measurements, then of their PointList entries; points of a set that
//    no entry covers are dropped; a point two entries cover is emitted twice.
//  * <Compensated>false</Compensated> with a <ProbeRadius>: points are probe centres. With
//    <Normals> (unit, out of the material) each point is moved by -radius along its normal and
//    the amount is kept as the attribute `probe_compensation_mm`; without normals the file is
//    refused (QifReadOptions::accept_uncompensated reads the centres as they are). No
//    <Compensated> element: the points are taken as compensated.
//  * A point set no feature measurement refers to, a PointList naming a missing point set, a
//    feature measurement without <FeatureItemId> or naming no feature item, a feature item
//    without <FeatureName>: errors (QifReadOptions::lenient_references keeps unreferenced sets
//    as unlabelled points and skips dangling references).
//  * Normals are kept only if every emitted point has one. <PointsBinary> is not supported.
//  * A <!DOCTYPE> is refused (XML_PARSE_HUGE, needed for scans, lifts entity limits).
// Errors are kParseError statuses `file:line: what was expected`; libxml2's own messages
// (unclosed tags, bad characters) carry its line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {

struct QifReadOptions {
  // Read uncompensated point sets without normals as probe centres instead of refusing them.
  bool accept_uncompensated = false;
  // Unreferenced point sets become unlabelled points; PointList entries naming a missing set
  // are skipped. Off: both are errors.
  bool lenient_references = false;
  // Threads parsing the numbers of a large plain <Points>/<Normals> text (128 KiB or more per
  // thread): 0 = all threads (core's limit), 1 = serial. The result does not depend on it.
  int threads = 0;
};

// What the reader did, for messages and tests.
struct QifReport {
  double mm_per_unit = 1.0;        // file length unit in mm
  std::string unit_name;           // as written (<UnitName>)
  std::size_t point_sets = 0;      // <MeasuredPointSet> elements read
  std::size_t sets_compensated_by_reader = 0;  // moved by -ProbeRadius along their normals
  std::size_t sets_read_as_centres = 0;        // accept_uncompensated
  std::size_t unreferenced_sets = 0;           // lenient_references
  std::size_t dropped_points = 0;              // in sets but outside every referenced range
};

struct QifFile {
  PointFile file;
  QifReport report;
};

// From text in memory (the fuzz entry point); `source_name` names the file in errors and
// becomes PointSet::source. Never throws.
Result<QifFile> ParseQif(std::string_view text, const std::string& source_name,
                         const QifReadOptions& qif_options = {});

// The point_io.h dispatch entry points (default QifReadOptions).
Result<PointFile> ParsePointQif(std::string_view text, const std::string& source_name,
                                const PointReadOptions& options = {});
Result<PointFile> ReadPointQif(const std::string& path, const PointReadOptions& options = {});

// A minimal QIF 3.0 results document holding `points` (mm): one OtherShapeFeatureItem and
// measurement per feature label, one MeasuredPointSet per feature (with Normals when the set
// has them, Compensated true). Numbers in shortest exact form, so ParseQif gives back the same
// doubles. Unlabelled points go into a set named "unlabelled". Not schema-validated.
std::string FormatPointQif(const PointSet& points);

}  // namespace tpcal::pipeline
