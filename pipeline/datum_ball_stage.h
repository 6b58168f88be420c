// The stage of `tpcal identify BALLPOS --instrument datum_ball`: the ball-position file
// (pipeline/io/ballpos_reader.h) read for a machine (given, or the nominal B/C or A/C table its
// rotary columns name) and identified (kinematics/datum_ball.h). Nothing is written here.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "pipeline/report/datum_ball_json.h"

namespace tpcal::pipeline {

struct DatumBallRequest {
  std::string path;                          // tpcal ballpos v1
  std::string machine_path;                  // "" = the nominal table machine of the file's rotary columns
  std::vector<std::string> parameters;       // "" = IsoLocationSet of the machine
  std::optional<Eigen::Vector3d> ball_part_mm;  // known ball centre (part frame); unset: fitted
};

// The report holds the identified errors as tpcal.errors/1 too. Errors: the file's (file:line); a rotary column the machine has not, or a machine rotary axis
// the file lacks (kInvalidArgument naming the file); the machine file's; the identification's
// (a reading that cannot be centred names its line).
Result<DatumBallReport> RunDatumBallStage(const DatumBallRequest& request);

}  // namespace tpcal::pipeline
