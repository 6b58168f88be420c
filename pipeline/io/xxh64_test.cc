#include "pipeline/io/xxh64.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal::pipeline {
namespace {

std::string Bytes0To255Times4PlusXyz() {
  std::string s;
  for (int r = 0; r < 4; ++r)
    for (int b = 0; b < 256; ++b) s.push_back(static_cast<char>(b));
  return s + "xyz";
}

// Reference values computed with the system's libxxhash 0.8.1 (XXH64).
TEST(Xxh64, MatchesReferenceImplementation) {
  EXPECT_EQ(Xxh64(""), 0xef46db3751d8e999ULL);
  EXPECT_EQ(Xxh64("abc"), 0x44bc2cf5ad770999ULL);
  EXPECT_EQ(Xxh64("abc", 7), 0x9e755206156676d7ULL);
  EXPECT_EQ(Xxh64("0123456789abcdef0123456789abcdef0"), 0xe87684f08d6d0816ULL);
  EXPECT_EQ(Xxh64("tpcal points v1", 12345), 0x18364e15fe8f83b1ULL);
  EXPECT_EQ(Xxh64(Bytes0To255Times4PlusXyz()), 0xe146cb31b65bc21aULL);
}

}  // namespace
}  // namespace tpcal::pipeline
