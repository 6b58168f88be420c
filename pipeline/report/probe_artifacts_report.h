// What `tpcal identify PROBEPTS --instrument probe_artifacts` writes: the tpcal.identification/1
// JSON (docs/formats/identify_json.md, section "Probe artifacts"), the text summary and an offline
// HTML page with one figure per error map (each error against its angle, 95 % bands) of an
// identification from an on-machine probing test of artifacts (kinematics/probe_artifact_identification.h).
#pragma once

#include <string>
#include <vector>

#include "kinematics/probe_artifact_identification.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::pipeline {

struct ProbeArtifactsReport {
  explicit ProbeArtifactsReport(kinematics::ProbeArtifactsResult r) : result(std::move(r)) {}
  std::string source;            // the probed-point file
  std::string artifacts_source;  // the artifact YAML ("" = seed 000's default set)
  std::string machine;           // machine type name
  kinematics::ArtifactSet artifacts;
  double probe_radius_mm = kinematics::kSeed000StylusRadiusMm;  // the stylus radius the touches were taken with
  std::vector<std::size_t> lines;  // source line of each touch
  kinematics::ProbeArtifactsResult result;
  // tpcal.errors/1 (kinematics/errors_yaml.md) of the maps, for `simulate --errors` and
  // `diagnose --reference`; comments state the reference pose, the zero-mean constraint and the
  // entries left at 0 because the plan cannot determine them.
  std::string errors_yaml;
};

std::string ProbeArtifactsJson(const ProbeArtifactsReport& report);
std::string ProbeArtifactsText(const ProbeArtifactsReport& report);
// A self-contained page (inline SVG, no script): the poses, the 12 maps as figures and tables.
std::string ProbeArtifactsHtml(const ProbeArtifactsReport& report);

}  // namespace tpcal::pipeline
