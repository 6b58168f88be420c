// libFuzzer target: the QIF 3.0 results reader (pipeline/io/qif_reader.h) on arbitrary bytes,
// with every option combination. It must return a value or a located kParseError, never crash,
// hang or leak. Seeds: tests/fuzz/corpus/qif/, dictionary tests/fuzz/qif.dict.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "pipeline/io/qif_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (int mode = 0; mode < 2; ++mode) {
    tpcal::pipeline::QifReadOptions options;
    options.accept_uncompensated = mode == 1;
    options.lenient_references = mode == 1;
    auto r = tpcal::pipeline::ParseQif(text, "fuzz.qif", options);
    if (r.ok()) {
      const tpcal::PointSet& ps = r->file.points;
      if (ps.empty() || ps.line.size() != ps.size() || ps.feature.size() != ps.size() ||
          (ps.has_normals() && ps.normal.size() != ps.size()))
        __builtin_trap();
    } else if (r.status().line() == 0 || r.status().file() != "fuzz.qif") {
      __builtin_trap();  // every error is located
    }
  }
  return 0;
}
