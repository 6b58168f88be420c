// libFuzzer target: the probed-point reader of the artifact probing test (pipeline/io/probepts_io.h)
// on arbitrary bytes. It must return rows or a located kParseError with a printable message,
// never crash or hang; what it reads, FormatProbePoints writes and it reads back to the same rows.
// Seeds: tests/fuzz/corpus/probepts/.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "pipeline/io/probepts_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto r = tpcal::pipeline::ParseProbePoints(text, "fuzz.csv");
  if (!r.ok()) {
    if (r.status().line() == 0 || r.status().file() != "fuzz.csv") __builtin_trap();
    tpcal::fuzz::CheckStatus(r.status());
    return 0;
  }
  if (r->rows.empty() || r->rotary_axes.empty()) __builtin_trap();
  for (const auto& row : r->rows) {
    if (row.line == 0 || row.rotary_deg.size() != r->rotary_axes.size()) __builtin_trap();
    if (row.artifact.empty() || row.face.empty() || row.u_um < 0.0) __builtin_trap();
    if (!(std::abs(row.approach.norm() - 1.0) <= 1e-6)) __builtin_trap();
  }
  // Format -> Parse keeps every row (names are trimmed, comma-free fields, so they survive).
  auto back = tpcal::pipeline::ParseProbePoints(tpcal::pipeline::FormatProbePoints(*r), "fuzz.csv");
  if (!back.ok() || back->rows.size() != r->rows.size() || back->is_plan != r->is_plan) __builtin_trap();
  for (std::size_t i = 0; i < r->rows.size(); ++i) {
    const auto &a = r->rows[i], &b = back->rows[i];
    if (a.rotary_deg != b.rotary_deg || a.artifact != b.artifact || a.face != b.face || a.point_mm != b.point_mm ||
        a.approach != b.approach || a.t_s != b.t_s || a.u_um != b.u_um)
      __builtin_trap();
  }
  return 0;
}
