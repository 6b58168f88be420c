// The stage of `tpcal simulate --instrument ballbar`: the virtual double ball bar (seed 003; ISO
// 230-4 circular tests). Every reading of the plan (pipeline/ballbar_plan_stage.h: the set-up's
// installations at their angles) is kinematics::SimulateBallbarDlUm under the errors file
// (position-dependent terms, and thermal terms at the reading's time) plus Gaussian noise,
// rounded to the bar's 0.1 um, and formatted as `tpcal ballbar v1` (docs/formats/ballbar.md) with
// the stated truth if asked (schema tpcal.simulation_truth/1, instrument ballbar). Nothing is
// written here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "pipeline/ballbar_plan_stage.h"
#include "pipeline/io/ballbar_io.h"

namespace tpcal::pipeline {

struct BallbarSimRequest {
  std::string setup_path;    // tpcal.ballbar_setup/1 (required)
  std::string machine_path;  // tpcal.machine/1; "" = the nominal bhead_ctable
  std::string errors_path;   // tpcal.errors/1
  std::string output_path;   // the ballbar file to be written (recorded in the truth)
  BallbarAngles angles;      // the plan's (seed 003's defaults)
  double noise_um = 0.0;     // 1-sigma noise of each reading, um
  std::uint64_t seed = 1;    // std::mt19937_64; one StandardNormal per reading, in file order
  // Time of reading i (errors with thermal terms only): t_s = i * seconds_per_reading.
  double seconds_per_reading = 5.0;
  bool truth = false;        // also format the stated truth

  // kInvalidArgument naming the flag: noise or seconds per reading not finite or < 0.
  Status Validate() const;
};

struct BallbarSimulation {
  std::vector<gcode::BallbarProgramTest> tests;
  std::vector<double> dl_um;  // noise included, full precision; one per row of `file`
  bool timed = false;         // the errors have thermal terms: the file has t_s
  BallbarFile file;           // the plan's rows with dl_um rounded to 0.1 um (and t_s when timed)
  std::string csv;            // FormatBallbar(file)
  std::string truth_yaml;     // "" unless request.truth
};

// Simulates with a loaded machine, set-up and errors. Row i's dl_um is SimulateBallbarDlUm at its
// installation and angle + noise_um * N_i, N_i the i-th StandardNormal of std::mt19937_64(seed).
// Errors: the plan's (MakeBallbarTests), the model's (kNotConverged naming installation and angle).
Result<BallbarSimulation> SimulateBallbar(const kinematics::MachineModel& model, const kinematics::ErrorState& errors,
                                          const kinematics::BallbarSetup& setup, const BallbarSimRequest& request);

// Reads the machine, set-up and errors files, then SimulateBallbar. Errors: no --setup, Validate's,
// the files' (file:line), SimulateBallbar's.
Result<BallbarSimulation> RunBallbarSimulateStage(const BallbarSimRequest& request);

}  // namespace tpcal::pipeline
