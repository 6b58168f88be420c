// The median of a sample (the mean of the two middle values for an even count; 0 for none).
#pragma once

#include <span>
#include <vector>

namespace tpcal {

double Median(std::vector<double> values);

// The same, reordering `values` in place (no copy: for a loop that refills one buffer).
double MedianInPlace(std::span<double> values);

}  // namespace tpcal
