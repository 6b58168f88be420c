// The process families of the candidate catalogue (diagnosis_candidates.h), columns from the cut
// model of each point's feature (testpieces/cut_model.h), um per unit of each parameter:
// tool_deflection per cut class, servo_reversal on circles interpolated in machine X-Y, and
// probe_radius (with CMM scale). Internal to the diagnosis library.
#pragma once

#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline::diagnosis_internal {

// Appends the process candidates that act on the measured points to out->candidates, and the
// process families with none to out->not_applicable (with why).
void AddProcessCandidates(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                          const testpieces::MeasuredObservations& observations, CandidateCatalogue* out);

}  // namespace tpcal::pipeline::diagnosis_internal
