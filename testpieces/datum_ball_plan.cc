#include "testpieces/datum_ball_plan.h"

#include <cmath>
#include <string>

#include "core/units.h"
#include "kinematics/datum_ball.h"

namespace tpcal::testpieces {
namespace {

Status CheckOptions(const DatumBallPlanOptions& options) {
  if (options.tilt_deg.empty()) return Status(StatusCode::kInvalidArgument, "datum-ball plan: no tilt angle");
  if (!(options.c_step_deg > 0.0 && options.c_step_deg <= 360.0))
    return Status(StatusCode::kInvalidArgument, "datum-ball plan: C step " + std::to_string(options.c_step_deg) +
                                   " deg, expected in (0, 360]");
  if (!(options.ball_diameter_mm > 0.0))
    return Status(StatusCode::kInvalidArgument, "datum-ball plan: ball diameter must be > 0 mm");
  if (!options.ball_part_mm.allFinite()) return Status(StatusCode::kInvalidArgument, "datum-ball plan: ball centre not finite");
  return Status::Ok();
}

}  // namespace

Result<DatumBallPlan> MakeDatumBallPlan(const kinematics::MachineModel& model, const DatumBallPlanOptions& options) {
  if (model.type != kinematics::MachineType::kBcTable && model.type != kinematics::MachineType::kAcTable)
    return Status(StatusCode::kInvalidArgument, std::string("datum-ball plan: machine type ") + kinematics::MachineTypeName(model.type) +
                                   ", expected bc_table or ac_table");
  if (Status s = CheckOptions(options); !s.ok()) return s;
  DatumBallPlan plan;
  plan.tilt_axis = model.type == kinematics::MachineType::kBcTable ? kinematics::Axis::kB : kinematics::Axis::kA;
  plan.ball_part_mm = options.ball_part_mm;
  plan.ball_diameter_mm = options.ball_diameter_mm;
  const int c_count = static_cast<int>(std::ceil(360.0 / options.c_step_deg - 1e-9));
  for (double tilt : options.tilt_deg) {
    for (int k = 0; k < c_count; ++k) {
      kinematics::AxisState s;
      (plan.tilt_axis == kinematics::Axis::kB ? s.b_rad : s.a_rad) = DegToRad(tilt);
      s.c_rad = DegToRad(k * options.c_step_deg);
      if (Status st = kinematics::CheckStrokes(model, s); !st.ok())
        return Status(StatusCode::kInvalidArgument, "datum-ball plan: tilt " + std::to_string(tilt) + " deg: " + st.message());
      plan.positions.push_back(s);
    }
  }
  return plan;
}

Result<std::vector<Eigen::Vector3d>> NominalCentringCommands(const kinematics::MachineModel& model,
                                                             const DatumBallPlan& plan) {
  const kinematics::ErrorState zero(model);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < plan.positions.size(); ++i) {
    auto c = kinematics::BallCentreCommand(model, zero, plan.positions[i], plan.ball_part_mm);
    if (!c.ok()) return c.status().WithContext("datum-ball plan position " + std::to_string(i + 1));
    out.push_back(*c);
  }
  return out;
}

}  // namespace tpcal::testpieces
