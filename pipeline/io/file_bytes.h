// Whole-file reads for the parsers and the cache: one open/fstat/read loop into an
// uninitialised buffer (no zero fill, no per-line I/O).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "core/status.h"

namespace tpcal::pipeline {

struct FileBytes {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
  std::string_view view() const { return {data.get(), size}; }
};

// The whole file. kIoError naming `path` if it cannot be opened or read, or is not a regular
// file (a FIFO, device or directory is refused without blocking). With max_line_bytes > 0 (text),
// a line longer than that is a kParseError at its line as soon as it is read, so a huge file
// of one line fails after max_line_bytes + 4 MiB of reading, not after all of it.
Result<FileBytes> ReadFileBytes(const std::string& path, std::size_t max_line_bytes = 0);

// The message of a line longer than `max_line_bytes` (shared by the readers that check it).
std::string LongLineMessage(std::size_t max_line_bytes);

// Size and modification time (ns since the epoch) of a regular file.
struct FileStamp {
  std::uint64_t size = 0;
  std::int64_t mtime_ns = 0;
};
Result<FileStamp> StatFile(const std::string& path);

}  // namespace tpcal::pipeline
