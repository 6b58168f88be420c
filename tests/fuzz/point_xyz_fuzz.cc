// The plain `x y z [i j k]` reader from memory, serial and in parallel chunks.
#include <cstdlib>

#include "pipeline/io/point_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  const std::string_view text = fuzz::AsText(data, size);
  pipeline::PointReadOptions serial;
  serial.threads = 1;
  const Result<pipeline::PointFile> a = pipeline::ParsePointXyz(text, "fuzz.xyz", serial);
  fuzz::CheckStatus(a.status());
  pipeline::PointReadOptions chunked;
  chunked.threads = 3;
  chunked.min_chunk_bytes = 8;
  const Result<pipeline::PointFile> b = pipeline::ParsePointXyz(text, "fuzz.xyz", chunked);
  if (a.ok() != b.ok() || (!a.ok() && a.status().ToString() != b.status().ToString()) ||
      (a.ok() && (a->points.xyz_mm != b->points.xyz_mm || a->points.normal != b->points.normal ||
                  a->points.line != b->points.line)))
    std::abort();
  return 0;
}
