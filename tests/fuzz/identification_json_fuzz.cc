// libFuzzer target: the identification JSON reader (pipeline/io/identification_reader.h, what
// `diagnose --reference` reads) on arbitrary bytes. It must return a well-formed file or a
// kParseError naming the source (a JSON fault with its line), never crash, hang or leak.
// Seeds: tests/fuzz/corpus/identification_json/, dictionary tests/fuzz/identification_json.dict.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "pipeline/io/identification_reader.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text = tpcal::fuzz::AsText(data, size);
  auto r = tpcal::pipeline::ParseIdentificationJson(text, "fuzz.json");
  if (r.ok()) {
    if (r->source != "fuzz.json") __builtin_trap();
    // Every parameter is at least {"name":"","unit":"","identifiable":false} in the text.
    if (r->parameters.size() > size / 40) __builtin_trap();
    for (const auto& p : r->parameters) {
      if (p.identifiable) {
        if (!std::isfinite(p.value) || !std::isfinite(p.u) || p.u < 0.0) __builtin_trap();
      } else if (p.value != 0.0 || p.u != 0.0) {
        __builtin_trap();  // not identifiable: value and u absent
      }
    }
    return 0;
  }
  const tpcal::Status& s = r.status();
  if (s.code() != tpcal::StatusCode::kParseError || s.file() != "fuzz.json") __builtin_trap();
  tpcal::fuzz::CheckStatus(s);
  // A JSON fault is located on a line of the text; the schema errors have no line.
  const std::size_t lines = 1 + static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  if (s.message().starts_with("expected JSON") && (s.line() == 0 || s.line() > lines)) __builtin_trap();
  return 0;
}
