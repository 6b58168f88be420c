#include "pipeline/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <utility>

#include <fmt/format.h>

namespace tpcal::pipeline {
namespace {

constexpr std::size_t kBufferBytes = 1 << 20;

Status IoError(const std::string& path, const char* what, int err) {
  return Status(StatusCode::kIoError, fmt::format("{} failed: {}", what, std::strerror(err)), path);
}

std::string DirectoryOf(const std::string& path) {
  std::filesystem::path p(path);
  auto parent = p.parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Best effort: makes the rename durable on file systems that support fsync on directories.
void SyncDirectory(const std::string& dir) {
  int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

Status WriteAll(int fd, const char* data, std::size_t size, const std::string& target) {
  while (size > 0) {
    ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return IoError(target, "write", errno);
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return Status::Ok();
}

// fsync + rename temp onto target; removes temp on failure.
Status SyncAndRename(const std::string& temp, const std::string& target) {
  int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    Status s = IoError(target, "reopening the temp file", errno);
    ::unlink(temp.c_str());
    return s;
  }
  struct stat old_st {};
  if (::stat(target.c_str(), &old_st) == 0 && S_ISREG(old_st.st_mode))
    (void)::fchmod(fd, old_st.st_mode & 07777);
  if (::fsync(fd) != 0) {
    Status s = IoError(target, "fsync", errno);
    ::close(fd);
    ::unlink(temp.c_str());
    return s;
  }
  ::close(fd);
  if (::rename(temp.c_str(), target.c_str()) != 0) {
    Status s = IoError(target, "rename", errno);
    ::unlink(temp.c_str());
    return s;
  }
  SyncDirectory(DirectoryOf(target));
  return Status::Ok();
}

}  // namespace

std::string MakeAtomicTempPath(const std::string& target_path) {
  std::random_device rd;
  const unsigned long long r = (static_cast<unsigned long long>(rd()) << 32) ^ rd();
  return fmt::format("{}.tmp.{}.{:016x}", target_path, static_cast<long>(::getpid()), r);
}

Result<AtomicFileWriter> AtomicFileWriter::Open(const std::string& target_path) {
  if (target_path.empty())
    return Status(StatusCode::kInvalidArgument, "empty output path");
  AtomicFileWriter w;
  w.target_ = target_path;
  for (int attempt = 0; attempt < 8; ++attempt) {
    w.temp_ = MakeAtomicTempPath(target_path);
    w.fd_ = ::open(w.temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (w.fd_ >= 0) break;
    if (errno != EEXIST) return IoError(target_path, "creating the temp file", errno);
  }
  if (w.fd_ < 0) return IoError(target_path, "creating the temp file", EEXIST);
  w.buffer_.reserve(kBufferBytes);
  return w;
}

AtomicFileWriter::AtomicFileWriter(AtomicFileWriter&& other) noexcept
    : target_(std::move(other.target_)),
      temp_(std::move(other.temp_)),
      fd_(std::exchange(other.fd_, -1)),
      buffer_(std::move(other.buffer_)) {}

AtomicFileWriter& AtomicFileWriter::operator=(AtomicFileWriter&& other) noexcept {
  if (this != &other) {
    Abandon();
    target_ = std::move(other.target_);
    temp_ = std::move(other.temp_);
    fd_ = std::exchange(other.fd_, -1);
    buffer_ = std::move(other.buffer_);
  }
  return *this;
}

AtomicFileWriter::~AtomicFileWriter() { Abandon(); }

void AtomicFileWriter::Abandon() {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
  ::unlink(temp_.c_str());
  buffer_.clear();
}

Status AtomicFileWriter::Fail(Status status) {
  Abandon();
  return status;
}

Status AtomicFileWriter::FlushBuffer() {
  Status s = WriteAll(fd_, buffer_.data(), buffer_.size(), target_);
  buffer_.clear();
  return s;
}

Status AtomicFileWriter::Write(std::string_view bytes) {
  if (fd_ < 0) return Status(StatusCode::kIoError, "write to a closed output", target_);
  if (buffer_.size() + bytes.size() > kBufferBytes) {
    if (Status s = FlushBuffer(); !s.ok()) return Fail(s);
    if (bytes.size() >= kBufferBytes) {
      if (Status s = WriteAll(fd_, bytes.data(), bytes.size(), target_); !s.ok()) return Fail(s);
      return Status::Ok();
    }
  }
  buffer_.append(bytes);
  return Status::Ok();
}

Status AtomicFileWriter::Commit() {
  if (fd_ < 0) return Status(StatusCode::kIoError, "commit of a closed output", target_);
  if (Status s = FlushBuffer(); !s.ok()) return Fail(s);
  struct stat old_st {};
  if (::stat(target_.c_str(), &old_st) == 0 && S_ISREG(old_st.st_mode))
    (void)::fchmod(fd_, old_st.st_mode & 07777);
  if (::fsync(fd_) != 0) return Fail(IoError(target_, "fsync", errno));
  if (::close(fd_) != 0) {
    fd_ = -1;
    Status s = IoError(target_, "close", errno);
    ::unlink(temp_.c_str());
    return s;
  }
  fd_ = -1;
  if (::rename(temp_.c_str(), target_.c_str()) != 0) {
    Status s = IoError(target_, "rename", errno);
    ::unlink(temp_.c_str());
    return s;
  }
  SyncDirectory(DirectoryOf(target_));
  return Status::Ok();
}

Status WriteFileAtomic(const std::string& path, std::string_view contents) {
  Result<AtomicFileWriter> w = AtomicFileWriter::Open(path);
  if (!w.ok()) return w.status();
  TPCAL_RETURN_IF_ERROR(w->Write(contents));
  return w->Commit();
}

Status WriteFileAtomic(const std::string& path,
                       const std::function<Status(AtomicFileWriter&)>& produce) {
  Result<AtomicFileWriter> w = AtomicFileWriter::Open(path);
  if (!w.ok()) return w.status();
  Status s = produce(*w);
  if (!s.ok()) {
    w->Abandon();
    return s;
  }
  return w->Commit();
}

Status WriteFileAtomicVia(const std::string& path,
                          const std::function<Status(const std::string& temp_path)>& write_to) {
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "empty output path");
  const std::string temp = MakeAtomicTempPath(path);
  Status s = write_to(temp);
  if (!s.ok()) {
    ::unlink(temp.c_str());
    return s;
  }
  return SyncAndRename(temp, path);
}

}  // namespace tpcal::pipeline
