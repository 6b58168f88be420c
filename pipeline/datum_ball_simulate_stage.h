// The stage of `tpcal simulate --instrument datum_ball`: the virtual datum-ball instrument. At each
// rotary position of the plan (testpieces/datum_ball_plan.h) the linear commands that centre the
// probe on the ball are solved through the full kinematic chain with every error of the errors
// file (kinematics::BallCentreCommand: position-dependent terms, and thermal terms at the reading's
// time), Gaussian noise is added per coordinate, and the readings are formatted as `tpcal ballpos
// v1` (docs/formats/ballpos.md) with the stated truth if asked (schema tpcal.simulation_truth/1,
// instrument datum_ball). Nothing is written here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "testpieces/datum_ball_plan.h"

namespace tpcal::pipeline {

struct DatumBallSimRequest {
  std::string machine_path;  // machine model YAML; "" = the nominal bc_table (seed 001)
  std::string errors_path;   // tpcal.errors/1 (RunDatumBallSimulateStage reads it)
  std::string output_path;   // the ballpos file to be written (recorded in the truth)
  testpieces::DatumBallPlanOptions plan;  // tilt angles, C step, ball centre
  double noise_um = 0.0;     // 1-sigma noise of each coordinate of a reading, um
  std::uint64_t seed = 1;    // std::mt19937_64; StandardNormal per reading, x then y then z
  // Time of reading i (errors with thermal terms only): t_s = i * seconds_per_position.
  double seconds_per_position = 60.0;
  bool truth = false;        // also format the stated truth

  // kInvalidArgument naming the flag: noise not finite or < 0, seconds per position not finite or < 0.
  Status Validate() const;
};

struct DatumBallSimulation {
  testpieces::DatumBallPlan plan;
  std::vector<kinematics::BallReading> readings;  // noise included, full precision
  bool timed = false;      // the errors have thermal terms: readings carry t_s (a t_s column)
  std::string csv;         // tpcal ballpos v1; coordinates to 4 decimals (0.1 um resolution)
  std::string truth_yaml;  // "" unless request.truth
};

// Simulates with a loaded machine and errors. Errors: the plan's (kInvalidArgument: a machine other
// than a B/C or A/C table, a tilt outside the stroke, ...), a position the chain cannot centre
// (kNotConverged naming the rotary position).
Result<DatumBallSimulation> SimulateDatumBall(const kinematics::MachineModel& model,
                                              const kinematics::ErrorState& errors, const DatumBallSimRequest& request);

// Reads the machine and errors files, then SimulateDatumBall. Errors: Validate's, the files'
// (file:line), SimulateDatumBall's (located at the errors file when the chain cannot centre).
Result<DatumBallSimulation> RunDatumBallSimulateStage(const DatumBallSimRequest& request);

}  // namespace tpcal::pipeline
