// The probed-point file of an on-machine probing test of artifacts (`tpcal probepts v1`,
// docs/formats/probepts.md): one touch per row, the rotary commands, the artifact and face
// touched, the contact point and the approach direction in the machine frame (mm, unit).
//
//   # tpcal probepts v1
//   # units: mm
//   A_deg,C_deg,artifact,face,x,y,z,i,j,k[,t_s][,u_um]
//
// Read as rows; the stage turns them into kinematics::ProbeTouch against an artifact set. A plan
// (tpcal plan --instrument probe_artifacts) is the same format with the nominal contact points
// and a `# plan: nominal contact points` comment line.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline {

struct ProbePointRow {
  std::size_t line = 0;
  std::map<char, double> rotary_deg;  // 'A' / 'B' / 'C' -> command (deg), the columns present
  std::string artifact;               // as named in the artifact YAML
  std::string face;                   // "+X", "-X", "+Y", "-Y", "+Z" (checked by the stage)
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d approach = Eigen::Vector3d::Zero();  // unit (checked to 1e-6 on reading)
  double t_s = 0.0, u_um = 0.0;       // optional (0 when absent)
};

struct ProbePointFile {
  std::string source;
  std::vector<char> rotary_axes;  // the rotary columns, in header order
  bool has_t = false, has_u = false;
  bool is_plan = false;           // the `# plan:` comment line was present
  std::vector<ProbePointRow> rows;
};

// Errors (kParseError, source:line): a first line other than `# tpcal probepts v1`, units other
// than mm, a header without artifact, face, x, y, z, i, j, k and at least one of A_deg, B_deg,
// C_deg, an unknown or repeated column, a row with another number of fields, an empty artifact
// or face, a number field that is not a finite number, an approach not unit to 1e-6, u_um < 0, no rows.
Result<ProbePointFile> ParseProbePoints(std::string_view text, const std::string& source);

// The file (ReadFileBytes: regular files only), then ParseProbePoints.
Result<ProbePointFile> ReadProbePoints(const std::string& path);

// The file text of `file`: header lines (with `# plan: nominal contact points` when is_plan), the
// columns of rotary_axes then artifact..k, t_s / u_um when has_t / has_u; numbers with 17
// significant digits trimmed (%.17g). ParseProbePoints reads it back to the same rows.
std::string FormatProbePoints(const ProbePointFile& file);

}  // namespace tpcal::pipeline
