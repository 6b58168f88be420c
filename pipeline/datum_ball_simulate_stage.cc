#include "pipeline/datum_ball_simulate_stage.h"

#include <fmt/format.h>

#include <cmath>
#include <random>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/truth_yaml_text.h"

namespace tpcal::pipeline {
namespace {

bool HasThermalTerms(const kinematics::ErrorState& errors) {
  for (const auto& t : errors.terms())
    if (t.kind == kinematics::TermKind::kExponentialDrift || t.kind == kinematics::TermKind::kLinearDrift) return true;
  return false;
}

// A rotary command in the file: degrees, rounded to 1e-9 deg so the plan's 30 deg reads "30".
std::string DegText(double rad) { return fmt::format("{}", std::round(RadToDeg(rad) * 1e9) / 1e9 + 0.0); }

char TiltLetter(const testpieces::DatumBallPlan& plan) { return plan.tilt_axis == kinematics::Axis::kB ? 'B' : 'A'; }

std::string BallposCsv(const DatumBallSimulation& sim) {
  const char tilt = TiltLetter(sim.plan);
  std::string out = fmt::format("# tpcal ballpos v1\n# units: mm\n{}_deg,C_deg,x,y,z{}\n", tilt, sim.timed ? ",t_s" : "");
  for (const auto& r : sim.readings) {
    out += fmt::format("{},{},{:.4f},{:.4f},{:.4f}", DegText(tilt == 'B' ? r.rotary.b_rad : r.rotary.a_rad),
                       DegText(r.rotary.c_rad), r.command_mm.x(), r.command_mm.y(), r.command_mm.z());
    out += sim.timed ? fmt::format(",{}\n", r.rotary.t_s) : "\n";
  }
  return out;
}

std::string TruthYaml(const DatumBallSimRequest& request, const kinematics::MachineModel& model,
                      const kinematics::ErrorState& errors, const DatumBallSimulation& sim) {
  std::string y;
  y += "# Stated truth of a tpcal simulate --instrument datum_ball run: the machine errors, the ball and\n";
  y += "# the rotary positions the virtual probe centred on it, and the noise added to the readings.\n";
  y += "schema: tpcal.simulation_truth/1\n";
  y += "instrument: datum_ball\n";
  y += "machine_file: " + TruthStr(request.machine_path) + "  # empty: the nominal bc_table\n";
  y += std::string("machine_type: ") + kinematics::MachineTypeName(model.type) + "\n";
  y += "errors_file: " + TruthStr(request.errors_path) + "\n";
  y += "ballpos_file: " + TruthStr(request.output_path) + "\n";
  y += fmt::format("n_readings: {}\n", sim.readings.size());
  y += fmt::format("seed: {}  # std::mt19937_64: one standard normal deviate per coordinate, x, y, z per reading\n",
                   request.seed);
  y += "noise_um: " + TruthNum(request.noise_um) + "  # 1-sigma per coordinate of a reading\n";
  y += "resolution_um: 0.1  # the file's 4 decimals (mm)\n";
  y += fmt::format("timed: {}  # true when the errors have thermal terms: reading i at t_s = i * seconds_per_position\n",
                   sim.timed ? "true" : "false");
  y += "seconds_per_position: " + TruthNum(request.seconds_per_position) + "\n";
  y += std::string("tilt_axis: ") + TiltLetter(sim.plan) + "\n";
  std::string tilts;
  for (double t : request.plan.tilt_deg) tilts += (tilts.empty() ? "" : ", ") + TruthNum(t);
  y += "tilt_deg: [" + tilts + "]\n";
  y += "c_step_deg: " + TruthNum(request.plan.c_step_deg) + "\n";
  const Eigen::Vector3d& b = sim.plan.ball_part_mm;
  y += fmt::format("ball_part_mm: [{}, {}, {}]  # part frame (on the C table)\n", TruthNum(b.x()), TruthNum(b.y()),
                   TruthNum(b.z()));
  y += "errors:\n" + IndentLines(kinematics::FormatErrorState(errors, model), "  ");
  return y;
}

}  // namespace

Status DatumBallSimRequest::Validate() const {
  if (!(noise_um >= 0) || !std::isfinite(noise_um))
    return Status(StatusCode::kInvalidArgument, "--noise-um must be a finite number >= 0 (um)");
  if (!(seconds_per_position >= 0) || !std::isfinite(seconds_per_position))
    return Status(StatusCode::kInvalidArgument, "--seconds-per-position must be a finite number >= 0 (s)");
  return Status::Ok();
}

Result<DatumBallSimulation> SimulateDatumBall(const kinematics::MachineModel& model,
                                              const kinematics::ErrorState& errors, const DatumBallSimRequest& request) {
  if (Status s = request.Validate(); !s.ok()) return s;
  auto plan = testpieces::MakeDatumBallPlan(model, request.plan);
  if (!plan.ok()) return plan.status();
  DatumBallSimulation sim;
  sim.plan = std::move(*plan);
  sim.timed = HasThermalTerms(errors);
  std::mt19937_64 rng(request.seed);
  for (std::size_t i = 0; i < sim.plan.positions.size(); ++i) {
    kinematics::BallReading r;
    r.rotary = sim.plan.positions[i];
    if (sim.timed) r.rotary.t_s = static_cast<double>(i) * request.seconds_per_position;
    auto cmd = kinematics::BallCentreCommand(model, errors, r.rotary, sim.plan.ball_part_mm);
    if (!cmd.ok())
      return cmd.status().WithContext(fmt::format("datum ball at {} = {} deg, C = {} deg", TiltLetter(sim.plan),
                                                  DegText(sim.plan.tilt_axis == kinematics::Axis::kB ? r.rotary.b_rad
                                                                                                     : r.rotary.a_rad),
                                                  DegText(r.rotary.c_rad)));
    r.command_mm = *cmd;
    for (int c = 0; c < 3; ++c) r.command_mm(c) += UmToMm(request.noise_um * StandardNormal(rng));
    r.line = i + 4;  // after the version, units and header lines
    sim.readings.push_back(r);
  }
  sim.csv = BallposCsv(sim);
  if (request.truth) sim.truth_yaml = TruthYaml(request, model, errors, sim);
  return sim;
}

Result<DatumBallSimulation> RunDatumBallSimulateStage(const DatumBallSimRequest& request) {
  if (Status s = request.Validate(); !s.ok()) return s;
  auto model = request.machine_path.empty() ? kinematics::MakeMachine(kinematics::MachineType::kBcTable)
                                            : kinematics::LoadMachineModel(request.machine_path);
  if (!model.ok()) return model.status();
  auto errors = kinematics::LoadErrorState(request.errors_path, *model);
  if (!errors.ok())
    return errors.status().file().empty() ? errors.status().WithLocation(request.errors_path) : errors.status();
  auto sim = SimulateDatumBall(*model, *errors, request);
  if (!sim.ok()) return kinematics::AtErrorsFile(sim.status(), request.errors_path);
  return sim;
}

}  // namespace tpcal::pipeline
