// What `tpcal identify BALLPOS --instrument datum_ball` writes: the tpcal.identification/1 JSON
// (docs/formats/identify_json.md, section "Datum ball") and the text summary of a datum-ball
// identification (kinematics/datum_ball.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "kinematics/datum_ball.h"

namespace tpcal::pipeline {

struct DatumBallReport {
  std::string source;        // the ball-position file
  std::string machine;       // machine type name
  std::vector<std::size_t> lines;  // source line of each reading
  kinematics::DatumBallResult result;
  // tpcal.errors/1 (kinematics/errors_yaml.md) of the identifiable errors, for `simulate --errors`
  // and `diagnose --reference`; a comment names those left out (not identifiable by the plan).
  std::string errors_yaml;
  bool ball_given = false;   // the ball centre was given (--ball), not fitted
};

std::string DatumBallJson(const DatumBallReport& report);
std::string DatumBallText(const DatumBallReport& report);

}  // namespace tpcal::pipeline
