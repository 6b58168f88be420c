// The stage of `tpcal identify BALLBAR --instrument ballbar`: the ball-bar file
// (pipeline/io/ballbar_io.h) read against its set-up (kinematics/ballbar_setup.h) on a machine
// (given, or nominal), each reading paired with its installation; the rotary installations
// identified per turned axis (kinematics/ballbar_identification.h), each circle analysed as an
// ISO 230-4 circular test (kinematics/circular_test_analysis.h). Nothing is written here.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "pipeline/report/ballbar_report.h"

namespace tpcal::pipeline {

struct BallbarRequest {
  std::string path;          // tpcal ballbar v1
  std::string setup_path;    // tpcal.ballbar_setup/1 (required)
  // tpcal.machine/1; "" = the nominal bhead_ctable when any installation turns a rotary axis
  // (seed 003's machine), else the nominal xyz machine.
  std::string machine_path;
  // Errors the identification lacks whose share of every turned axis's maps is reported
  // (BallbarAxisReport::map_response, kinematics::BallbarMapResponse); names the machine lacks
  // are skipped.
  std::vector<std::string> map_response_to;
};

// Errors: the files' (file:line); a row naming an installation the set-up lacks (kInvalidArgument,
// file:line); an installation the machine cannot hold (naming the set-up file); the
// identification's or the circle analysis's (the ball-bar file named); the map response's
// (kinematics::BallbarMapResponse, the ball-bar file named).
Result<BallbarReport> RunBallbarStage(const BallbarRequest& request);

}  // namespace tpcal::pipeline
