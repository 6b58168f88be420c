#include "pipeline/io/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "pipeline/io/large_alloc.h"

namespace tpcal::pipeline {
namespace {

Status FileIoError(const std::string& path, const char* what, int err) {
  return Status(StatusCode::kIoError, fmt::format("{}: {}", what, std::strerror(err)), path);
}

// Blocks read between two line-length checks.
constexpr std::size_t kLineCheckBlock = std::size_t{4} << 20;

// Tracks the start and number of the current line over bytes read so far.
struct LineLengthScan {
  std::size_t scanned = 0;
  std::size_t line_start = 0;
  std::size_t line_no = 1;
  // False if the line in progress (or one completed in [scanned, size)) exceeds max_bytes.
  bool Scan(const char* data, std::size_t size, std::size_t max_bytes) {
    while (scanned < size) {
      const void* nl = std::memchr(data + scanned, '\n', size - scanned);
      if (!nl) {
        scanned = size;
        break;
      }
      const std::size_t at = static_cast<std::size_t>(static_cast<const char*>(nl) - data);
      if (at - line_start > max_bytes) return false;
      line_start = at + 1;
      scanned = at + 1;
      ++line_no;
    }
    return size - line_start <= max_bytes;
  }
};

}  // namespace

Result<FileStamp> StatFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return FileIoError(path, "cannot open", errno);
  if (!S_ISREG(st.st_mode))
    return Status(StatusCode::kIoError, "not a regular file", path);
  FileStamp stamp;
  stamp.size = static_cast<std::uint64_t>(st.st_size);
  stamp.mtime_ns = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  return stamp;
}

std::string LongLineMessage(std::size_t max_line_bytes) {
  return fmt::format("line longer than {} bytes; expected at most {} bytes per line", max_line_bytes,
                     max_line_bytes);
}

Result<FileBytes> ReadFileBytes(const std::string& path, std::size_t max_line_bytes) {
  // O_NONBLOCK: opening a FIFO without a writer returns at once; it is then refused below.
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return FileIoError(path, "cannot open", errno);
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    Status s = FileIoError(path, "cannot stat", errno);
    ::close(fd);
    return s;
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return Status(StatusCode::kIoError, "not a regular file", path);
  }
  FileBytes out;
  LineLengthScan lines;
  std::size_t capacity = static_cast<std::size_t>(st.st_size);
  out.data = std::make_unique_for_overwrite<char[]>(capacity + 1);
  AdviseHugePages(out.data.get(), capacity + 1);
  // Read until EOF (the file may grow or shrink while being read; we take what is there).
  while (true) {
    if (out.size == capacity) {
      // Probe for more data than fstat said.
      char probe;
      ssize_t n = ::read(fd, &probe, 1);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n < 0) {
        Status s = FileIoError(path, "read failed", errno);
        ::close(fd);
        return s;
      }
      if (n == 0) break;
      std::size_t new_capacity = capacity * 2 + 4096;
      auto bigger = std::make_unique_for_overwrite<char[]>(new_capacity + 1);
      std::memcpy(bigger.get(), out.data.get(), out.size);
      bigger[out.size++] = probe;
      out.data = std::move(bigger);
      capacity = new_capacity;
      continue;
    }
    const std::size_t want = max_line_bytes == 0 ? capacity - out.size
                                                 : std::min(capacity - out.size, kLineCheckBlock);
    ssize_t n = ::read(fd, out.data.get() + out.size, want);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0) {
      Status s = FileIoError(path, "read failed", errno);
      ::close(fd);
      return s;
    }
    if (n == 0) break;
    out.size += static_cast<std::size_t>(n);
    if (max_line_bytes > 0 && !lines.Scan(out.data.get(), out.size, max_line_bytes)) {
      ::close(fd);
      return Status(StatusCode::kParseError, LongLineMessage(max_line_bytes), path, lines.line_no);
    }
  }
  ::close(fd);
  out.data[out.size] = '\0';
  return out;
}

}  // namespace tpcal::pipeline
