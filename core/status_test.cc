#include "core/status.h"

#include <gtest/gtest.h>

namespace tpcal {
namespace {

TEST(Status, FormatsFileLineMessage) {
  Status s(StatusCode::kParseError, "expected a number in column 'x', got 'abc'", "cmm.csv", 12);
  EXPECT_EQ(s.ToString(), "cmm.csv:12: expected a number in column 'x', got 'abc'");
  EXPECT_EQ(Status(StatusCode::kIoError, "cannot open", "a.csv").ToString(), "a.csv: cannot open");
  EXPECT_EQ(Status(StatusCode::kDegenerate, "collinear").ToString(), "collinear");
  // No line (the whole file at fault): never "line 0" nor ":0:".
  EXPECT_EQ(Status(StatusCode::kParseError, "empty file", "e.pcd", 0).ToString(), "e.pcd: empty file");
  EXPECT_EQ(Status(StatusCode::kParseError, "empty file").WithLocation("e.pcd", 0).ToString(), "e.pcd: empty file");
  EXPECT_TRUE(Status::Ok().ok());
}

TEST(Result, HoldsValueOrError) {
  Result<int> good = 3;
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, 3);
  Result<int> bad = Status(StatusCode::kTooFewPoints, "need 3 points, got 2");
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kTooFewPoints);
  EXPECT_EQ(bad.status().WithLocation("f.csv", 4).ToString(), "f.csv:4: need 3 points, got 2");
}

}  // namespace
}  // namespace tpcal
