// Shared by the libFuzzer targets of tests/fuzz: the properties every reader keeps on any input,
// checked after each call (a violation aborts, so libFuzzer reports it as a finding).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/input_echo.h"
#include "core/status.h"

namespace tpcal::fuzz {

inline std::string_view AsText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// An error names what was expected in bounded, printable UTF-8 text: input echoed into a message
// goes through EchoInput, so no control byte, broken UTF-8 or megabyte of input reaches stderr.
inline void CheckStatus(const Status& status) {
  if (status.ok()) return;
  const std::string& m = status.message();
  bool bad = m.empty() || m.size() > 4096 || FirstInvalidUtf8(m) != std::string_view::npos;
  for (char c : m) bad = bad || (static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7F;
  if (bad) {
    std::fprintf(stderr, "tpcal fuzz: malformed error message (%zu bytes): %s\n", m.size(),
                 EchoInput(m, 400).c_str());
    std::abort();
  }
}

// For readers that take a path: the input as a file in /dev/shm (or /tmp), one per process.
class TempFile {
 public:
  explicit TempFile(const std::string& extension) {
    const char* dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    path_ = std::string(dir) + "/tpcal_fuzz_" + std::to_string(getpid()) + extension;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& Write(std::string_view bytes) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
      std::perror(path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace tpcal::fuzz
