#include "core/median.h"

#include <gtest/gtest.h>

namespace tpcal {
namespace {

TEST(Median, OddEvenAndEmpty) {
  EXPECT_EQ(Median({}), 0.0);
  EXPECT_EQ(Median({3.0}), 3.0);
  EXPECT_EQ(Median({5.0, -1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);  // mean of the two middle values
  EXPECT_EQ(Median({1.0, 1.0, 100.0, 1.0}), 1.0);
}

}  // namespace
}  // namespace tpcal
