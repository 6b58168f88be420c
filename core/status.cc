#include "core/status.h"

namespace tpcal {

const char* StatusCodeName(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "ok";
    case StatusCode::kInvalidArgument: return "invalid argument";
    case StatusCode::kParseError: return "parse error";
    case StatusCode::kIoError: return "i/o error";
    case StatusCode::kTooFewPoints: return "too few points";
    case StatusCode::kDegenerate: return "degenerate geometry";
    case StatusCode::kNotConverged: return "not converged";
    case StatusCode::kNotIdentifiable: return "not identifiable";
    case StatusCode::kInternal: return "internal error";
  }
  return "unknown";
}

Status Status::WithLocation(std::string file, std::size_t line) const {
  Status s = *this;
  s.file_ = std::move(file);
  if (line != 0) s.line_ = line;
  return s;
}

Status Status::WithContext(const std::string& context) const {
  Status s = *this;
  std::string m;
  m.append(context).append(": ").append(message_);
  s.message_ = std::move(m);
  return s;
}

std::string Status::ToString() const {
  if (ok()) return "ok";
  std::string out;
  if (!file_.empty()) {
    out.append(file_);
    if (line_ != 0) out.append(":").append(std::to_string(line_));
    out.append(": ");
  }
  out.append(message_);
  return out;
}

}  // namespace tpcal
