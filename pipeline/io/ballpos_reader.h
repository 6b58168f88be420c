// The ball-position file of a datum-ball test (`tpcal ballpos v1`, docs/formats/ballpos.md):
// the measured ball centre (machine frame, mm) at each rotary command. Read as rows; the stage
// (pipeline/datum_ball_stage.h) turns them into kinematics::BallReading for a machine.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline {

struct BallPositionRow {
  std::size_t line = 0;
  std::map<char, double> rotary_deg;  // 'A' / 'B' / 'C' -> command (deg), the columns present
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  std::string ball;                   // optional label ("" when the column is absent)
  double t_s = 0.0, u_um = 0.0;       // optional (0 when absent)
};

struct BallPositionFile {
  std::string source;
  std::vector<char> rotary_axes;  // the rotary columns, in header order
  std::vector<BallPositionRow> rows;
};

// Errors (kParseError, source:line): a first line other than `# tpcal ballpos v1`, units other
// than mm, a header without x, y, z and at least one of A_deg, B_deg, C_deg, an unknown or
// repeated column, a row with another number of fields, a field that is not a finite number, no rows.
Result<BallPositionFile> ParseBallPositions(std::string_view text, const std::string& source);

// The file (ReadFileBytes: regular files only), then ParseBallPositions.
Result<BallPositionFile> ReadBallPositions(const std::string& path);

}  // namespace tpcal::pipeline
