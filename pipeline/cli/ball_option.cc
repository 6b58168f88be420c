#include "pipeline/cli/ball_option.h"

#include <string>

namespace tpcal::cli {

Result<std::optional<Eigen::Vector3d>> BallOption(const std::vector<double>& values) {
  if (values.empty()) return std::optional<Eigen::Vector3d>();
  if (values.size() != 3)
    return Status(StatusCode::kInvalidArgument,
                  "--ball: expected X,Y,Z (mm, part frame), got " + std::to_string(values.size()) + " numbers");
  const Eigen::Vector3d b(values[0], values[1], values[2]);
  if (!b.allFinite()) return Status(StatusCode::kInvalidArgument, "--ball: expected finite X,Y,Z (mm, part frame)");
  return std::optional<Eigen::Vector3d>(b);
}

}  // namespace tpcal::cli
