#include "pipeline/plan_stage.h"

#include <vector>

#include "pipeline/io/point_io.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

// The plan as a contract PointSet: datum-frame points and normals, then the extra columns.
PointSet PlanAsPointSet(const testpieces::ProbingPlan& plan, const kinematics::MachineModel& machine) {
  PointSet ps = testpieces::PlanPointSet(plan);
  // No negative zeros in the file ("-0" reads back as 0 but looks like a sign).
  for (auto* v : {&ps.xyz_mm, &ps.normal})
    for (Eigen::Vector3d& p : *v) p = p.array() + 0.0;
  const std::vector<testpieces::PlanRow> rows = testpieces::PlanRows(plan);
  for (const std::string& col : testpieces::PlanExtraColumns(machine)) {
    PointAttribute a;
    a.name = col;
    a.values.reserve(rows.size());
    for (const testpieces::PlanRow& r : rows) {
      double v = 0;
      if (col == "op") v = r.op;
      else if (col == "t_s") v = r.t_s;
      else if (col == "A_deg") v = r.a_deg;
      else if (col == "B_deg") v = r.b_deg;
      else if (col == "C_deg") v = r.c_deg;
      else if (col == "X_mm") v = r.x_mm;
      else if (col == "Y_mm") v = r.y_mm;
      else if (col == "Z_mm") v = r.z_mm;
      a.values.push_back(v);
    }
    ps.attributes.push_back(std::move(a));
  }
  return ps;
}

}  // namespace

Result<PlanStageResult> RunPlanStage(const LoadedPiece& loaded, const std::string& csv_path) {
  auto plan = testpieces::MakeProbingPlan(loaded.piece);
  if (!plan.ok()) return plan.status().WithContext("probing plan of " + loaded.piece.name);
  PlanStageResult out;
  out.points = PlanAsPointSet(*plan, loaded.machine);
  PointWriteOptions wo;
  wo.kind = PointFileKind::kPlan;
  auto text = FormatPointCsv(out.points, wo);
  if (!text.ok()) return text.status().WithLocation(csv_path);
  out.csv = std::move(*text);
  out.plan = std::move(*plan);
  return out;
}

}  // namespace tpcal::pipeline
