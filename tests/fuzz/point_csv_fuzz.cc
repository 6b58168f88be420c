// The point CSV reader (docs/formats/points.md) from memory, serial and in parallel chunks: both
// must agree, and errors must be well-formed.
#include <cstdlib>

#include "pipeline/io/point_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string_view text = fuzz::AsText(data, size);
  pipeline::PointReadOptions serial;
  serial.threads = 1;
  const Result<pipeline::PointFile> a = pipeline::ParsePointCsv(text, "fuzz.csv", serial);
  fuzz::CheckStatus(a.status());
  pipeline::PointReadOptions chunked;
  chunked.threads = 3;
  chunked.min_chunk_bytes = 8;
  const Result<pipeline::PointFile> b = pipeline::ParsePointCsv(text, "fuzz.csv", chunked);
  if (a.ok() != b.ok() || (!a.ok() && a.status().ToString() != b.status().ToString()) ||
      (a.ok() && (a->points.size() != b->points.size() || a->points.xyz_mm != b->points.xyz_mm ||
                  a->points.feature != b->points.feature || a->points.line != b->points.line ||
                  a->points.feature_names != b->points.feature_names)))
    std::abort();  // the chunked parse must be the serial one
  return 0;
}
