#include "pipeline/ballbar_simulate_stage.h"

#include <fmt/format.h>

#include <cmath>
#include <random>

#include "core/portable_random.h"
#include "kinematics/ballbar.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/ballbar_machine.h"
#include "pipeline/truth_yaml_text.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a BarSim prefix: a unity build merges this file with the other stages.

bool BarSimHasThermalTerms(const kinematics::ErrorState& errors) {
  for (const auto& t : errors.terms())
    if (t.kind == kinematics::TermKind::kExponentialDrift || t.kind == kinematics::TermKind::kLinearDrift) return true;
  return false;
}

bool BarSimFiniteAtLeastZero(double v) { return std::isfinite(v) && v >= 0.0; }

std::string BarSimTruthYaml(const BallbarSimRequest& request, const kinematics::MachineModel& model,
                            const kinematics::ErrorState& errors, const kinematics::BallbarSetup& setup,
                            const BallbarSimulation& sim) {
  std::string y;
  y += "# Stated truth of a tpcal simulate --instrument ballbar run: the machine errors, the installations,\n";
  y += "# the angles read and the noise added.\n";
  y += "schema: tpcal.simulation_truth/1\n";
  y += "instrument: ballbar\n";
  y += "machine_file: " + TruthStr(request.machine_path) + "  # empty: the nominal bhead_ctable\n";
  y += std::string("machine_type: ") + kinematics::MachineTypeName(model.type) + "\n";
  y += "errors_file: " + TruthStr(request.errors_path) + "\n";
  y += "setup_file: " + TruthStr(request.setup_path) + "\n";
  y += "ballbar_file: " + TruthStr(request.output_path) + "\n";
  y += fmt::format("n_readings: {}\n", sim.file.rows.size());
  y += fmt::format("seed: {}  # std::mt19937_64: one standard normal deviate per reading, in file order\n",
                   request.seed);
  y += "noise_um: " + TruthNum(request.noise_um) + "  # 1-sigma of each reading\n";
  y += "resolution_um: 0.1  # dl_um is rounded to 0.1 um\n";
  y += fmt::format("timed: {}  # true when the errors have thermal terms: reading i at t_s = i * seconds_per_reading\n",
                   sim.timed ? "true" : "false");
  y += "seconds_per_reading: " + TruthNum(request.seconds_per_reading) + "\n";
  y += "angles:  # deg, per installation in test order (circles: read ccw, then cw in reverse order)\n";
  for (const gcode::BallbarProgramTest& t : sim.tests) {
    std::string a;
    for (double v : t.angles_deg) a += (a.empty() ? "" : ", ") + TruthNum(v);
    y += "  " + TruthStr(t.geometry.installation.name) + ": [" + a + "]\n";
  }
  y += "setup:\n" + IndentLines(kinematics::FormatBallbarSetup(setup), "  ");
  y += "errors:\n" + IndentLines(kinematics::FormatErrorState(errors, model), "  ");
  return y;
}

}  // namespace

Status BallbarSimRequest::Validate() const {
  if (!BarSimFiniteAtLeastZero(noise_um))
    return Status(StatusCode::kInvalidArgument, "--noise-um must be a finite number >= 0 (um)", "tpcal simulate");
  if (!BarSimFiniteAtLeastZero(seconds_per_reading))
    return Status(StatusCode::kInvalidArgument, "--seconds-per-reading must be a finite number >= 0 (s)",
                  "tpcal simulate");
  return Status::Ok();
}

Result<BallbarSimulation> SimulateBallbar(const kinematics::MachineModel& model, const kinematics::ErrorState& errors,
                                          const kinematics::BallbarSetup& setup, const BallbarSimRequest& request) {
  if (Status s = request.Validate(); !s.ok()) return s;
  auto tests = MakeBallbarTests(model, setup, request.angles, request.setup_path, "tpcal simulate");
  if (!tests.ok()) return tests.status();
  BallbarSimulation sim;
  sim.tests = std::move(tests).value();
  sim.timed = BarSimHasThermalTerms(errors);
  sim.file = BallbarPlanReadings(sim.tests);
  sim.file.source = request.output_path;
  sim.file.has_t = sim.timed;
  std::mt19937_64 rng(request.seed);
  kinematics::Workspace ws;
  for (std::size_t i = 0; i < sim.file.rows.size(); ++i) {
    BallbarRow& row = sim.file.rows[i];
    const gcode::BallbarProgramTest* test = nullptr;
    for (const gcode::BallbarProgramTest& t : sim.tests)
      if (t.geometry.installation.name == row.setup) test = &t;
    if (sim.timed) row.t_s = static_cast<double>(i) * request.seconds_per_reading;
    auto dl = kinematics::SimulateBallbarDlUm(model, errors, test->geometry, row.angle_deg, row.t_s, &ws);
    if (!dl.ok())
      return dl.status().WithContext(fmt::format("installation {} at {} deg", row.setup, row.angle_deg));
    sim.dl_um.push_back(*dl + request.noise_um * StandardNormal(rng));
    row.dl_um = std::round(sim.dl_um.back() * 10.0) / 10.0 + 0.0;
    row.line = i + 4;  // after the version, units and header lines
  }
  sim.csv = FormatBallbar(sim.file);
  if (request.truth) sim.truth_yaml = BarSimTruthYaml(request, model, errors, setup, sim);
  return sim;
}

Result<BallbarSimulation> RunBallbarSimulateStage(const BallbarSimRequest& request) {
  if (request.setup_path.empty())
    return Status(StatusCode::kInvalidArgument, "--setup S.yaml is needed with --instrument ballbar", "tpcal simulate");
  if (Status s = request.Validate(); !s.ok()) return s;
  auto setup = kinematics::LoadBallbarSetup(request.setup_path);
  if (!setup.ok())
    return setup.status().file().empty() ? setup.status().WithLocation(request.setup_path) : setup.status();
  auto model = BallbarMachine(request.machine_path, *setup);
  if (!model.ok()) return model.status();
  auto errors = kinematics::LoadErrorState(request.errors_path, *model);
  if (!errors.ok())
    return errors.status().file().empty() ? errors.status().WithLocation(request.errors_path) : errors.status();
  auto sim = SimulateBallbar(*model, *errors, *setup, request);
  if (!sim.ok()) {
    if (sim.status().code() == StatusCode::kNotConverged)
      return kinematics::AtErrorsFile(sim.status(), request.errors_path);
    return sim.status();
  }
  return sim;
}

}  // namespace tpcal::pipeline
