#include "core/median.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace tpcal {
namespace {

TEST(Median, OddEvenAndEmpty) {
  EXPECT_EQ(Median({}), 0.0);
  EXPECT_EQ(Median({3.0}), 3.0);
  EXPECT_EQ(Median({5.0, -1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);  // mean of the two middle values
  EXPECT_EQ(Median({1.0, 1.0, 100.0, 1.0}), 1.0);
}

// In place: the same median from a buffer that keeps its values (reordered) and its storage.
TEST(Median, InPlaceKeepsTheBuffer) {
  std::vector<double> v = {4.0, 1.0, 3.0, 2.0, 9.0};
  const double* data = v.data();
  EXPECT_EQ(MedianInPlace(v), 3.0);
  EXPECT_EQ(v.data(), data);
  std::sort(v.begin(), v.end());
  EXPECT_EQ(v, (std::vector<double>{1.0, 2.0, 3.0, 4.0, 9.0}));
  v.pop_back();
  EXPECT_EQ(MedianInPlace(v), 2.5);
}

}  // namespace
}  // namespace tpcal
