// libFuzzer target: the ball-position reader of the datum-ball test (pipeline/io/ballpos_reader.h)
// on arbitrary bytes. It must return rows or a located kParseError, never crash or hang.
// Seeds: tests/fuzz/corpus/ballpos/.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "pipeline/io/ballpos_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto r = tpcal::pipeline::ParseBallPositions(text, "fuzz.csv");
  if (r.ok()) {
    if (r->rows.empty() || r->rotary_axes.empty()) __builtin_trap();
    for (const auto& row : r->rows)
      if (row.line == 0 || row.rotary_deg.size() != r->rotary_axes.size()) __builtin_trap();
  } else if (r.status().line() == 0 || r.status().file() != "fuzz.csv") {
    __builtin_trap();
  }
  return 0;
}
