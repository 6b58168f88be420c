// The machine a ball-bar test runs on, one rule for its plan, simulation and identification.
#pragma once

#include <string>

#include "core/status.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/machine_model.h"

namespace tpcal::pipeline {

// The tpcal.machine/1 file at `machine_path`; when empty, the nominal bhead_ctable (seed 003's
// machine) if an installation of `setup` turns a rotary axis, else the nominal xyz (circles only).
// Errors: those of LoadMachineModel (file:line).
Result<kinematics::MachineModel> BallbarMachine(const std::string& machine_path, const kinematics::BallbarSetup& setup);

}  // namespace tpcal::pipeline
