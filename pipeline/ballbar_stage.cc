#include "pipeline/ballbar_stage.h"

#include <algorithm>
#include <map>

#include "kinematics/ballbar.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/ballbar_machine.h"
#include "pipeline/io/ballbar_io.h"

namespace tpcal::pipeline {
namespace {

using kinematics::BallbarInstallation;
using kinematics::BallbarKind;

// The readings of one turned axis, grouped by installation (geometry index in first-seen order).
struct BbsAxisInput {
  kinematics::Axis axis = kinematics::Axis::kC;
  std::vector<std::string> names;
  std::vector<kinematics::BallbarGeometry> geometry;
  std::vector<kinematics::BallbarReading> readings;
  std::vector<std::size_t> lines;
};

struct BbsCircleInput {
  const BallbarInstallation* installation = nullptr;
  std::vector<kinematics::CircularReading> readings;
  std::vector<std::size_t> lines;
};

struct BbsInputs {
  std::vector<BbsAxisInput> axes;
  std::vector<BbsCircleInput> circles;
};

Status BbsAddRotary(const kinematics::MachineModel& m, const BallbarInstallation& inst, const BallbarRow& row,
                    const std::string& setup_path, BbsInputs* in) {
  auto axis = std::find_if(in->axes.begin(), in->axes.end(), [&](const BbsAxisInput& a) { return a.axis == inst.axis; });
  if (axis == in->axes.end()) {
    in->axes.emplace_back();
    axis = std::prev(in->axes.end());
    axis->axis = inst.axis;
  }
  auto at = std::find(axis->names.begin(), axis->names.end(), inst.name);
  if (at == axis->names.end()) {
    auto g = kinematics::MakeBallbarGeometry(m, inst);
    if (!g.ok()) return g.status().WithContext("installation '" + inst.name + "'").WithLocation(setup_path, 0);
    axis->names.push_back(inst.name);
    axis->geometry.push_back(*g);
    at = std::prev(axis->names.end());
  }
  kinematics::BallbarReading rd;
  rd.installation = static_cast<int>(at - axis->names.begin());
  rd.angle_deg = row.angle_deg;
  rd.dl_um = row.dl_um;
  rd.t_s = row.t_s;
  rd.line = static_cast<int>(row.line);
  axis->readings.push_back(rd);
  axis->lines.push_back(row.line);
  return Status();
}

void BbsAddCircle(const BallbarInstallation& inst, const BallbarRow& row, BbsInputs* in) {
  auto c = std::find_if(in->circles.begin(), in->circles.end(),
                        [&](const BbsCircleInput& x) { return x.installation == &inst; });
  if (c == in->circles.end()) {
    in->circles.emplace_back();
    c = std::prev(in->circles.end());
    c->installation = &inst;
  }
  kinematics::CircularReading rd;
  rd.angle_deg = row.angle_deg;
  rd.dl_um = row.dl_um;
  rd.ccw = row.direction != BallbarDirection::kCw;
  rd.line = static_cast<int>(row.line);
  c->readings.push_back(rd);
  c->lines.push_back(row.line);
}

Result<BbsInputs> BbsPair(const kinematics::MachineModel& m, const kinematics::BallbarSetup& setup,
                          const BallbarFile& file, const std::string& setup_path) {
  BbsInputs in;
  for (const BallbarRow& row : file.rows) {
    const BallbarInstallation* inst = setup.Find(row.setup);
    if (inst == nullptr) {
      return Status(StatusCode::kInvalidArgument, "setup '" + row.setup + "' is not an installation of " + setup_path,
                    file.source, row.line);
    }
    if (inst->kind == BallbarKind::kCircle) {
      BbsAddCircle(*inst, row, &in);
    } else {
      TPCAL_RETURN_IF_ERROR(BbsAddRotary(m, *inst, row, setup_path, &in));
    }
  }
  return in;
}

// The tables of every identified axis in one tpcal.errors/1 text, with the conventions and the
// entries written as 0 because the installations cannot determine them.
std::string BbsErrorsYaml(const kinematics::MachineModel& m, const std::vector<BallbarAxisReport>& axes) {
  if (axes.empty()) return "";
  kinematics::ErrorState all(m);
  std::string out = "# error motions identified from a double-ball-bar test (tpcal identify --instrument ballbar)\n";
  for (const BallbarAxisReport& a : axes) {
    for (const auto& term : a.result.errors.terms()) (void)all.AddTerm(m, term);
    for (const std::string& c : a.result.conventions) out += "# " + a.axis + ": " + c + "\n";
    for (const std::string& f : a.result.not_separable) out += "# " + a.axis + " not separable: " + f + "\n";
    if (!a.result.not_identifiable.empty()) {
      out += "# " + a.axis + " not identifiable by these installations, written as 0:";
      for (const std::string& n : a.result.not_identifiable) out += " " + n;
      out += "\n";
    }
  }
  return out + kinematics::FormatErrorState(all, m);
}

}  // namespace

Result<BallbarReport> RunBallbarStage(const BallbarRequest& r) {
  if (r.setup_path.empty()) {
    return Status(StatusCode::kInvalidArgument, "the ball-bar test needs its set-up (--setup S.yaml)");
  }
  auto file = ReadBallbar(r.path);
  if (!file.ok()) return file.status();
  auto setup = kinematics::LoadBallbarSetup(r.setup_path);
  if (!setup.ok()) return setup.status();
  auto machine = BallbarMachine(r.machine_path, *setup);
  if (!machine.ok()) return machine.status();
  auto in = BbsPair(*machine, *setup, *file, r.setup_path);
  if (!in.ok()) return in.status();
  BallbarReport report;
  report.source = r.path;
  report.setup_source = r.setup_path;
  report.machine = kinematics::MachineTypeName(machine->type);
  report.readings = static_cast<int>(file->rows.size());
  for (BbsAxisInput& a : in->axes) {
    kinematics::BallbarIdentificationOptions options;
    options.axis = a.axis;
    auto result = kinematics::IdentifyBallbar(*machine, a.geometry, a.readings, options);
    if (!result.ok()) {
      Status s = result.status();
      return s.file().empty() ? s.WithLocation(r.path, s.line()) : s;
    }
    BallbarAxisReport axis(std::move(*result));
    for (const std::string& name : r.map_response_to)
      if (kinematics::LookupParameter(*machine, name).ok()) axis.response_to.push_back(name);
    if (!axis.response_to.empty()) {
      auto response = kinematics::BallbarMapResponse(*machine, a.geometry, a.readings, axis.response_to, options);
      if (!response.ok()) return response.status().WithLocation(r.path, 0);
      axis.map_response = std::move(*response);
    }
    axis.axis = std::string(1, kinematics::AxisLetter(a.axis));
    axis.installations = a.names;
    axis.lines = a.lines;
    report.axes.push_back(std::move(axis));
  }
  for (BbsCircleInput& c : in->circles) {
    auto result = kinematics::AnalyseCircularTest(*c.installation, c.readings);
    if (!result.ok()) {
      Status s = result.status().WithContext("circle '" + c.installation->name + "'");
      return s.file().empty() ? s.WithLocation(r.path, s.line()) : s;
    }
    report.circles.push_back({c.installation->name, c.lines, std::move(*result)});
  }
  report.errors_yaml = BbsErrorsYaml(*machine, report.axes);
  return report;
}

}  // namespace tpcal::pipeline
