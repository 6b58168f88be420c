// The stage of `tpcal plan`: the CMM probing plan of a built test piece as the `tpcal plan v1`
// CSV (docs/formats/probing_plan.md): nominal points and outward normals in the part's datum
// frame (mm), then op, t_s, the rotary axes the machine has (A_deg / B_deg, C_deg) and X_mm, Y_mm,
// Z_mm of the machine state that cut each point. Nothing is written here.
#pragma once

#include <string>

#include "core/point_set.h"
#include "core/status.h"
#include "pipeline/piece_loader.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {

struct PlanStageResult {
  PointSet points;  // datum frame, mm; no negative zeros
  std::string csv;  // the file's text
  testpieces::ProbingPlan plan;  // the plan itself (for its DMIS program, testpieces/dmis_program.h)
};

// Errors: the probing plan's ("probing plan of NAME: ..."), and a row the CSV cannot hold
// (reported at `csv_path`, the file it is meant for).
Result<PlanStageResult> RunPlanStage(const LoadedPiece& loaded, const std::string& csv_path);

}  // namespace tpcal::pipeline
