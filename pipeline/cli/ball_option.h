// `--ball X,Y,Z`: the datum ball's centre in the part frame (mm), as plan, simulate and identify
// take it.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/status.h"

namespace tpcal::cli {

// Unset when `values` is empty. Errors: kInvalidArgument "--ball: expected X,Y,Z (mm, part
// frame), got N numbers" or "... finite".
Result<std::optional<Eigen::Vector3d>> BallOption(const std::vector<double>& values);

}  // namespace tpcal::cli
