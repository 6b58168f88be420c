// The NC program reader (gcode/nc_reader.h) of every dialect: the first byte picks the dialect,
// the rest is the program.
#include "gcode/nc_reader.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tpcal;
  if (size == 0) return 0;
  static constexpr gcode::Dialect kDialects[] = {gcode::Dialect::kFanuc, gcode::Dialect::kLinuxCnc,
                                                 gcode::Dialect::kSinumerik, gcode::Dialect::kHeidenhain};
  const gcode::GcodeOptions options = gcode::GcodeOptions::ForDialect(kDialects[data[0] % 4]);
  fuzz::CheckStatus(gcode::ReadNcProgram(fuzz::AsText(data + 1, size - 1), options).status());
  return 0;
}
