// Inspection plans (gdt::InspectionPlan) built from a test piece's own parameters, so that the
// nominals the GD&T evaluation compares against are the dimensions the piece was machined to.
// Turning piece: seed 002 section 2.2 datum frame (B_R, S_R, H1) and Table 1 (#1-#7, a-d), plus
// the characteristics the diagnosis uses (sizes and circularity of every turned face, plane
// distances and parallelism of every bottom face, the hole pattern).
#pragma once

#include "core/status.h"
#include "gdt/plan.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

// Builds and validates (gdt::ValidatePlan) the plan of a finished piece. `piece.inspection`
// holds the same plan (MakeTestPiece calls this).
Result<gdt::InspectionPlan> BuildInspectionPlan(const TestPiece& piece);

// Names of the seed 002 Table 1 characteristics in the turning plan.
//   #1 "conc_Ch_SR"  #2 "par_B1_BR"  #3 "dist_B3_BR"  #4 "size_S3"  #5 "conc_S4_SR"
//   #6 "conc_S4_S1"  #7 "conc_S6_S3"  a-d "circ_S1", "circ_S3", "circ_S4", "circ_S6"
// Values (gdt/PLAN_FORMAT.md): concentricity dx_um, dy_um; parallelism da_urad, db_urad;
// plane_distance error_um; size radius_error_um.

}  // namespace tpcal::testpieces
