// Machine model files (YAML, schema tpcal.machine/1). Example: samples/machines/ac_table.yaml.
//
//   schema: tpcal.machine/1          # optional; if present must be this
//   name: seed 002 A/C swiveling table
//   type: ac_table                   # ac_table | bc_table | bhead_ctable | xyz
//   workpiece_chain: [A, C]          # optional, bed -> part (default per type, machine_model.h)
//   tool_chain: [X, Y, Z]            # optional, bed -> tool
//   axes:                            # every axis of the chains, once
//     X: {min_mm: -600, max_mm: 600, pivot_mm: [0, 0, 0]}   # pivot optional (linear: angular
//     A: {min_deg: -120, max_deg: 30, pivot_mm: [0, 0, 0]}  #   error reference point)
//     C: {continuous: true, pivot_mm: [0, 0, 0]}
//
// Errors name the file, the line and what was expected; unknown keys are errors.
#pragma once

#include <string>

#include "core/status.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

Result<MachineModel> LoadMachineModel(const std::string& path);
// `source` names the text in messages (file name or "<string>").
Result<MachineModel> ParseMachineModel(const std::string& yaml_text, const std::string& source);
// YAML text that ParseMachineModel reads back to the same model.
std::string FormatMachineModel(const MachineModel& model);

}  // namespace tpcal::kinematics
