#include "pipeline/datum_ball_plan_stage.h"

#include <fmt/format.h>


#include "core/units.h"
#include "gcode/nc_format.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::pipeline {
namespace {

Status PlanArgError(const std::string& message) { return Status(StatusCode::kInvalidArgument, message, "tpcal plan"); }

Result<kinematics::MachineModel> BallPlanMachine(const std::string& path) {
  if (!path.empty()) return kinematics::LoadMachineModel(path);
  return kinematics::MakeMachine(kinematics::MachineType::kBcTable);
}

Result<testpieces::DatumBallPlanOptions> BallPlanOptionsOf(const DatumBallPlanRequest& r) {
  testpieces::DatumBallPlanOptions o;
  if (!r.tilt_deg.empty()) o.tilt_deg = r.tilt_deg;
  if (r.c_step_deg) {
    if (!(*r.c_step_deg > 0.0 && *r.c_step_deg <= 360.0))
      return PlanArgError("--c-step-deg: expected a step in (0, 360] deg, got " + gcode::FormatNumber(*r.c_step_deg, 6));
    o.c_step_deg = *r.c_step_deg;
  }
  if (!r.ball_part_mm.empty()) {
    if (r.ball_part_mm.size() != 3) return PlanArgError("--ball: expected x,y,z (mm, part frame)");
    o.ball_part_mm = Eigen::Vector3d(r.ball_part_mm[0], r.ball_part_mm[1], r.ball_part_mm[2]);
    if (!o.ball_part_mm.allFinite()) return PlanArgError("--ball: expected finite x,y,z");
  }
  if (r.ball_diameter_mm) {
    if (!(*r.ball_diameter_mm > 0.0)) return PlanArgError("--ball-diameter: expected > 0 mm");
    o.ball_diameter_mm = *r.ball_diameter_mm;
  }
  return o;
}



std::string RotaryColumn(const testpieces::DatumBallPlan& plan) {
  return plan.tilt_axis == kinematics::Axis::kA ? "A_deg" : "B_deg";
}

}  // namespace

std::string FormatBallPositionPlan(const testpieces::DatumBallPlan& plan,
                                   const std::vector<Eigen::Vector3d>& centre_commands_mm, const std::string& machine) {
  std::string out = "# tpcal ballpos v1\n# units: mm\n";
  out += "# plan: nominal centring commands of an error-free " + machine +
         " (tpcal plan --instrument datum_ball), not a measurement; ball D " +
         gcode::FormatNumber(plan.ball_diameter_mm, 4) + " mm at part (" + gcode::FormatNumber(plan.ball_part_mm.x(), 4) +
         ", " + gcode::FormatNumber(plan.ball_part_mm.y(), 4) + ", " + gcode::FormatNumber(plan.ball_part_mm.z(), 4) +
         ") mm\n";
  out += RotaryColumn(plan) + ",C_deg,x,y,z\n";
  for (std::size_t i = 0; i < plan.positions.size(); ++i) {
    const kinematics::AxisState& p = plan.positions[i];
    const double tilt_rad = plan.tilt_axis == kinematics::Axis::kA ? p.a_rad : p.b_rad;
    const Eigen::Vector3d& c = centre_commands_mm[i];
    out += gcode::FormatNumber(RadToDeg(tilt_rad), 4) + "," + gcode::FormatNumber(RadToDeg(p.c_rad), 4) + "," +
           gcode::FormatNumber(c.x(), 4) + "," + gcode::FormatNumber(c.y(), 4) + "," + gcode::FormatNumber(c.z(), 4) + "\n";
  }
  return out;
}

Result<DatumBallPlanResult> RunDatumBallPlanStage(const DatumBallPlanRequest& r) {
  auto machine = BallPlanMachine(r.machine_path);
  if (!machine.ok()) return machine.status();
  auto plan_options = BallPlanOptionsOf(r);
  if (!plan_options.ok()) return plan_options.status();
  DatumBallPlanResult out;
  out.machine = machine->name.empty() ? kinematics::MachineTypeName(machine->type) : machine->name;
  auto plan = testpieces::MakeDatumBallPlan(*machine, *plan_options);
  if (!plan.ok()) return plan.status().WithLocation(r.machine_path.empty() ? "tpcal plan" : r.machine_path);
  out.plan = std::move(plan).value();
  auto centres = testpieces::NominalCentringCommands(*machine, out.plan);
  if (!centres.ok()) return centres.status().WithLocation("tpcal plan");
  out.centre_commands_mm = std::move(*centres);
  out.csv = FormatBallPositionPlan(out.plan, out.centre_commands_mm, out.machine);
  out.files.push_back({r.csv_path, out.csv});
  const auto post = [&](const gcode::GcodeOptions& o) { return gcode::PostDatumBallProgram(out.plan, *machine, r.probe, o); };
  if (Status s = PostPlanProgram(r.nc, post, &out.options, &out.posted, &out.files); !s.ok()) return s;
  return out;
}

}  // namespace tpcal::pipeline
