// The test piece every command works on, and the machine it is cut on: a NAME
// (testpieces::PieceNames(): turning, turning_enriched, iso10791_m1_160, iso10791_m1_320 (alias
// iso10791_m1), iso10791_m2, cone_frustum, cone_frustum_enriched) or, where allowed, a
// tpcal.testpiece/1 file; optionally a configuration file replacing NAME's defaults (its `piece:`
// must agree with NAME; M1: its size decides 160 or 320), probing-density overrides, and a
// tpcal.machine/1 file. Without a machine file the piece's usual machine is built with nominal
// geometry (turning, cone_frustum: ac_table; M1, M2: xyz).
#pragma once

#include <optional>
#include <string>

#include "core/status.h"
#include "kinematics/machine_model.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// How a command words the errors of the loader (its messages stay as each command documents them).
struct PieceErrorWording {
  std::string unknown_name_prefix{};  // before the unknown-NAME message, e.g. "--testpiece: "
  std::string unknown_name_suffix{};  // after it, e.g. " (or --config FILE)"
  std::string unknown_name_file{};    // where that error is reported, e.g. "tpcal gcode"; "" = nowhere
  bool name_piece_errors = false;   // "test piece NAME: " before the errors of building the piece
  // Errors of building the piece that name no file are reported at: the configuration file
  // (kConfig, if given), or the configuration else the machine file (kConfigElseMachine).
  enum class Locate { kNone, kConfig, kConfigElseMachine } locate_piece_errors = Locate::kNone;
};

struct PieceRequest {
  std::string testpiece{};     // NAME, or (allow_piece_file) a tpcal.testpiece/1 file (.yaml / .yml)
  std::string config_path{};   // "" = NAME's defaults
  std::string machine_path{};  // "" = the piece's usual machine, nominal
  bool allow_piece_file = false;
  bool config_must_match_name = true;  // false: a configuration of any piece replaces NAME's
  // Probing-density overrides: "" or paper (as configured), dense, or N points per circle (N/2,
  // at least 3, per hole); levels (>= 1 when set): probing.levels_per_face. The configuration is
  // validated after them (errors at the configuration file, if given), and the plan they make
  // must stay within testpieces::kMaxPlanPoints.
  std::string density{};
  std::optional<int> levels{};
  PieceErrorWording wording{};
};

struct LoadedPiece {
  kinematics::MachineModel machine;
  testpieces::TestPiece piece;  // piece.config: the effective configuration (probing density included)
};

// Errors, in this order (file:line where a file is at fault): an unknown NAME (listing the names;
// with allow_piece_file "unknown test piece 'X' (expected one of: ..., or a tpcal.testpiece/1
// file)"), configuration file errors, a configuration for another piece, bad density or levels,
// machine file errors, a machine the piece cannot be cut on, a probing plan of more than
// testpieces::kMaxPlanPoints points (named after --density / --levels when given, else at the
// configuration file).
Result<LoadedPiece> LoadPiece(const PieceRequest& request);

}  // namespace tpcal::pipeline
