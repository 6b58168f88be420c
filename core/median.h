// The median of a sample (the mean of the two middle values for an even count; 0 for none).
#pragma once

#include <vector>

namespace tpcal {

double Median(std::vector<double> values);

}  // namespace tpcal
