#include "fitting/fit_result.h"

#include <cmath>
#include <string>

namespace tpcal::fitting {

const char* TerminationName(Termination t) {
  switch (t) {
    case Termination::kClosedForm: return "closed_form";
    case Termination::kConverged: return "converged";
    case Termination::kMaxIterations: return "max_iterations";
  }
  return "unknown";
}

Status FitOptions::Validate() const {
  if (max_iterations < 1) {
    return Status(StatusCode::kInvalidArgument,
                  "FitOptions.max_iterations must be >= 1, got " + std::to_string(max_iterations));
  }
  // The step tolerance is relative to the feature size; above 1e-3 a "converged" fit could
  // be off by more than the ISO 10360-6 accuracy class on a 100 mm feature.
  if (!(std::isfinite(step_tolerance_mm) && step_tolerance_mm > 0.0 && step_tolerance_mm <= 1e-3)) {
    return Status(StatusCode::kInvalidArgument,
                  "FitOptions.step_tolerance_mm must be in (0, 1e-3], got " + std::to_string(step_tolerance_mm));
  }
  return Status::Ok();
}

}  // namespace tpcal::fitting
