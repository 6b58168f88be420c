#include "core/median.h"

#include <algorithm>
#include <cstddef>

namespace tpcal {

double Median(std::vector<double> values) { return MedianInPlace(values); }

double MedianInPlace(std::span<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t h = values.size() / 2;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(h);
  std::nth_element(values.begin(), mid, values.end());
  const double upper = *mid;
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), mid));
}

}  // namespace tpcal
