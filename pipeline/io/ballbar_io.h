// The ball-bar file of a double-ball-bar test (`tpcal ballbar v1`, docs/formats/ballbar.md): one
// reading per row, the installation (named in the set-up YAML, kinematics/ballbar_setup.h), the
// rotary command or path angle, and the bar length minus its nominal length.
//
//   # tpcal ballbar v1
//   # units: mm
//   setup,angle_deg,dl_um[,direction][,t_s]
//   C_radial_H1,0,0.0
//   C_radial_H1,20,1.8
//
// `direction` (cw | ccw) is the path direction of a circular test of two linear axes; `t_s` the
// time of the reading. Columns in any order. Read as rows; the stage pairs them with the set-up.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline {

enum class BallbarDirection { kNone, kCw, kCcw };  // kNone: the column is absent

struct BallbarRow {
  std::size_t line = 0;      // 1-based source line
  std::string setup;         // installation name (non-empty, trimmed, no comma)
  double angle_deg = 0.0;    // rotary command, or path angle of a circle test
  double dl_um = 0.0;        // bar length - nominal length
  BallbarDirection direction = BallbarDirection::kNone;
  double t_s = 0.0;          // 0 when absent
};

struct BallbarFile {
  std::string source;
  bool has_direction = false, has_t = false;
  std::vector<BallbarRow> rows;
};

// Errors (kParseError, source:line): a first line other than `# tpcal ballbar v1`, units other
// than mm, a header without setup, angle_deg and dl_um, an unknown or repeated column, a row with
// another number of fields, an empty setup or one starting with '#', a direction other than cw / ccw, a number field that
// is not a finite number, no rows.
Result<BallbarFile> ParseBallbar(std::string_view text, const std::string& source);

// The file (ReadFileBytes: regular files only), then ParseBallbar.
Result<BallbarFile> ReadBallbar(const std::string& path);

// The file text of `file`: the header lines, setup,angle_deg,dl_um then direction / t_s when
// has_direction / has_t (then every row's direction is cw or ccw; kNone is written as ccw);
// shortest round-trip numbers. ParseBallbar reads it back to the same rows.
std::string FormatBallbar(const BallbarFile& file);

}  // namespace tpcal::pipeline
