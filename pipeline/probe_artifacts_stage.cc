#include "pipeline/probe_artifacts_stage.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "kinematics/artifacts_yaml.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/io/probepts_io.h"

namespace tpcal::pipeline {
namespace {

Result<kinematics::MachineModel> ProbeMachine(const ProbeArtifactsRequest& r) {
  auto m = r.machine_path.empty() ? kinematics::MakeMachine(kinematics::MachineType::kAcTable)
                                  : kinematics::LoadMachineModel(r.machine_path);
  if (!m.ok()) return m.status();
  if (m->type != kinematics::MachineType::kAcTable) {
    return Status(StatusCode::kInvalidArgument,
                  std::string("the probing test of artifacts needs an A/C table (ac_table), not ") +
                      kinematics::MachineTypeName(m->type),
                  r.machine_path);
  }
  return m;
}

Result<std::vector<kinematics::ProbeTouch>> ProbeTouches(const ProbePointFile& file, const kinematics::ArtifactSet& set) {
  std::vector<char> axes = file.rotary_axes;
  std::sort(axes.begin(), axes.end());
  if (axes != std::vector<char>{'A', 'C'}) {
    return Status(StatusCode::kInvalidArgument, "expected the rotary columns A_deg and C_deg (an A/C table)",
                  file.source);
  }
  std::vector<kinematics::ProbeTouch> touches;
  for (const ProbePointRow& row : file.rows) {
    kinematics::ProbeTouch t;
    t.rotary.a_rad = DegToRad(row.rotary_deg.at('A'));
    t.rotary.c_rad = DegToRad(row.rotary_deg.at('C'));
    t.rotary.t_s = row.t_s;
    t.artifact = set.Find(row.artifact);
    if (t.artifact < 0) {
      return Status(StatusCode::kInvalidArgument, "artifact '" + row.artifact + "' is not in the artifact set",
                    file.source, row.line);
    }
    const auto face = kinematics::BoxFaceFromName(row.face);
    if (!face) {
      return Status(StatusCode::kInvalidArgument, "face '" + row.face + "': expected +X, -X, +Y, -Y or +Z",
                    file.source, row.line);
    }
    t.face = *face;
    t.contact_mm = row.point_mm;
    t.approach = row.approach;
    t.line = row.line;
    t.u_um = row.u_um;
    touches.push_back(t);
  }
  return touches;
}

// The maps and the linear axes' errors fitted with the poses (squareness), as tpcal.errors/1.
Result<std::string> ProbeErrorsYaml(const kinematics::MachineModel& m, const kinematics::ProbeArtifactsResult& r) {
  const kinematics::ErrorMaps& maps = r.maps;
  std::string out = "# error maps identified from a probing test of artifacts (tpcal identify --instrument probe_artifacts)\n";
  for (const std::string& c : maps.conventions) out += "# " + c + "\n";
  if (!maps.not_identifiable.empty()) {
    out += "# not identifiable by this plan, written as 0:";
    for (const std::string& n : maps.not_identifiable) out += " " + n;
    out += "\n";
  }
  kinematics::ErrorState errors = maps.maps;
  std::string linear;
  for (const kinematics::ParameterEstimate& e : r.poses.linear_errors) {
    if (!e.identifiable) {
      linear += " " + e.name + " (not identifiable, 0)";
      continue;
    }
    TPCAL_RETURN_IF_ERROR(errors.SetParameter(m, e.name, 0.0));
    const int c = *errors.FindCoefficient(e.name);
    errors.set_coefficient(c, e.value / errors.coefficient_info(c).display_per_internal);
    linear += " " + e.name;
  }
  if (!linear.empty()) out += "# the linear axes' errors fitted with the table poses:" + linear + "\n";
  return out + kinematics::FormatErrorState(errors, m);
}

}  // namespace

Result<ProbeArtifactsReport> RunProbeArtifactsStage(const ProbeArtifactsRequest& r) {
  if (!std::isfinite(r.probe_radius_mm) || !(r.probe_radius_mm > 0.0))
    return Status(StatusCode::kInvalidArgument,
                  fmt::format("stylus radius {} mm (--probe-radius-mm, --reference-probe-radius-mm or "
                              "reference.probe_radius_mm): expected a ball radius > 0 mm",
                              r.probe_radius_mm));
  auto file = ReadProbePoints(r.path);
  if (!file.ok()) return file.status();
  auto set = r.artifacts_path.empty() ? Result<kinematics::ArtifactSet>(kinematics::Seed000Artifacts())
                                      : kinematics::LoadArtifactsYaml(r.artifacts_path);
  if (!set.ok()) return set.status();
  auto machine = ProbeMachine(r);
  if (!machine.ok()) return machine.status();
  auto touches = ProbeTouches(*file, *set);
  if (!touches.ok()) return touches.status();
  kinematics::TablePoseOptions options;
  options.reference_a_deg = r.reference_a_deg;
  options.reference_c_deg = r.reference_c_deg;
  options.probe_radius_mm = r.probe_radius_mm;
  auto result = kinematics::IdentifyProbeArtifacts(*machine, *set, *touches, options);
  if (!result.ok()) {
    Status s = result.status();
    return s.file().empty() ? s.WithLocation(r.path, s.line()) : s;
  }
  ProbeArtifactsReport report(std::move(*result));
  report.source = r.path;
  report.artifacts_source = r.artifacts_path;
  report.machine = kinematics::MachineTypeName(machine->type);
  report.artifacts = *set;
  report.probe_radius_mm = r.probe_radius_mm;
  for (const auto& t : *touches) report.lines.push_back(t.line);
  auto yaml = ProbeErrorsYaml(*machine, report.result);
  if (!yaml.ok()) return yaml.status();
  report.errors_yaml = std::move(*yaml);
  return report;
}

}  // namespace tpcal::pipeline
