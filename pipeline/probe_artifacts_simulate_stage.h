// The stage of `tpcal simulate --instrument probe_artifacts`: the virtual on-machine probing test
// of artifacts (seed 000). Every planned touch (testpieces/probe_artifacts_plan.h) is simulated
// with kinematics::SimulateTouch under the errors file (position-dependent terms, and thermal terms
// at the touch's time) and the stylus pre-travel, Gaussian noise is added along the approach, and
// the touches are formatted as `tpcal probepts v1` (docs/formats/probepts.md; not a plan) with the
// stated truth if asked (schema tpcal.simulation_truth/1, instrument probe_artifacts). Nothing is
// written here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"
#include "kinematics/probe_touch.h"
#include "pipeline/io/probepts_io.h"
#include "testpieces/probe_artifacts_plan.h"

namespace tpcal::pipeline {

struct ProbeArtifactsSimRequest {
  std::string machine_path;    // machine model YAML (an A/C table); "" = the nominal ac_table
  std::string errors_path;     // tpcal.errors/1 (RunProbeArtifactsSimulateStage reads it)
  std::string artifacts_path;  // tpcal.artifacts/1; "" = kinematics::Seed000Artifacts()
  std::string output_path;     // the probepts file to be written (recorded in the truth)
  // The plan (seed 000's pattern by default); its probe_radius_mm is replaced by touch's.
  testpieces::ProbeArtifactsPlanOptions plan;
  kinematics::TouchOptions touch;  // stylus radius 3 mm, pre-travel p0 and p3 (um), default 0
  double noise_um = 0.0;           // 1-sigma noise of a contact along its approach, um
  std::uint64_t seed = 1;          // std::mt19937_64; one StandardNormal per touch, in plan order
  // Time of touch i (errors with thermal terms only): t_s = i * seconds_per_touch.
  double seconds_per_touch = 10.0;
  bool truth = false;              // also format the stated truth

  // kInvalidArgument naming the flag: noise or seconds per touch not finite or < 0; the touch
  // options' (--probe-radius-mm, --pretravel-um, --pretravel-lobing-um).
  Status Validate() const;
};

struct ProbeArtifactsSimulation {
  testpieces::ProbeArtifactsPlan plan;
  std::vector<kinematics::ProbeTouch> touches;  // noise included, full precision; one per planned touch
  bool timed = false;     // the errors have thermal terms: touches carry t_s (a t_s column)
  ProbePointFile points;  // the file's rows: contact rounded to 1e-4 mm (0.1 um), the plan's approach
  std::string csv;        // FormatProbePoints(points)
  std::string truth_yaml; // "" unless request.truth
};

// Simulates with a loaded machine, errors and artifacts. The reported contact of planned touch i
// is SimulateTouch(model, errors, rotary, face, target, touch) + noise_um * N_i * approach_i (mm),
// N_i the i-th StandardNormal of std::mt19937_64(seed); the approach is the plan's nominal one.
// Errors: the plan's (kInvalidArgument: not an A/C table, an A outside the stroke, ...), the
// touch's (kNotConverged naming the pose, artifact and face).
Result<ProbeArtifactsSimulation> SimulateProbeArtifacts(const kinematics::MachineModel& model,
                                                        const kinematics::ErrorState& errors,
                                                        const kinematics::ArtifactSet& artifacts,
                                                        const ProbeArtifactsSimRequest& request);

// Reads the machine, artifacts and errors files, then SimulateProbeArtifacts. Errors: Validate's,
// the files' (file:line), SimulateProbeArtifacts' (located at the errors file when a touch fails).
Result<ProbeArtifactsSimulation> RunProbeArtifactsSimulateStage(const ProbeArtifactsSimRequest& request);

}  // namespace tpcal::pipeline
