#include "pipeline/io/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "pipeline/io/large_alloc.h"

namespace tpcal::pipeline {
namespace {

Status FileIoError(const std::string& path, const char* what, int err) {
  return Status(StatusCode::kIoError, fmt::format("{}: {}", what, std::strerror(err)), path);
}

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

Result<FileBytes> ReadFileBytes(const std::string& path) {
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
    ssize_t n = ::read(fd, out.data.get() + out.size, capacity - out.size);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0) {
      Status s = FileIoError(path, "read failed", errno);
      ::close(fd);
      return s;
    }
    if (n == 0) break;
    out.size += static_cast<std::size_t>(n);
  }
  ::close(fd);
  out.data[out.size] = '\0';
  return out;
}

}  // namespace tpcal::pipeline
