// libFuzzer target: the ball-bar reader of the double-ball-bar test (pipeline/io/ballbar_io.h) on
// arbitrary bytes. It must return rows or a located kParseError with a printable message, never
// crash or hang; what it reads, FormatBallbar writes and it reads back to the same rows.
// Seeds: tests/fuzz/corpus/ballbar/.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "pipeline/io/ballbar_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using tpcal::pipeline::BallbarDirection;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto r = tpcal::pipeline::ParseBallbar(text, "fuzz.csv");
  if (!r.ok()) {
    if (r.status().line() == 0 || r.status().file() != "fuzz.csv") __builtin_trap();
    tpcal::fuzz::CheckStatus(r.status());
    return 0;
  }
  if (r->rows.empty()) __builtin_trap();
  for (const auto& row : r->rows) {
    if (row.line == 0 || row.setup.empty() || row.setup.front() == '#') __builtin_trap();
    if ((row.direction != BallbarDirection::kNone) != r->has_direction) __builtin_trap();
  }
  auto back = tpcal::pipeline::ParseBallbar(tpcal::pipeline::FormatBallbar(*r), "fuzz.csv");
  if (!back.ok() || back->rows.size() != r->rows.size() || back->has_t != r->has_t ||
      back->has_direction != r->has_direction)
    __builtin_trap();
  for (std::size_t i = 0; i < r->rows.size(); ++i) {
    const auto &a = r->rows[i], &b = back->rows[i];
    if (a.setup != b.setup || a.angle_deg != b.angle_deg || a.dl_um != b.dl_um || a.direction != b.direction ||
        a.t_s != b.t_s)
      __builtin_trap();
  }
  return 0;
}
