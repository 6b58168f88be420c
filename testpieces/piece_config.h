// Test-piece configuration files (`tpcal ... --config TP.yaml`, schema tpcal.testpiece/1):
// every parameter of the piece, the probing density and the time model, units in the key names.
// Defaults are the paper's / our documented choices (testpieces/README.md), so an empty map (or
// just `piece: turning`) is the seed 002 piece. Unknown or duplicate keys, wrong types and
// invalid values are errors "file:line: what was expected". yaml-cpp stays in the .cc.
//
//   schema: tpcal.testpiece/1        # optional; if present must be this
//   piece: turning                   # turning | iso10791_m1 | iso10791_m2 | cone_frustum
//   turning:                         # the section named like `piece` (others are errors)
//     groove: {bottom_z_mm: 405.702, depth_mm: 5, outer_radius_mm: 119, ...}
//     holes: {count: 16, pitch_radius_mm: 140, ...}
//     steps: [{radius_mm: 160, shoulder_z_mm: 395.702, probe_z_mm: 400.702}, ...]  # 6 entries
//     ...
//   probing: {points_per_circle: 16, levels_per_face: 1, ...}
//   process: {rapid_mm_per_min: 20000, ...}
// FormatPieceConfig writes every key (testpieces/README.md lists them with their meaning).
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

// `source` names the text in messages. Errors: kParseError (syntax, schema, unknown keys, types:
// with the line), kInvalidArgument (PieceConfig::Validate, naming the key).
Result<PieceConfig> ParsePieceConfig(std::string_view yaml_text, const std::string& source);
// Reads and parses a file (kIoError if it cannot be read).
Result<PieceConfig> LoadPieceConfig(const std::string& path);
// YAML that ParsePieceConfig reads back to the same configuration (17 significant digits).
std::string FormatPieceConfig(const PieceConfig& config);

}  // namespace tpcal::testpieces
