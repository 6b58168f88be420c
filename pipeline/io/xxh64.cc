#include "pipeline/io/xxh64.h"

#include <xxhash.h>

namespace tpcal::pipeline {

std::uint64_t Xxh64(std::string_view bytes, std::uint64_t seed) { return XXH64(bytes.data(), bytes.size(), seed); }

}  // namespace tpcal::pipeline
