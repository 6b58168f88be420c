// XXH64 (Yann Collet's xxHash, 64-bit variant; algorithm as published in the xxHash
// specification), one-shot and streaming. Used as the content checksum of the point cache;
// results equal `xxhsum -H1` / libxxhash XXH64 with the same seed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace tpcal::pipeline {

// Streaming XXH64: Update() any number of times with any split, Digest() at the end; the
// result does not depend on how the input was split.
// One-shot XXH64 of `bytes`.
std::uint64_t Xxh64(std::string_view bytes, std::uint64_t seed = 0);

class Xxh64State {
 public:
  explicit Xxh64State(std::uint64_t seed = 0);
  void Update(const void* data, std::size_t size);
  void Update(std::string_view bytes) { Update(bytes.data(), bytes.size()); }
  std::uint64_t Digest() const;

 private:
  std::uint64_t v_[4];
  std::uint64_t seed_;
  std::uint64_t total_ = 0;
  unsigned char buf_[32];
  std::size_t buf_size_ = 0;
};

}  // namespace tpcal::pipeline
