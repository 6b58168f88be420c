// Status and Result<T>: the one error type for data-dependent failures (bad file, too few
// points, degenerate geometry, non-identifiable parameter). Programmer bugs use assert.
// A Status may carry the file and the 1-based line it refers to; ToString() prints
// "file:line: message" (or "file: message", or just "message"), the CLI's error format.
#pragma once

#include <cassert>
#include <cstddef>
#include <string>
#include <utility>
#include <variant>

namespace tpcal {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,   // a caller-supplied value or option is out of range
  kParseError,        // a file or string does not follow its format
  kIoError,           // a file cannot be opened, read or written
  kTooFewPoints,      // a fit or evaluation needs more data than given
  kDegenerate,        // geometry does not define the feature (collinear, coincident, ...)
  kNotConverged,      // an iterative method stopped without meeting its tolerance
  kNotIdentifiable,   // the data cannot separate the requested quantity
  kInternal,          // a third-party library failed unexpectedly
};

const char* StatusCodeName(StatusCode code);

class Status {
 public:
  Status() = default;  // OK
  Status(StatusCode code, std::string message, std::string file = {}, std::size_t line = 0)
      : code_(code), message_(std::move(message)), file_(std::move(file)), line_(line) {}

  static Status Ok() { return {}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }  // 1-based; 0 = no line

  // Returns a copy with file (and line if given) set, for errors raised below the I/O layer.
  Status WithLocation(std::string file, std::size_t line = 0) const;
  // Returns a copy whose message is prefixed by `context + ": "`.
  Status WithContext(const std::string& context) const;

  // "file:line: message", "file: message" or "message".
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
  std::string file_;
  std::size_t line_ = 0;
};

// Result<T>: either a value or a non-OK Status.
template <typename T>
class Result {
 public:
  Result(T value) : data_(std::move(value)) {}              // NOLINT: implicit by design
  Result(Status status) : data_(std::move(status)) {        // NOLINT: implicit by design
    assert(!std::get<Status>(data_).ok() && "Result built from an OK status");
  }

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { assert(ok()); return std::get<T>(data_); }
  T& value() & { assert(ok()); return std::get<T>(data_); }
  T&& value() && { assert(ok()); return std::get<T>(std::move(data_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  // The error; Status::Ok() when a value is held.
  Status status() const { return ok() ? Status::Ok() : std::get<Status>(data_); }

 private:
  std::variant<T, Status> data_;
};

}  // namespace tpcal

// Propagate a non-OK Status from an expression returning Status or Result<U>.
#define TPCAL_RETURN_IF_ERROR(expr)              \
  do {                                           \
    auto tpcal_status_ = (expr);                 \
    if (!tpcal_status_.ok()) {                   \
      return ::tpcal::internal::ToStatus(tpcal_status_); \
    }                                            \
  } while (0)

namespace tpcal::internal {
inline Status ToStatus(const Status& s) { return s; }
template <typename T>
Status ToStatus(const Result<T>& r) { return r.status(); }
}  // namespace tpcal::internal
