#include "pipeline/probe_artifacts_plan_stage.h"

#include <fmt/format.h>

#include <cmath>

#include "core/units.h"
#include "gcode/nc_format.h"
#include "kinematics/artifacts_yaml.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a ProbePlan prefix: a unity build merges this file with the other stages.

Result<kinematics::MachineModel> ProbePlanMachine(const std::string& path) {
  if (!path.empty()) return kinematics::LoadMachineModel(path);
  return kinematics::MakeMachine(kinematics::MachineType::kAcTable);
}

Result<kinematics::ArtifactSet> ProbePlanArtifacts(const std::string& path) {
  if (path.empty()) return kinematics::Seed000Artifacts();
  auto set = kinematics::LoadArtifactsYaml(path);
  if (!set.ok() && set.status().file().empty()) return set.status().WithLocation(path);
  return set;
}



double ProbePlanRound(double v, double step) { return std::round(v / step) * step + 0.0; }

}  // namespace

double ProbeRotaryDeg(double rad) { return std::round(RadToDeg(rad) * 1e9) / 1e9 + 0.0; }

std::string ArtifactLabel(const kinematics::ArtifactSet& artifacts, int index) {
  if (index >= 0 && index < static_cast<int>(artifacts.boxes.size()) && !artifacts.boxes[index].name.empty())
    return artifacts.boxes[index].name;
  return std::to_string(index + 1);
}

ProbePointFile ProbeArtifactsPlanPoints(const testpieces::ProbeArtifactsPlan& plan) {
  ProbePointFile file;
  file.rotary_axes = {'A', 'C'};
  file.is_plan = true;
  for (const testpieces::PlannedTouch& t : plan.touches) {
    ProbePointRow row;
    row.rotary_deg = {{'A', ProbeRotaryDeg(t.rotary.a_rad)}, {'C', ProbeRotaryDeg(t.rotary.c_rad)}};
    row.artifact = ArtifactLabel(plan.artifacts, t.artifact);
    row.face = kinematics::BoxFaceName(t.face);
    for (int k = 0; k < 3; ++k) {
      row.point_mm(k) = ProbePlanRound(t.contact_mm(k), 1e-4);
      row.approach(k) = ProbePlanRound(t.approach(k), 1e-12);
    }
    file.rows.push_back(row);
  }
  return file;
}

std::string SkippedTouchLine(const testpieces::ProbeArtifactsPlan& plan, const testpieces::SkippedTouch& s) {
  return fmt::format("A {} C {}: artifact {} face {} skipped: {}", ProbeRotaryDeg(s.rotary.a_rad),
                     ProbeRotaryDeg(s.rotary.c_rad), ArtifactLabel(plan.artifacts, s.artifact),
                     kinematics::BoxFaceName(s.face), s.reason);
}

Result<ProbeArtifactsPlanResult> RunProbeArtifactsPlanStage(const ProbeArtifactsPlanRequest& r) {
  auto machine = ProbePlanMachine(r.machine_path);
  if (!machine.ok()) return machine.status();
  auto artifacts = ProbePlanArtifacts(r.artifacts_path);
  if (!artifacts.ok()) return artifacts.status();
  ProbeArtifactsPlanResult out;
  out.machine = machine->name.empty() ? kinematics::MachineTypeName(machine->type) : machine->name;
  if (Status s = r.plan.Validate(); !s.ok()) return s.file().empty() ? s.WithLocation("tpcal plan") : s;
  auto plan = testpieces::MakeProbeArtifactsPlan(*machine, *artifacts, r.plan);
  if (!plan.ok()) return plan.status().WithLocation(r.machine_path.empty() ? "tpcal plan" : r.machine_path);
  out.plan = std::move(plan).value();
  out.points = ProbeArtifactsPlanPoints(out.plan);
  out.csv = FormatProbePoints(out.points);
  for (const testpieces::SkippedTouch& s : out.plan.skipped) out.skipped_lines.push_back(SkippedTouchLine(out.plan, s));
  out.files.push_back({r.csv_path, out.csv});
  const auto post = [&](const gcode::GcodeOptions& o) {
    return gcode::PostProbeArtifactsProgram(out.plan, *machine, r.probe, o);
  };
  if (Status s = PostPlanProgram(r.nc, post, &out.options, &out.posted, &out.files); !s.ok()) return s;
  return out;
}

}  // namespace tpcal::pipeline
