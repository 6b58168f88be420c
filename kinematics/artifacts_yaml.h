// Artifact files (`tpcal.artifacts/1`, docs/formats/artifacts.md): the nominal boxes of an
// on-machine probing test (kinematics/probe_artifacts.h), part frame, mm.
//
//   schema: tpcal.artifacts/1      # optional; if present must be exactly this
//   artifacts:
//     - {name: "1", base_centre_mm: [100, 0, 0], size_mm: [30, 30, 60], rotation_deg: 0}
//
// rotation_deg is optional (0). Names are unique and non-empty; sizes > 0.
#pragma once

#include <string>
#include <string_view>

#include "core/status.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::kinematics {

// Errors (kParseError, `source:line: message`): malformed YAML, unknown or missing keys, a wrong
// schema, no artifacts, a repeated or empty name, a size <= 0, a value not finite.
Result<ArtifactSet> ParseArtifactsYaml(std::string_view text, const std::string& source);
// The file, then ParseArtifactsYaml. Errors also kIoError when it cannot be read.
Result<ArtifactSet> LoadArtifactsYaml(const std::string& path);
// The file text of `set` (17 significant digits), re-read by ParseArtifactsYaml to the same set.
std::string FormatArtifactsYaml(const ArtifactSet& set);

}  // namespace tpcal::kinematics
