// Whole reads of small text files (YAML configurations): checked before they are read, so a FIFO,
// a device or a directory never blocks or feeds a parser, and a huge file fails before any
// memory is taken.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/status.h"

namespace tpcal {

// Largest configuration file read (16 MiB; the bundled ones are below 10 KiB).
inline constexpr std::uint64_t kMaxConfigFileBytes = std::uint64_t{16} << 20;

// The bytes of `path`. kIoError naming `path`: `open_error` (verbatim) if it cannot be opened,
// "not a regular file" for a FIFO, device, socket or directory (checked without blocking),
// a read error; kParseError (line 0) if it holds more than `max_bytes`.
Result<std::string> ReadTextFile(const std::string& path, std::string_view open_error,
                                 std::uint64_t max_bytes = kMaxConfigFileBytes);

}  // namespace tpcal
