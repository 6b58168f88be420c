// Options and names shared by the minimum-zone evaluations (fitting/minimum_zone.h).
#include "fitting/minimum_zone.h"

#include <cmath>

namespace tpcal::fitting {

const char* OptimalityScopeName(OptimalityScope scope) {
  switch (scope) {
    case OptimalityScope::kNotVerified: return "not_verified";
    case OptimalityScope::kLocal: return "local";
    case OptimalityScope::kGlobal: return "global";
  }
  return "unknown";
}

Status ZoneOptions::Validate() const {
  if (!(gap_tolerance_mm >= 0) || !std::isfinite(gap_tolerance_mm)) {
    return {StatusCode::kInvalidArgument, "ZoneOptions.gap_tolerance_mm must be finite and >= 0"};
  }
  if (max_iterations < 1) {
    return {StatusCode::kInvalidArgument, "ZoneOptions.max_iterations must be >= 1"};
  }
  if (max_global_boxes < 1) {
    return {StatusCode::kInvalidArgument, "ZoneOptions.max_global_boxes must be >= 1"};
  }
  return Status::Ok();
}

}  // namespace tpcal::fitting
