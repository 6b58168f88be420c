#include "pipeline/probe_artifacts_simulate_stage.h"

#include <fmt/format.h>

#include <cmath>
#include <random>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/artifacts_yaml.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/probe_artifacts_plan_stage.h"
#include "pipeline/truth_yaml_text.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a ProbeSim prefix: a unity build merges this file with
// datum_ball_simulate_stage.cc (HasThermalTerms, TruthYaml, ...).

bool ProbeSimHasThermalTerms(const kinematics::ErrorState& errors) {
  for (const auto& t : errors.terms())
    if (t.kind == kinematics::TermKind::kExponentialDrift || t.kind == kinematics::TermKind::kLinearDrift) return true;
  return false;
}

Status ProbeSimFlagError(const std::string& flag, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, flag + " must be " + what);
}

bool ProbeSimFiniteAtLeastZero(double v) { return std::isfinite(v) && v >= 0.0; }

// The file's rows: the plan's rotary, artifact, face and approach; the simulated contact rounded
// to 1e-4 mm (a probing system's 0.1 um resolution); t_s when timed.
ProbePointFile ProbeSimPoints(const ProbeArtifactsSimulation& sim) {
  ProbePointFile file = ProbeArtifactsPlanPoints(sim.plan);
  file.is_plan = false;
  file.has_t = sim.timed;
  for (std::size_t i = 0; i < file.rows.size(); ++i) {
    for (int k = 0; k < 3; ++k) file.rows[i].point_mm(k) = std::round(sim.touches[i].contact_mm(k) * 1e4) / 1e4 + 0.0;
    file.rows[i].t_s = sim.touches[i].rotary.t_s;
  }
  return file;
}

std::string ProbeSimTruthYaml(const ProbeArtifactsSimRequest& request, const kinematics::MachineModel& model,
                              const kinematics::ErrorState& errors, const ProbeArtifactsSimulation& sim) {
  std::string y;
  y += "# Stated truth of a tpcal simulate --instrument probe_artifacts run: the machine errors, the artifacts,\n";
  y += "# the rotary poses and faces the virtual probe touched, the pre-travel and the noise added.\n";
  y += "schema: tpcal.simulation_truth/1\n";
  y += "instrument: probe_artifacts\n";
  y += "machine_file: " + TruthStr(request.machine_path) + "  # empty: the nominal ac_table\n";
  y += std::string("machine_type: ") + kinematics::MachineTypeName(model.type) + "\n";
  y += "errors_file: " + TruthStr(request.errors_path) + "\n";
  y += "artifacts_file: " + TruthStr(request.artifacts_path) + "  # empty: seed 000's three columns\n";
  y += "probepts_file: " + TruthStr(request.output_path) + "\n";
  y += fmt::format("n_touches: {}\n", sim.touches.size());
  y += fmt::format("n_skipped: {}  # planned out: faces down or corridor blocked\n", sim.plan.skipped.size());
  y += fmt::format("seed: {}  # std::mt19937_64: one standard normal deviate per touch, in file order\n", request.seed);
  y += "noise_um: " + TruthNum(request.noise_um) + "  # 1-sigma along the approach of each touch\n";
  y += "resolution_um: 0.1  # the contact points are rounded to 1e-4 mm\n";
  y += "probe_radius_mm: " + TruthNum(request.touch.probe_radius_mm) + "\n";
  y += "pretravel_um: " + TruthNum(request.touch.pretravel_um) + "  # p0: constant, along the approach\n";
  y += "pretravel_lobing_um: " + TruthNum(request.touch.pretravel_lobing_um) +
       "  # p3: p3 |d_xy| cos(3 phi) along the approach (kinematics/probe_touch.h)\n";
  y += fmt::format("timed: {}  # true when the errors have thermal terms: touch i at t_s = i * seconds_per_touch\n",
                   sim.timed ? "true" : "false");
  y += "seconds_per_touch: " + TruthNum(request.seconds_per_touch) + "\n";
  std::string a;
  for (double v : request.plan.a_deg) a += (a.empty() ? "" : ", ") + TruthNum(v);
  y += "a_deg: [" + a + "]\n";
  y += "c_step_deg: " + TruthNum(request.plan.c_step_deg) + "\n";
  y += "artifacts:\n" + IndentLines(kinematics::FormatArtifactsYaml(sim.plan.artifacts), "  ");
  y += "errors:\n" + IndentLines(kinematics::FormatErrorState(errors, model), "  ");
  return y;
}

}  // namespace

Status ProbeArtifactsSimRequest::Validate() const {
  if (!ProbeSimFiniteAtLeastZero(noise_um)) return ProbeSimFlagError("--noise-um", "a finite number >= 0 (um)");
  if (!ProbeSimFiniteAtLeastZero(seconds_per_touch))
    return ProbeSimFlagError("--seconds-per-touch", "a finite number >= 0 (s)");
  if (!(std::isfinite(touch.probe_radius_mm) && touch.probe_radius_mm > 0.0))
    return ProbeSimFlagError("--probe-radius-mm", "a finite number > 0 (mm)");
  if (!std::isfinite(touch.pretravel_um)) return ProbeSimFlagError("--pretravel-um", "a finite number (um)");
  if (!std::isfinite(touch.pretravel_lobing_um))
    return ProbeSimFlagError("--pretravel-lobing-um", "a finite number (um)");
  return touch.Validate();
}

Result<ProbeArtifactsSimulation> SimulateProbeArtifacts(const kinematics::MachineModel& model,
                                                        const kinematics::ErrorState& errors,
                                                        const kinematics::ArtifactSet& artifacts,
                                                        const ProbeArtifactsSimRequest& request) {
  if (Status s = request.Validate(); !s.ok()) return s;
  testpieces::ProbeArtifactsPlanOptions plan_options = request.plan;
  plan_options.probe_radius_mm = request.touch.probe_radius_mm;
  auto plan = testpieces::MakeProbeArtifactsPlan(model, artifacts, plan_options);
  if (!plan.ok()) return plan.status();
  ProbeArtifactsSimulation sim;
  sim.plan = std::move(*plan);
  sim.timed = ProbeSimHasThermalTerms(errors);
  std::mt19937_64 rng(request.seed);
  for (std::size_t i = 0; i < sim.plan.touches.size(); ++i) {
    const testpieces::PlannedTouch& planned = sim.plan.touches[i];
    kinematics::ProbeTouch touch;
    touch.rotary = planned.rotary;
    if (sim.timed) touch.rotary.t_s = static_cast<double>(i) * request.seconds_per_touch;
    touch.artifact = planned.artifact;
    touch.face = planned.face;
    touch.approach = planned.approach;
    const kinematics::FaceGeometry face = kinematics::FaceOf(sim.plan.artifacts.boxes[planned.artifact], planned.face);
    auto contact = kinematics::SimulateTouch(model, errors, touch.rotary, face, planned.target_part_mm, request.touch);
    if (!contact.ok())
      return contact.status().WithContext(fmt::format("touch at A = {} deg, C = {} deg, artifact {} face {}",
                                                      ProbeRotaryDeg(touch.rotary.a_rad),
                                                      ProbeRotaryDeg(touch.rotary.c_rad),
                                                      ArtifactLabel(sim.plan.artifacts, planned.artifact),
                                                      kinematics::BoxFaceName(planned.face)));
    touch.contact_mm = *contact + UmToMm(request.noise_um * StandardNormal(rng)) * touch.approach;
    touch.line = i + 4;  // after the version, units and header lines
    sim.touches.push_back(touch);
  }
  sim.points = ProbeSimPoints(sim);
  sim.csv = FormatProbePoints(sim.points);
  if (request.truth) sim.truth_yaml = ProbeSimTruthYaml(request, model, errors, sim);
  return sim;
}

Result<ProbeArtifactsSimulation> RunProbeArtifactsSimulateStage(const ProbeArtifactsSimRequest& request) {
  if (Status s = request.Validate(); !s.ok()) return s;
  auto model = request.machine_path.empty() ? kinematics::MakeMachine(kinematics::MachineType::kAcTable)
                                            : kinematics::LoadMachineModel(request.machine_path);
  if (!model.ok()) return model.status();
  auto artifacts = request.artifacts_path.empty() ? Result<kinematics::ArtifactSet>(kinematics::Seed000Artifacts())
                                                  : kinematics::LoadArtifactsYaml(request.artifacts_path);
  if (!artifacts.ok())
    return artifacts.status().file().empty() ? artifacts.status().WithLocation(request.artifacts_path)
                                             : artifacts.status();
  auto errors = kinematics::LoadErrorState(request.errors_path, *model);
  if (!errors.ok())
    return errors.status().file().empty() ? errors.status().WithLocation(request.errors_path) : errors.status();
  auto sim = SimulateProbeArtifacts(*model, *errors, *artifacts, request);
  if (!sim.ok()) {
    if (sim.status().code() == StatusCode::kInvalidArgument && sim.status().file().empty())
      return sim.status().WithLocation(request.machine_path.empty() ? "tpcal simulate" : request.machine_path);
    return kinematics::AtErrorsFile(sim.status(), request.errors_path);
  }
  return sim;
}

}  // namespace tpcal::pipeline
