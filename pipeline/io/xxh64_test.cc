#include "pipeline/xxh64.h"

#include <gtest/gtest.h>

#include <random>
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

TEST(Xxh64, StreamingEqualsOneShotForAnySplit) {
  const std::string data = Bytes0To255Times4PlusXyz();
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    Xxh64State h;
    std::size_t pos = 0;
    while (pos < data.size()) {
      const std::size_t n = std::min<std::size_t>(data.size() - pos, rng() % 70);
      h.Update(data.data() + pos, n);
      pos += n;
    }
    ASSERT_EQ(h.Digest(), 0xe146cb31b65bc21aULL) << trial;
  }
}

}  // namespace
}  // namespace tpcal::pipeline
