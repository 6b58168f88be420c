// A piece's probing plan as a DMIS 5.3 inspection program (`.dmi`, docs/formats/dmis.md): the
// lab's CMM probes exactly the plan and reports every point as `FA(<feature>_<k>)` in its
// output (`.dmo`), which pipeline/io/dmis_reader.h reads back with its feature label.
//
// Program: header (DMISMN, FILNAM, UNITS/MM,ANGDEC, approach/retract distances); (1) manual
// alignment: every datum feature of the piece's inspection plan (primary, centre/secondary,
// direction feature) measured as its DMIS type (PLANE, CIRCLE, CYLNDR, LINE, POINT) at its
// planned points, DATDEF, and one DATSET that makes the CMM's part frame the piece's datum
// frame (the nominal geometry of the plan); (2) DCC: for every planned point in plan order
// `F(<feature>_<k>)=FEAT/POINT,CART,x,y,z,i,j,k`, MEAS/POINT, a GOTO to its approach point
// (approach_mm along the outward normal), PTMEAS/CART with the normal, the same GOTO back,
// ENDMES; between features a retract to the clearance plane (z = the highest approach point +
// clearance_mm in the datum frame, +Z up) and a move above the next feature; (3) OUTPUT of
// every point actual; ENDFIL. Coordinates in mm, datum frame, 6 decimals (1 nm).
// Moves are straight lines: check the program in the CMM software's simulation before a run.
#pragma once

#include <string>

#include "core/status.h"
#include "testpieces/probing_plan.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct DmisProgramOptions {
  double approach_mm = 2.0;    // start of each touch, along the outward normal
  double clearance_mm = 20.0;  // clearance plane above the highest approach point
};

// The label of the k-th (1-based) planned point of `feature`: `<feature>_<k>`.
std::string DmisPointLabel(const std::string& feature, int k);

// Errors: kInvalidArgument for a feature name DMIS labels cannot hold (characters other than
// letters, digits, `_` and `-`), non-positive distances, a datum feature that is not in the
// plan, a plan without a datum frame.
Result<std::string> FormatDmisProgram(const TestPiece& piece, const ProbingPlan& plan,
                                      const DmisProgramOptions& options = {});

}  // namespace tpcal::testpieces
