#include "pipeline/ballbar_plan_stage.h"

#include <cmath>
#include <set>

#include "gcode/nc_format.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/ballbar_machine.h"

namespace tpcal::pipeline {
namespace {

// File-local names carry a BarPlan prefix: a unity build merges this file with the other stages.

Status BarPlanArgError(const std::string& message, const std::string& command) {
  return Status(StatusCode::kInvalidArgument, message, command);
}

// 0, step, 2 step, ... up to `end_deg` (its sign gives the direction), end included when reached.
std::vector<double> BarPlanRange(double end_deg, double step_deg) {
  std::vector<double> out;
  const double sign = end_deg < 0 ? -1.0 : 1.0;
  const int n = static_cast<int>(std::floor(std::abs(end_deg) / step_deg + 1e-9));
  for (int k = 0; k <= n; ++k) out.push_back(sign * step_deg * k + 0.0);
  return out;
}

std::vector<double> BarPlanDefaultAngles(const kinematics::BallbarInstallation& inst, const BallbarAngles& a) {
  if (!a.angles_deg.empty()) return a.angles_deg;
  if (inst.kind == kinematics::BallbarKind::kCircle) {
    std::vector<double> out = BarPlanRange(360.0, a.step_deg.value_or(1.0));
    if (out.size() > 1 && std::abs(out.back() - 360.0) < 1e-9) out.pop_back();  // 360 is 0 again
    return out;
  }
  if (inst.axis == kinematics::Axis::kC) return BarPlanRange(360.0, a.step_deg.value_or(20.0));
  return BarPlanRange(-100.0, a.step_deg.value_or(5.0));
}

}  // namespace

Status BallbarAngles::Validate(const std::string& command) const {
  if (step_deg && !angles_deg.empty()) return BarPlanArgError("--step-deg and --angles-deg: give one", command);
  if (step_deg && !(std::isfinite(*step_deg) && *step_deg > 0.0 && *step_deg <= 360.0))
    return BarPlanArgError("--step-deg: expected a step in (0, 360] deg, got " + gcode::FormatNumber(*step_deg, 6),
                           command);
  std::set<double> seen;
  for (double a : angles_deg) {
    if (!std::isfinite(a)) return BarPlanArgError("--angles-deg: expected finite angles (deg)", command);
    if (!seen.insert(a).second)
      return BarPlanArgError("--angles-deg: " + gcode::FormatNumber(a, 6) + " deg is given twice", command);
  }
  return Status::Ok();
}

Result<std::vector<gcode::BallbarProgramTest>> MakeBallbarTests(const kinematics::MachineModel& model,
                                                                const kinematics::BallbarSetup& setup,
                                                                const BallbarAngles& angles,
                                                                const std::string& setup_path,
                                                                const std::string& command) {
  if (Status s = angles.Validate(command); !s.ok()) return s;
  std::vector<gcode::BallbarProgramTest> tests;
  for (const kinematics::BallbarInstallation& inst : setup.installations) {
    auto g = kinematics::MakeBallbarGeometry(model, inst);
    if (!g.ok()) return g.status().file().empty() ? g.status().WithLocation(setup_path) : g.status();
    tests.push_back({std::move(g).value(), BarPlanDefaultAngles(inst, angles)});
  }
  return tests;
}

BallbarFile BallbarPlanReadings(const std::vector<gcode::BallbarProgramTest>& tests) {
  BallbarFile file;
  for (const gcode::BallbarProgramTest& t : tests)
    file.has_direction |= t.geometry.installation.kind == kinematics::BallbarKind::kCircle;
  for (const gcode::BallbarProgramTest& t : tests) {
    BallbarRow row;
    row.setup = t.geometry.installation.name;
    const std::vector<double>& a = t.angles_deg;
    if (t.geometry.installation.kind == kinematics::BallbarKind::kCircle) {
      for (const BallbarDirection d : {BallbarDirection::kCcw, BallbarDirection::kCw}) {
        row.direction = d;
        for (std::size_t k = 0; k < a.size(); ++k) {
          row.angle_deg = d == BallbarDirection::kCcw ? a[k] : a[a.size() - 1 - k];
          file.rows.push_back(row);
        }
      }
      continue;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
      row.angle_deg = a[i];
      if (file.has_direction) {
        const double step = a.size() < 2 ? 1.0 : i == 0 ? a[1] - a[0] : a[i] - a[i - 1];
        row.direction = step < 0 ? BallbarDirection::kCw : BallbarDirection::kCcw;
      }
      file.rows.push_back(row);
    }
  }
  return file;
}

std::string FormatBallbarPlan(const BallbarFile& readings, const std::string& machine) {
  std::string text = FormatBallbar(readings);
  const std::string units = "# units: mm\n";
  const std::size_t at = text.find(units);
  if (at != std::string::npos)
    text.insert(at + units.size(), "# plan: nominal readings of an error-free " + machine +
                                       " (tpcal plan --instrument ballbar), not a measurement: every dl_um is 0\n");
  return text;
}

Result<BallbarPlanResult> RunBallbarPlanStage(const BallbarPlanRequest& r) {
  if (r.setup_path.empty()) return BarPlanArgError("--setup S.yaml is needed with --instrument ballbar", "tpcal plan");
  auto setup = kinematics::LoadBallbarSetup(r.setup_path);
  if (!setup.ok()) return setup.status().file().empty() ? setup.status().WithLocation(r.setup_path) : setup.status();
  auto machine = BallbarMachine(r.machine_path, *setup);
  if (!machine.ok()) return machine.status();
  BallbarPlanResult out;
  out.setup = std::move(setup).value();
  out.machine = machine->name.empty() ? kinematics::MachineTypeName(machine->type) : machine->name;
  if (!(std::isfinite(r.program.feed_mm_per_min) && r.program.feed_mm_per_min > 0.0))
    return BarPlanArgError("--feed-mm-per-min: expected a feed > 0 mm/min, got " +
                               gcode::FormatNumber(r.program.feed_mm_per_min, 6),
                           "tpcal plan");
  auto tests = MakeBallbarTests(*machine, out.setup, r.angles, r.setup_path, "tpcal plan");
  if (!tests.ok()) return tests.status();
  out.tests = std::move(tests).value();
  out.readings = BallbarPlanReadings(out.tests);
  out.csv = FormatBallbarPlan(out.readings, out.machine);
  out.files.push_back({r.csv_path, out.csv});
  const auto post = [&](const gcode::GcodeOptions& o) {
    return gcode::PostBallbarProgram(out.tests, *machine, r.program, o);
  };
  if (Status s = PostPlanProgram(r.nc, post, &out.options, &out.posted, &out.files); !s.ok()) return s;
  return out;
}

}  // namespace tpcal::pipeline
