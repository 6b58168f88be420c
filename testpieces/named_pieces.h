// The test pieces a user can name on the command line (`--testpiece NAME`), one list for every
// command: the standard pieces with their documented defaults and the enriched variants proposed
// for the diagnosis (samples/testpieces/*_enriched.yaml hold the same configurations).
//   turning                 seed 002 turning piece, A/C table, paper plan
//   turning_enriched        + inner groove wall cut CW, 3 levels x 32 points per face, 2 per hole
//   iso10791_m1             = iso10791_m1_320; iso10791_m1_160 the small M1 (3-axis)
//   iso10791_m2             face-milling piece (3-axis)
//   cone_frustum            NAS 979 / ISO 10791-7 cone frustum, A/C table
//   cone_frustum_enriched   + cones 130 mm along +X and +Y on a 380 mm plate, 48 points per section
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"
#include "kinematics/machine_model.h"
#include "testpieces/piece_config.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct NamedPiece {
  PieceConfig config;                 // parameters, probing plan and time model of the named piece
  kinematics::MachineType usual_machine = kinematics::MachineType::kAcTable;  // when no machine is given
  double m1_size_mm = 0.0;            // names that fix the M1 size (iso10791_m1_160 / _320); 0 otherwise
};

// Every accepted NAME, in --help order.
const std::vector<std::string>& PieceNames();
// "turning, turning_enriched, ..." for --help and messages.
std::string PieceNameList();

// Error kInvalidArgument: unknown NAME (the message lists the names).
Result<NamedPiece> NamedPieceConfig(std::string_view name);

// A configuration file given with a NAME must describe the same piece: the same kind, and for a
// name that fixes the M1 size, that size. Error kInvalidArgument naming both (`source`: the file).
Status CheckConfigMatchesName(const PieceConfig& config, const NamedPiece& named, std::string_view name,
                              const std::string& source);

// The nominal machine the piece is usually cut on: A/C table for turning and cone pieces, 3-axis
// for M1 and M2.
kinematics::MachineType UsualMachine(const PieceConfig& config);

}  // namespace tpcal::testpieces
