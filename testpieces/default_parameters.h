// The machine errors identified by default on a test piece: what the piece's cuts can say about
// the machine it was cut on.
#pragma once

#include <string>
#include <vector>

#include "kinematics/machine_model.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

// The parameter set identified by default on `piece` with `machine`: the seed 002 Table 2 set
// and the X-Y squareness E_C(0X)Y for the turning piece on an A/C table; for M2 the straightness
// of X in Z (E_ZX.c2, E_ZX.c3, um per mm^2 and mm^3); the ISO 230-1 location set otherwise.
std::vector<std::string> DefaultParameterSet(const TestPiece& piece, const kinematics::MachineModel& machine);

}  // namespace tpcal::testpieces
