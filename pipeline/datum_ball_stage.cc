#include "pipeline/datum_ball_stage.h"

#include <algorithm>

#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/io/ballpos_reader.h"

namespace tpcal::pipeline {
namespace {

Result<kinematics::MachineModel> BallMachine(const DatumBallRequest& r, const BallPositionFile& file) {
  if (!r.machine_path.empty()) return kinematics::LoadMachineModel(r.machine_path);
  const bool b = std::find(file.rotary_axes.begin(), file.rotary_axes.end(), 'B') != file.rotary_axes.end();
  return kinematics::MakeMachine(b ? kinematics::MachineType::kBcTable : kinematics::MachineType::kAcTable);
}

// The file's rotary columns must be the machine's rotary axes.
Status CheckRotaryColumns(const kinematics::MachineModel& m, const BallPositionFile& file) {
  for (char axis : {'A', 'B', 'C'}) {
    const bool in_file = std::find(file.rotary_axes.begin(), file.rotary_axes.end(), axis) != file.rotary_axes.end();
    const bool in_machine = m.HasAxis(*kinematics::AxisFromName(std::string(1, axis)));
    if (in_file != in_machine)
      return Status(StatusCode::kInvalidArgument,
                    std::string(1, axis) + "_deg: the machine (" + kinematics::MachineTypeName(m.type) + ") " +
                        (in_machine ? "has this axis but the file has no column for it" : "has no such axis"),
                    file.source);
  }
  return Status::Ok();
}

// The identifiable errors as tpcal.errors/1; the others are named in a comment, not given a value.
Result<std::string> IdentifiedErrorsYaml(const kinematics::MachineModel& m, const kinematics::DatumBallResult& r) {
  kinematics::ErrorState e(m);
  std::string left_out;
  for (const auto& p : r.parameters) {
    if (!p.identifiable) {
      left_out += (left_out.empty() ? "" : ", ") + p.name;
      continue;
    }
    auto info = kinematics::LookupParameter(m, p.name);
    if (!info.ok()) return info.status();
    const double internal = info->quantity == kinematics::Quantity::kAngle ? p.value * 1e-6 : UmToMm(p.value);
    if (Status s = e.SetParameter(m, p.name, internal); !s.ok()) return s;
  }
  std::string out = "# identified from a datum-ball test (tpcal identify --instrument datum_ball)\n";
  if (!left_out.empty()) out += "# not identifiable by this plan, left out: " + left_out + "\n";
  return out + kinematics::FormatErrorState(e, m);
}

}  // namespace

Result<DatumBallReport> RunDatumBallStage(const DatumBallRequest& r) {
  auto file = ReadBallPositions(r.path);
  if (!file.ok()) return file.status();
  auto machine = BallMachine(r, *file);
  if (!machine.ok()) return machine.status();
  if (Status s = CheckRotaryColumns(*machine, *file); !s.ok()) return s;
  std::vector<kinematics::BallReading> readings;
  std::vector<std::size_t> lines;
  for (const auto& row : file->rows) {
    kinematics::BallReading b;
    for (const auto& [axis, deg] : row.rotary_deg) (axis == 'A' ? b.rotary.a_rad : axis == 'B' ? b.rotary.b_rad : b.rotary.c_rad) = DegToRad(deg);
    b.rotary.t_s = row.t_s;
    b.command_mm = row.centre_mm;
    b.line = row.line;
    b.u_um = row.u_um;
    readings.push_back(b);
    lines.push_back(row.line);
  }
  kinematics::DatumBallOptions options;
  options.parameters = r.parameters;
  options.ball_part_mm = r.ball_part_mm;
  auto result = kinematics::IdentifyDatumBall(*machine, readings, options);
  if (!result.ok()) {
    Status s = result.status();
    return s.file().empty() ? s.WithLocation(r.path, s.line()) : s;
  }
  auto yaml = IdentifiedErrorsYaml(*machine, *result);
  if (!yaml.ok()) return yaml.status();
  return DatumBallReport{r.path, kinematics::MachineTypeName(machine->type), std::move(lines), std::move(*result),
                         std::move(*yaml), r.ball_part_mm.has_value()};
}

}  // namespace tpcal::pipeline
