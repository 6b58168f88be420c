// XXH64 content digests (Debian's libxxhash): the digest of a point file that result.json
// records, equal to `xxhsum -H1` of the same bytes.
#pragma once

#include <cstdint>
#include <string_view>

namespace tpcal::pipeline {

// XXH64 of `bytes` with `seed`. Never fails.
std::uint64_t Xxh64(std::string_view bytes, std::uint64_t seed = 0);

}  // namespace tpcal::pipeline
