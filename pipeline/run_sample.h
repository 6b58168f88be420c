// Simulated samples with stated truth (samples/*/truth.yaml, schema tpcal.sample_truth/1): the
// test piece, the machine, its errors, the CMM noise, probe error, placement and seed from which
// a bundled CMM export was generated. SimulateSample regenerates the export exactly (same seed,
// same bytes), so tests check both the file and the identification against the truth.
//
//   schema: tpcal.sample_truth/1
//   description: free text
//   testpiece: turning                 # kind or tpcal.testpiece/1 file (relative to this file)
//   machine: ../machines/ac_table.yaml # tpcal.machine/1 (relative), or omitted: nominal machine
//   seed: 2026                         # std::mt19937_64: placement, then noise
//   noise_um: 0.5                      # 1-sigma CMM noise along the normal
//   probe_radius_error_um: 0.0
//   random_placement: true             # part placed anywhere on the CMM
//   points_per_circle: 16              # optional probing density overrides (else the piece's)
//   points_per_hole: 8
//   levels_per_face: 1
//   levels_per_hole: 1
//   raw_scan: false                    # true: the export carries no feature labels (a raw scan,
//                                      # points in plan order; the pipeline labels them itself)
//   errors: {machine: ac_table, dx_CR(0)_um: 12.4, ...}   # tpcal.errors/1 body (kinematics/errors_yaml.md)
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "pipeline/piece_loader.h"
#include "pipeline/run_config.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {

struct SampleTruth {
  std::string source;
  std::string description;
  std::string testpiece = "turning";
  std::string machine;  // resolved path or ""
  std::string errors_yaml;  // tpcal.errors/1 text
  testpieces::PieceSimOptions sim;
  std::optional<int> points_per_circle, points_per_hole, levels_per_face, levels_per_hole;
  bool raw_scan = false;  // the bundled export drops the labels (SampleExportPoints)
};

Result<SampleTruth> LoadSampleTruth(const std::string& path);

struct SimulatedSample {
  LoadedPiece setup;
  kinematics::ErrorState errors;
  testpieces::SimulatedPiece simulated;
};

// Builds the piece and machine, parses the errors and simulates the CMM points.
Result<SimulatedSample> SimulateSample(const SampleTruth& truth);

// The points as bundled: the simulated CMM points, without their labels when truth.raw_scan.
PointSet SampleExportPoints(const SampleTruth& truth, const SimulatedSample& sample);

// The true value of each named coefficient in its display unit (um, urad, ...): coefficients
// missing from `errors` are zero (the stated truth has no such error).
std::map<std::string, double> TruthValues(const kinematics::ErrorState& errors,
                                          const std::vector<std::string>& coefficient_names);

// Loads a truth file and returns the true values of `coefficient_names` (for report marks).
Result<std::map<std::string, double>> LoadTruthValues(const std::string& truth_path,
                                                      const std::vector<std::string>& coefficient_names);

}  // namespace tpcal::pipeline
