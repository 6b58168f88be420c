// Atomic file output: every file tpcal writes goes through here, so a reader never sees a
// partial file and a failed run never leaves a half-written target behind.
//
// Protocol: the bytes go to `<target>.tmp.<pid>.<random hex>` in the target's own directory
// (same file system, so rename(2) is atomic), then fsync(temp), rename(temp, target),
// fsync(directory). On any failure before the rename, or if the writer is destroyed without
// Commit(), the temp file is removed and an existing target is left untouched. A new target
// gets mode 0666 & ~umask; an existing target's permission bits are kept.
// Errors are kIoError statuses naming the target path and the failing system call.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "core/status.h"

namespace tpcal::pipeline {

// Writes `contents` to `path` atomically.
Status WriteFileAtomic(const std::string& path, std::string_view contents);

// Streaming writer. Open() creates the temp file; Write() appends (buffered); Commit()
// publishes the file under its target name. Move-only. Destroying an uncommitted writer
// (or any failed Write/Commit) removes the temp file.
class AtomicFileWriter {
 public:
  static Result<AtomicFileWriter> Open(const std::string& target_path);

  AtomicFileWriter(AtomicFileWriter&& other) noexcept;
  AtomicFileWriter& operator=(AtomicFileWriter&& other) noexcept;
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  Status Write(std::string_view bytes);
  // Flushes, fsyncs and renames onto the target. After Commit (ok or not) the writer is closed.
  Status Commit();
  // Closes and removes the temp file without touching the target. Idempotent.
  void Abandon();

  const std::string& target_path() const { return target_; }
  const std::string& temp_path() const { return temp_; }
  bool is_open() const { return fd_ >= 0; }

 private:
  AtomicFileWriter() = default;
  Status FlushBuffer();
  Status Fail(Status status);  // Abandon() and return status

  std::string target_;
  std::string temp_;
  int fd_ = -1;
  std::string buffer_;
};

// Streaming variant: `produce` writes through the writer; if it returns an error the temp file
// is removed, the target is untouched and that error is returned.
Status WriteFileAtomic(const std::string& path,
                       const std::function<Status(AtomicFileWriter&)>& produce);

// For third-party writers that insist on a file name (PCL): `write_to` must create the file at
// the given temp path (same directory as `path`); it is then fsynced and renamed onto `path`.
// On error from `write_to` (or a missing temp file) the temp file is removed.
Status WriteFileAtomicVia(const std::string& path,
                          const std::function<Status(const std::string& temp_path)>& write_to);

// The temp-file name this module would use for `target_path` (fresh random part each call).
std::string MakeAtomicTempPath(const std::string& target_path);

}  // namespace tpcal::pipeline
