// The PLY reader: tpcal's own check of the whole file (cloud_file_check.h), then PCL on a temp
// file, as `tpcal fit x.ply` reads it. PCL is not instrumented: a crash there means the check let
// through a file PCL cannot take.
#include "pipeline/io/cloud_file_check.h"
#include "pipeline/io/point_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  static fuzz::TempFile file(".ply");
  const std::string_view bytes = fuzz::AsText(data, size);
  const Status check = pipeline::internal::CheckPlyBytes(bytes, "fuzz.ply");
  fuzz::CheckStatus(check);
  if (!check.ok()) return 0;
  pipeline::PointReadOptions options;
  options.skip_nonfinite_points = size % 2 == 0;
  fuzz::CheckStatus(pipeline::ReadPointPly(file.Write(bytes), options).status());
  return 0;
}
