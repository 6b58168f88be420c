// The seed 002 GD&T items (Table 1 names, kinematics/seed002_closed_form.h) read from an
// evaluated turning-piece inspection (testpieces/inspection_plan.cc names), and the geometry
// the closed-form relations need, read from the piece's parameters.
#pragma once

#include "core/status.h"
#include "gdt/inspection.h"
#include "kinematics/seed002_closed_form.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// Heights (mm from the A axis) and the B3 probing radius of a turning piece. kInvalidArgument if
// the piece is not the turning piece.
Result<kinematics::Seed002Geometry> Seed002GeometryOf(const testpieces::TestPiece& piece);

// Every item present in `inspection` (um / urad): Table 1 #1-#7 and the extra items
// (concentricity of S3 to S_R, radius differences S1-S4 and S2-S5). dd_B3_BR is the separation
// error (positive: B3 further from B_R than nominal; seed 002's sign). kInvalidArgument if the
// inspection lacks the Table 1 characteristics.
Result<kinematics::Seed002Items> Seed002ItemsFromInspection(const gdt::InspectionResult& inspection);

}  // namespace tpcal::pipeline
