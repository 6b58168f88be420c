// The stage of `tpcal identify PROBEPTS --instrument probe_artifacts`: the probed-point file
// (pipeline/io/probepts_io.h) read against the artifact set (kinematics/artifacts_yaml.h; default
// seed 000's three columns) for an A/C table (given, or the nominal one) and identified
// (kinematics/probe_artifact_identification.h). Nothing is written here.
#pragma once

#include <string>

#include "core/status.h"
#include "kinematics/probe_artifacts.h"
#include "pipeline/report/probe_artifacts_report.h"

namespace tpcal::pipeline {

struct ProbeArtifactsRequest {
  std::string path;            // tpcal probepts v1
  std::string artifacts_path;  // tpcal.artifacts/1; "" = kinematics::Seed000Artifacts()
  std::string machine_path;    // tpcal.machine/1; "" = the nominal A/C table
  double reference_a_deg = 0.0, reference_c_deg = 0.0;  // the pose that is zero by definition
  // The stylus ball radius the touches were taken with (mm): a touch's linear command is its
  // contact minus radius x approach, which places the squareness's columns.
  double probe_radius_mm = kinematics::kSeed000StylusRadiusMm;
};

// Errors: a stylus radius not finite or not > 0 (kInvalidArgument); the files' (file:line); a row
// naming an artifact the set lacks or a face name other than +X -X +Y -Y +Z (kInvalidArgument,
// file:line); a machine other than an A/C table, rotary columns other than A_deg and C_deg
// (naming the file); the identification's (a touch's line named).
Result<ProbeArtifactsReport> RunProbeArtifactsStage(const ProbeArtifactsRequest& request);

}  // namespace tpcal::pipeline
