// The test piece a command works on: `--testpiece NAME [--config TP.yaml] [--machine M.yaml]`.
// Names: testpieces::PieceNames() (turning, turning_enriched, iso10791_m1_160, iso10791_m1_320
// (alias iso10791_m1), iso10791_m2, cone_frustum, cone_frustum_enriched). Without --machine the piece's usual machine is built with nominal
// geometry (turning, cone_frustum: ac_table; M1, M2: xyz). With --config, the file's `piece:`
// must agree with NAME (M1: its size decides 160 or 320).
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/machine_model.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct PieceSetup {
  testpieces::PieceConfig config;
  kinematics::MachineModel machine;
  testpieces::TestPiece piece;
};

// Errors: unknown NAME (listing the names), config / machine file errors (file:line), a config
// for another piece, a machine the piece cannot be cut on.
Result<PieceSetup> LoadPieceSetup(const std::string& name, const std::string& config_path = "",
                                  const std::string& machine_path = "");

}  // namespace tpcal::pipeline
