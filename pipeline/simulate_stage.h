// The stage of `tpcal simulate`: virtual machining and measurement of a built test piece
// (testpieces::SimulatePiece) with machine errors (tpcal.errors/1) and optional process effects
// (tpcal.process/1): every probing-plan point solved on the surface the erroneous machine cut,
// then measured by a virtual CMM (noise along the normal, probe-radius error, optional random
// placement). Gives the `tpcal points v1` CSV (docs/formats/points.md) and, if asked, the stated
// truth (schema tpcal.simulation_truth/1). Nothing is written here.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/status.h"
#include "pipeline/piece_loader.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {

struct SimulateRequest {
  // The piece as asked for (recorded in the truth): NAME, configuration and machine files.
  std::string testpiece;
  std::string config_path;
  std::string machine_path;
  std::string errors_path;   // tpcal.errors/1
  std::string process_path;  // tpcal.process/1; "" = no process effects
  std::string points_path;   // where the CSV goes (CSV errors are reported there; recorded in the truth)
  double noise_um = 0.0;     // 1-sigma CMM noise along the normal
  std::uint64_t seed = 1;    // std::mt19937_64: placement first, then one normal deviate per point
  std::string placement = "datum";  // datum (CMM frame = datum frame) or random
  double max_translation_mm = 300.0;  // random placement: bound per axis
  double probe_radius_error_um = 0.0;  // actual - calibrated probe radius
  bool truth = false;        // also format the stated truth
  std::function<void(const std::string& line)> info;  // progress lines; may be empty

  // kInvalidArgument naming the flag: noise not finite or < 0, probe radius error not finite,
  // max translation not finite or < 0.
  Status Validate() const;
};

struct SimulateStageResult {
  testpieces::SimulatedPiece simulated;  // normals without negative zeros
  std::string csv;
  std::string truth_yaml;  // "" unless request.truth
};

// Errors: those of the errors and process files (file:line), of the simulation ("simulating NAME:
// ..."), and a point the CSV cannot hold (at points_path).
Result<SimulateStageResult> RunSimulateStage(const LoadedPiece& loaded, const SimulateRequest& request);

}  // namespace tpcal::pipeline
