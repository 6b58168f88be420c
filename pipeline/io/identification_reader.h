// A machine-error identification written by tpcal (`tpcal.identification/1` JSON,
// docs/formats/identify_json.md), read back as a reference: who measured (instrument, machine
// type) and each parameter's value and standard uncertainty in its display unit.
#pragma once

#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline {

struct IdentifiedParameter {
  std::string name;           // ISO 230-1 or catalogue name
  std::string unit;           // "um", "urad", ...
  bool identifiable = false;  // false: value and u are absent (null) in the file
  double value = 0.0, u = 0.0;
};

struct IdentificationFile {
  std::string source;
  std::string instrument;  // "" for a test piece's identification
  std::string machine;     // machine type name ("ac_table", ...), "" if absent
  // A parameter file's; of an error-map instrument's, the constant errors identified with its
  // maps (probe_artifacts: the linear axes' squareness), optional there.
  std::vector<IdentifiedParameter> parameters;
  // The parameters' covariance ("parameter_covariance", display units, k = 1, their order),
  // row-major, n x n; empty when the file has none (only u per parameter is then known).
  std::vector<double> parameter_covariance;
  // An error-map instrument's file (probe_artifacts, ballbar): its maps as one tpcal.errors/1
  // document ("errors_yaml"), the number of map entries, those without a number and (ball bar)
  // the families its installations cannot separate ("C: ..."). Empty for a parameter file.
  std::string errors_yaml;
  int map_entries = 0;
  std::vector<std::string> not_identifiable, not_separable;
  // The entries' standard uncertainties by coefficient ("coefficient", "u" > 0; display units).
  std::vector<std::pair<std::string, double>> map_u;
  std::vector<std::string> map_undetermined;  // coefficients of the entries marked not identifiable
  // A ball bar's map response ("axes[].response_to", "axes[].errors[].response"): the errors its
  // model lacks and, per entry coefficient, its change per display unit of each (entry's unit).
  std::vector<std::string> map_unmodelled;
  std::vector<std::pair<std::string, std::vector<double>>> map_unmodelled_response;
};

// Errors (kParseError naming `source`): not JSON (with the line of the fault), a schema other
// than tpcal.identification/1, neither a "parameters" array nor an "errors_yaml" string (an
// error-map instrument's), a parameter without a string "name" or
// "unit" or a boolean "identifiable", an identifiable one whose "value" or "u" is not a finite
// number (u >= 0) — located as parameters[i] ("name"); a ball-bar axis whose "response_to" is not
// a non-empty array of strings, or not the same (names, or absence) on every axis with errors, or
// an entry of such an axis without a string "coefficient" or whose "response" is not one finite
// number per name — located as axes[i] or axes[i].errors[k]; a "parameter_covariance" that is
// not one row of finite numbers per parameter, each as long, symmetric to 1e-9 of its largest,
// positive semi-definite (no eigenvalue below -1e-9 of the largest).
Result<IdentificationFile> ParseIdentificationJson(std::string_view text, const std::string& source);
// The file at `path`; also kIoError when it cannot be read.
Result<IdentificationFile> ReadIdentificationJson(const std::string& path);

}  // namespace tpcal::pipeline
