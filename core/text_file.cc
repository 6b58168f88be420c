#include "core/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace tpcal {

Result<std::string> ReadTextFile(const std::string& path, std::string_view open_error,
                                 std::uint64_t max_bytes) {
  // O_NONBLOCK: opening a FIFO without a writer returns at once; it is then refused below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return Status(StatusCode::kIoError, std::string(open_error), path);
  auto too_large = [&](std::uint64_t bytes) {
    return Status(StatusCode::kParseError,
                  "file of " + std::to_string(bytes) + " bytes; expected at most " +
                      std::to_string(max_bytes) + " bytes for this kind of file",
                  path);
  };
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return Status(StatusCode::kIoError, "not a regular file", path);
  }
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    return too_large(static_cast<std::uint64_t>(st.st_size));
  }
  // One byte more than fstat said, so a file that grew past the limit is noticed.
  std::string text(static_cast<std::size_t>(st.st_size) + 1, '\0');
  std::size_t size = 0;
  while (true) {
    if (size == text.size()) {
      if (size > max_bytes) {
        ::close(fd);
        return too_large(size);
      }
      text.resize(std::min<std::uint64_t>(max_bytes + 1, text.size() * 2 + 4096));
    }
    const ssize_t n = ::read(fd, text.data() + size, text.size() - size);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      return Status(StatusCode::kIoError, std::string("read failed: ") + std::strerror(err), path);
    }
    if (n == 0) break;
    size += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(size);
  return text;
}

}  // namespace tpcal
