// libFuzzer target: the DMIS output reader (pipeline/io/dmis_reader.h) and the PC-DMIS XYZIJK
// reader (pipeline/io/xyzijk_reader.h) on arbitrary bytes. They must return a value or a
// located kParseError, never crash or hang. Seeds: tests/fuzz/corpus/dmis/.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "pipeline/io/dmis_reader.h"
#include "pipeline/io/xyzijk_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  tpcal::pipeline::DmisReadOptions options;
  if (size % 2 == 1) options.known_features = {"S_R", "B_R", "H1"};
  auto r = tpcal::pipeline::ParseDmisOutput(text, "fuzz.dmo", options);
  if (r.ok()) {
    const tpcal::PointSet& ps = r->file.points;
    if (ps.empty() || ps.normal.size() != ps.size() || ps.line.size() != ps.size()) __builtin_trap();
  } else if (r.status().line() == 0 || r.status().file() != "fuzz.dmo") {
    __builtin_trap();
  }
  auto x = tpcal::pipeline::ParsePointXyzijk(text, "fuzz.txt");
  if (!x.ok() && x.status().file() != "fuzz.txt") __builtin_trap();
  return 0;
}
