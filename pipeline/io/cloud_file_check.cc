#include "pipeline/io/cloud_file_check.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>
#include <pcl/io/lzf.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <vector>

#include "core/input_echo.h"

namespace tpcal::pipeline::internal {
namespace {

// Bounds of what a header may declare (far above any scanner's output).
constexpr std::uint64_t kCloudMaxPoints = (std::uint64_t{1} << 31) - 1;  // PCL counts in int
constexpr std::size_t kCloudMaxFields = 1024;
constexpr std::uint64_t kCloudMaxFieldCount = 1 << 16;  // values per PCD field
constexpr std::uint64_t kCloudMaxListLength = 1 << 16;  // items of one PLY list
// LZF cannot expand by more than this (a 3-byte back reference copies at most 264 bytes).
constexpr std::uint64_t kLzfMaxRatio = 88;

bool CloudBlank(char c) { return c == ' ' || c == '\t'; }

// Lines of `bytes` from `pos`; a line excludes its '\n' and a trailing '\r'.
class CloudLines {
 public:
  CloudLines(std::string_view bytes, std::size_t pos) : bytes_(bytes), pos_(pos) {}
  bool Next(std::string_view* line) {
    if (pos_ >= bytes_.size()) return false;
    const std::size_t nl = bytes_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? bytes_.size() : nl;
    *line = bytes_.substr(pos_, end - pos_);
    raw_empty_ = line->empty();
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = nl == std::string_view::npos ? bytes_.size() : nl + 1;
    ++line_no_;
    return true;
  }
  std::size_t line_no() const { return line_no_; }  // of the line last returned
  std::size_t pos() const { return pos_; }            // byte after the line last returned
  bool raw_empty() const { return raw_empty_; }       // it had no byte at all (not even '\r')

 private:
  std::string_view bytes_;
  std::size_t pos_;
  std::size_t line_no_ = 0;
  bool raw_empty_ = false;
};

std::vector<std::string_view> CloudTokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && CloudBlank(line[i])) ++i;
    if (i == line.size()) return out;
    std::size_t e = i;
    while (e < line.size() && !CloudBlank(line[e])) ++e;
    out.push_back(line.substr(i, e - i));
    i = e;
  }
}

bool CloudUnsigned(std::string_view s, std::uint64_t max, std::uint64_t* out) {
  if (s.empty()) return false;
  auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && *out <= max;
}

bool CloudInteger(std::string_view s, std::int64_t* out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool IsXyzName(std::string_view name) { return name == "x" || name == "y" || name == "z"; }

// A coordinate token (already checked to be a number) that PCL reads as NaN or infinity in a
// field of `bytes` bytes.
bool NonFiniteCoordinate(std::string_view token, int bytes) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double v = 0;
  fast_float::from_chars(token.data(), token.data() + token.size(), v);
  return !std::isfinite(v) || (bytes == 4 && std::abs(v) > std::numeric_limits<float>::max());
}

// Notes the first row with a non-finite coordinate.
void NoteNonFinite(std::string_view token, int bytes, std::size_t line_no, CloudNotes* notes) {
  if (notes && notes->first_nonfinite_xyz_line == 0 && NonFiniteCoordinate(token, bytes))
    notes->first_nonfinite_xyz_line = line_no;
}

bool CloudReal(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  double v;
  auto r = fast_float::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// ---- PCD ------------------------------------------------------------------------------------

struct PcdField {
  std::string_view name;
  std::uint64_t size = 0;
  char type = 0;
  std::uint64_t count = 1;
};

Status CheckPcdAscii(CloudLines lines, const std::vector<PcdField>& fields, std::uint64_t points,
                     const std::string& path, CloudNotes* notes) {
  std::uint64_t values = 0;
  for (const PcdField& f : fields) values += f.count;
  std::uint64_t rows = 0;
  std::string_view line;
  while (lines.Next(&line)) {
    const std::vector<std::string_view> tokens = CloudTokens(line);
    if (tokens.empty()) continue;  // PCL skips blank lines
    auto error = [&](std::string msg) {
      return Status(StatusCode::kParseError, std::move(msg), path, lines.line_no());
    };
    if (rows == points)
      return error(fmt::format("more data rows than the {} points the header declares", points));
    if (tokens.size() != values)
      return error(fmt::format("data row has {} values; expected {} (the FIELDS and COUNT of the "
                               "header)", tokens.size(), values));
    std::size_t t = 0;
    for (const PcdField& f : fields) {
      for (std::uint64_t c = 0; c < f.count; ++c, ++t) {
        std::int64_t i;
        const bool ok = f.type == 'F' ? CloudReal(tokens[t]) : CloudInteger(tokens[t], &i);
        if (!ok)
          return error(fmt::format("field '{}': expected {}, got '{}'", EchoInput(f.name),
                                   f.type == 'F' ? "a number" : "an integer", EchoInput(tokens[t])));
        if (f.type == 'F' && f.count == 1 && IsXyzName(f.name))
          NoteNonFinite(tokens[t], static_cast<int>(f.size), lines.line_no(), notes);
      }
    }
    ++rows;
  }
  if (rows < points)
    return Status(StatusCode::kParseError,
                  fmt::format("the data ends after {} rows; the header declares {} points", rows, points),
                  path, lines.line_no());
  return Status::Ok();
}

Status CheckPcdCompressed(std::string_view data, std::uint64_t need, const std::string& path) {
  auto error = [&](std::string msg) { return Status(StatusCode::kParseError, std::move(msg), path); };
  if (data.size() < 8)
    return error("the binary_compressed data lacks its 8-byte size header");
  std::uint32_t compressed = 0, uncompressed = 0;
  std::memcpy(&compressed, data.data(), 4);
  std::memcpy(&uncompressed, data.data() + 4, 4);
  if (compressed == 0 || compressed > data.size() - 8)
    return error(fmt::format("the binary_compressed data declares {} compressed bytes; the file "
                             "holds {} after the header", compressed, data.size() - 8));
  if (uncompressed != need)
    return error(fmt::format("the binary_compressed data declares {} uncompressed bytes; the header "
                             "declares points of {} bytes in all", uncompressed, need));
  if (need > kLzfMaxRatio * compressed)
    return error(fmt::format("the binary_compressed data cannot hold the {} bytes the header declares "
                             "in {} compressed bytes", need, compressed));
  auto out = std::make_unique_for_overwrite<char[]>(need);
  const unsigned int got = pcl::lzfDecompress(data.data() + 8, compressed, out.get(),
                                              static_cast<unsigned int>(need));
  if (got != need)
    return error("the binary_compressed data is damaged (it does not decompress to the declared size)");
  return Status::Ok();
}

// PCL's header loop does not stop at DATA: it goes on reading "lines" of the data, skipping empty
// lines and `#` comments, and re-reads any that begins with a header keyword (binary data that
// starts with "COUNT" changes the field counts, and PCL then reads out of bounds). The first word
// of the first such line must therefore not be a keyword; returns it if it is, else "".
std::string_view PcdKeywordInData(std::string_view data) {
  static constexpr std::string_view kKeywords[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT",
                                                   "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; };
  std::size_t pos = 0;
  while (pos < data.size()) {
    const std::size_t nl = data.find('\n', pos);
    const std::string_view line = data.substr(pos, (nl == std::string_view::npos ? data.size() : nl) - pos);
    pos = nl == std::string_view::npos ? data.size() : nl + 1;
    if (line.empty()) continue;
    std::size_t b = 0;
    while (b < line.size() && space(line[b])) ++b;
    std::size_t e = b;
    while (e < line.size() && !space(line[e])) ++e;
    const std::string_view word = line.substr(b, e - b);
    if (!word.empty() && word.front() == '#') continue;
    for (std::string_view k : kKeywords)
      if (word.substr(0, k.size()) == k) return k;
    return {};
  }
  return {};
}

}  // namespace

Status CheckPcdBytes(std::string_view bytes, const std::string& path, CloudNotes* notes) {
  CloudLines lines(bytes, 0);
  auto error = [&](std::string msg) {
    return Status(StatusCode::kParseError, std::move(msg), path, lines.line_no());
  };
  if (bytes.empty()) return Status(StatusCode::kParseError, "empty file: expected a PCD header", path);
  std::vector<PcdField> fields;
  std::set<std::string_view> seen;  // keywords
  std::uint64_t width = 0, height = 0, points = 0;
  std::string_view data_kind;
  std::string_view line;
  while (data_kind.empty() && lines.Next(&line)) {
    const std::vector<std::string_view> tok = CloudTokens(line);
    if (lines.raw_empty()) continue;
    // PCL ends its header at a line of blanks (or a lone CR) and then reads no fields at all.
    if (tok.empty()) return error("a line of blanks in the header; expected header lines up to DATA");
    if (tok[0].front() == '#') continue;
    const std::string_view key = tok[0];
    static const std::set<std::string_view> kKeys = {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE",
                                                    "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (!kKeys.count(key))
      return error(fmt::format("'{}' is not a PCD header keyword; expected VERSION, FIELDS, SIZE, TYPE, "
                               "COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS or DATA", EchoInput(key)));
    const std::string_view canonical = key == "COLUMNS" ? "FIELDS" : key;
    if (!seen.insert(canonical).second) return error(fmt::format("{} given twice", canonical));
    const std::size_t n = tok.size() - 1;
    if (canonical == "VERSION") continue;
    if (canonical == "FIELDS") {
      if (n == 0 || n > kCloudMaxFields)
        return error(fmt::format("FIELDS lists {} names; expected 1 to {}", n, kCloudMaxFields));
      fields.resize(n);
      for (std::size_t i = 0; i < n; ++i) fields[i].name = tok[i + 1];
      continue;
    }
    if (canonical == "SIZE" || canonical == "TYPE" || canonical == "COUNT") {
      const bool order_ok = canonical == "SIZE"   ? seen.count("FIELDS")
                            : canonical == "TYPE" ? seen.count("SIZE")
                                                  : seen.count("TYPE");
      if (!order_ok)
        return error(fmt::format("{} before {}; expected FIELDS, SIZE, TYPE, COUNT in that order", canonical,
                                 canonical == "SIZE" ? "FIELDS" : canonical == "TYPE" ? "SIZE" : "TYPE"));
      if (n != fields.size())
        return error(fmt::format("{} has {} values for {} FIELDS", canonical, n, fields.size()));
      for (std::size_t i = 0; i < n; ++i) {
        const std::string_view v = tok[i + 1];
        PcdField& f = fields[i];
        if (canonical == "SIZE") {
          if (!CloudUnsigned(v, 8, &f.size) || (f.size != 1 && f.size != 2 && f.size != 4 && f.size != 8))
            return error(fmt::format("SIZE of field '{}' is '{}'; expected 1, 2, 4 or 8", EchoInput(f.name),
                                     EchoInput(v)));
        } else if (canonical == "TYPE") {
          if (v.size() != 1 || (v[0] != 'I' && v[0] != 'U' && v[0] != 'F') ||
              (v[0] == 'F' && f.size != 4 && f.size != 8))
            return error(fmt::format("TYPE of field '{}' is '{}' (SIZE {}); expected I or U, or F of SIZE 4 or 8",
                                     EchoInput(f.name), EchoInput(v), f.size));
          f.type = v[0];
        } else if (!CloudUnsigned(v, kCloudMaxFieldCount, &f.count) || f.count == 0) {
          return error(fmt::format("COUNT of field '{}' is '{}'; expected 1 to {}", EchoInput(f.name),
                                   EchoInput(v), kCloudMaxFieldCount));
        }
      }
      continue;
    }
    if (canonical == "WIDTH" || canonical == "HEIGHT" || canonical == "POINTS") {
      std::uint64_t v = 0;
      if (n != 1 || !CloudUnsigned(tok[1], kCloudMaxPoints, &v))
        return error(fmt::format("{} expects one count from 0 to {}", canonical, kCloudMaxPoints));
      (canonical == "WIDTH" ? width : canonical == "HEIGHT" ? height : points) = v;
      continue;
    }
    if (canonical == "VIEWPOINT") {
      if (n != 7) return error("VIEWPOINT expects 7 numbers (tx ty tz qw qx qy qz)");
      for (std::size_t i = 1; i <= 7; ++i)
        if (!CloudReal(tok[i])) return error(fmt::format("VIEWPOINT value '{}' is not a number", EchoInput(tok[i])));
      continue;
    }
    // DATA
    if (n != 1 || (tok[1] != "ascii" && tok[1] != "binary" && tok[1] != "binary_compressed"))
      return error("DATA expects ascii, binary or binary_compressed");
    if (!seen.count("TYPE")) return error("DATA before FIELDS, SIZE and TYPE");
    data_kind = tok[1];
  }
  if (data_kind.empty())
    return Status(StatusCode::kParseError,
                  "no DATA line: expected a PCD header (FIELDS, SIZE, TYPE, WIDTH, POINTS, DATA)", path,
                  fields.empty() ? 0 : lines.line_no());
  const std::size_t data_line = lines.line_no();
  auto header_error = [&](std::string msg) { return Status(StatusCode::kParseError, std::move(msg), path, data_line); };
  if (seen.count("HEIGHT") && !seen.count("WIDTH")) return header_error("HEIGHT without WIDTH");
  if (!seen.count("WIDTH") && !seen.count("POINTS")) return header_error("neither WIDTH nor POINTS is given");
  if (!seen.count("HEIGHT")) height = 1;
  if (!seen.count("WIDTH")) width = points;
  if (!seen.count("POINTS")) points = width * height;
  if (width * height != points)
    return header_error(fmt::format("WIDTH x HEIGHT = {} x {} is not POINTS = {}", width, height, points));
  if (points == 0) return header_error("the header declares no points");
  std::uint64_t point_bytes = 0;
  for (const PcdField& f : fields) point_bytes += f.size * f.count;
  if (const std::string_view k = PcdKeywordInData(bytes.substr(lines.pos())); !k.empty())
    return header_error(fmt::format("the data after DATA begins a line with '{}', which PCL would read as "
                                    "a header line; expected the data only", k));
  if (data_kind == "ascii") return CheckPcdAscii(lines, fields, points, path, notes);
  const std::string_view data = bytes.substr(lines.pos());
  const std::uint64_t need = points * point_bytes;  // < 2^31 * 2^26: no overflow
  if (data_kind == "binary_compressed") {
    if (need > 0xFFFFFFFFu) return header_error("the declared points exceed what binary_compressed can hold");
    return CheckPcdCompressed(data, need, path);
  }
  if (data.size() < need)
    return Status(StatusCode::kParseError,
                  fmt::format("the binary data holds {} bytes; the header declares {} points of {} bytes "
                              "({} bytes)", data.size(), points, point_bytes, need),
                  path);
  return Status::Ok();
}

// ---- PLY ------------------------------------------------------------------------------------

namespace {

struct PlyProperty {
  std::string_view name;
  int size = 0;            // bytes of the value (of each list item)
  bool real = false;       // float/double
  bool is_signed = false;  // see count_size
  int count_size = 0;      // list: bytes of the length; 0 = scalar
  // Scalar: the value is signed; list: the length is.
};

// PCL sizes the cloud from `obj_info num_cols/num_rows` and a camera element's viewportx/viewporty
// when they are given (and allocates that many points): the values seen, to bound them.
struct PlyGrid {
  double cols = -1, rows = -1;          // obj_info num_cols / num_rows
  double viewport_x = -1, viewport_y = -1;  // element camera
};

struct PlyElement {
  std::string_view name;
  std::uint64_t count = 0;
  std::size_t line = 0;
  std::vector<PlyProperty> properties;
};

// Size and kind of a PLY type name; false if unknown.
bool PlyType(std::string_view t, int* size, bool* real, bool* is_signed) {
  struct T { const char* a; const char* b; int size; bool real; bool is_signed; };
  static constexpr T kTypes[] = {
      {"char", "int8", 1, false, true},     {"uchar", "uint8", 1, false, false},
      {"short", "int16", 2, false, true},   {"ushort", "uint16", 2, false, false},
      {"int", "int32", 4, false, true},     {"uint", "uint32", 4, false, false},
      {"float", "float32", 4, true, true},  {"double", "float64", 8, true, true}};
  for (const T& k : kTypes) {
    if (t == k.a || t == k.b) {
      *size = k.size;
      *real = k.real;
      *is_signed = k.is_signed;
      return true;
    }
  }
  return false;
}

std::uint64_t PlyListLength(const char* p, int size, bool is_signed, bool big_endian, bool* negative) {
  unsigned char b[4] = {0, 0, 0, 0};
  for (int i = 0; i < size; ++i) b[i] = static_cast<unsigned char>(p[big_endian ? size - 1 - i : i]);
  std::uint64_t v = 0;
  for (int i = size - 1; i >= 0; --i) v = (v << 8) | b[i];
  *negative = is_signed && (b[size - 1] & 0x80);
  return v;
}

double PlyBinaryScalar(const char* p, const PlyProperty& prop, bool big_endian) {
  unsigned char b[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (int i = 0; i < prop.size; ++i) b[i] = static_cast<unsigned char>(p[big_endian ? prop.size - 1 - i : i]);
  if (prop.real) {
    if (prop.size == 4) {
      float f;
      std::memcpy(&f, b, 4);
      return f;
    }
    double d;
    std::memcpy(&d, b, 8);
    return d;
  }
  std::uint64_t v = 0;
  for (int i = prop.size - 1; i >= 0; --i) v = (v << 8) | b[i];
  if (!prop.is_signed) return static_cast<double>(v);
  const int shift = 64 - 8 * prop.size;  // sign-extend
  return static_cast<double>(static_cast<std::int64_t>(v << shift) >> shift);
}

void PlyNoteCamera(const PlyElement& e, const PlyProperty& p, double value, PlyGrid* grid) {
  if (e.name != "camera") return;
  if (p.name == "viewportx") grid->viewport_x = value;
  if (p.name == "viewporty") grid->viewport_y = value;
}

Status CheckPlyBinary(std::string_view data, const std::vector<PlyElement>& elements, bool big_endian,
                      const std::string& path, PlyGrid* grid) {
  std::size_t pos = 0;
  for (const PlyElement& e : elements) {
    auto short_data = [&](std::uint64_t i) {
      return Status(StatusCode::kParseError,
                    fmt::format("the binary data ends in {} {} of the {} declared (line {}); expected "
                                "every declared {}", EchoInput(e.name), i, e.count, e.line, EchoInput(e.name)),
                    path);
    };
    bool has_list = false;
    std::uint64_t row = 0;
    for (const PlyProperty& p : e.properties) {
      has_list = has_list || p.count_size != 0;
      row += static_cast<std::uint64_t>(p.count_size != 0 ? p.count_size : p.size);
    }
    if (!has_list && (e.name != "camera" || row == 0)) {
      const std::uint64_t need = row * e.count;  // < 2^10 * 8 * 2^31: no overflow
      if (data.size() - pos < need) return short_data((data.size() - pos) / row);
      pos += need;
      continue;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        if (p.count_size == 0) {
          if (data.size() - pos < static_cast<std::size_t>(p.size)) return short_data(i);
          PlyNoteCamera(e, p, PlyBinaryScalar(data.data() + pos, p, big_endian), grid);
          pos += static_cast<std::size_t>(p.size);
          continue;
        }
        if (data.size() - pos < static_cast<std::size_t>(p.count_size)) return short_data(i);
        bool negative = false;
        const std::uint64_t len = PlyListLength(data.data() + pos, p.count_size, p.is_signed, big_endian, &negative);
        pos += static_cast<std::size_t>(p.count_size);
        if (negative || len > kCloudMaxListLength)
          return Status(StatusCode::kParseError,
                        fmt::format("{} {}: list '{}' has a length outside 0..{}", EchoInput(e.name), i,
                                    EchoInput(p.name), kCloudMaxListLength),
                        path);
        if ((data.size() - pos) / static_cast<std::size_t>(p.size) < len) return short_data(i);
        pos += static_cast<std::size_t>(len) * static_cast<std::size_t>(p.size);
      }
    }
  }
  return Status::Ok();
}

bool PlyValue(std::string_view token, const PlyProperty& p) {
  if (p.real) return CloudReal(token);
  std::int64_t v;
  return CloudInteger(token, &v);
}

Status CheckPlyAscii(CloudLines lines, const std::vector<PlyElement>& elements, const std::string& path,
                     PlyGrid* grid, CloudNotes* notes) {
  std::string_view line;
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      if (!lines.Next(&line))
        return Status(StatusCode::kParseError,
                      fmt::format("the data ends after {} of the {} {} rows the header declares (line {})", i,
                                  e.count, EchoInput(e.name), e.line),
                      path, lines.line_no());
      auto error = [&](std::string msg) {
        return Status(StatusCode::kParseError, std::move(msg), path, lines.line_no());
      };
      const std::vector<std::string_view> tok = CloudTokens(line);
      std::size_t t = 0;
      for (const PlyProperty& p : e.properties) {
        std::uint64_t n = 1;
        if (p.count_size != 0) {
          std::int64_t len = -1;
          if (t >= tok.size() || !CloudInteger(tok[t], &len) || len < 0 ||
              static_cast<std::uint64_t>(len) > kCloudMaxListLength)
            return error(fmt::format("{} row: list '{}' expects a length from 0 to {}", EchoInput(e.name),
                                     EchoInput(p.name), kCloudMaxListLength));
          ++t;
          n = static_cast<std::uint64_t>(len);
        }
        for (std::uint64_t k = 0; k < n; ++k, ++t) {
          if (t >= tok.size())
            return error(fmt::format("{} row has {} values; expected more (property '{}')", EchoInput(e.name),
                                     tok.size(), EchoInput(p.name)));
          if (!PlyValue(tok[t], p))
            return error(fmt::format("{} row: property '{}' expects {}, got '{}'", EchoInput(e.name),
                                     EchoInput(p.name), p.real ? "a number" : "an integer", EchoInput(tok[t])));
          if (p.count_size == 0) {
            double v = 0;
            fast_float::from_chars(tok[t].data() + (tok[t].front() == '+'), tok[t].data() + tok[t].size(), v);
            PlyNoteCamera(e, p, v, grid);
            if (p.real && e.name == "vertex" && IsXyzName(p.name)) NoteNonFinite(tok[t], p.size, lines.line_no(), notes);
          }
        }
      }
      if (t != tok.size())
        return error(fmt::format("{} row has {} values; expected {}", EchoInput(e.name), tok.size(), t));
    }
  }
  while (lines.Next(&line)) {
    if (!CloudTokens(line).empty())
      return Status(StatusCode::kParseError, "data after the last row the header declares", path,
                    lines.line_no());
  }
  return Status::Ok();
}

}  // namespace

Status CheckPlyBytes(std::string_view bytes, const std::string& path, CloudNotes* notes) {
  CloudLines lines(bytes, 0);
  auto error = [&](std::string msg) {
    return Status(StatusCode::kParseError, std::move(msg), path, lines.line_no());
  };
  if (bytes.empty()) return Status(StatusCode::kParseError, "empty file: expected a PLY header", path);
  std::string_view line;
  if (!lines.Next(&line) || line != "ply") return error("the first line is not 'ply'; expected a PLY file");
  std::string_view format;
  std::vector<PlyElement> elements;
  PlyGrid grid;
  std::size_t n_properties = 0;
  bool ended = false;
  while (!ended && lines.Next(&line)) {
    const std::vector<std::string_view> tok = CloudTokens(line);
    if (tok.empty()) return error("blank line in the PLY header");
    const std::string_view key = tok[0];
    if (key == "comment") continue;
    if (key == "obj_info") {
      // PCL splits the line on every blank and asserts exactly three fields (abort, not an error).
      if (tok.size() != 3 || CloudBlank(line.front()) || CloudBlank(line.back()))
        return error("expected 'obj_info NAME VALUE': three fields, no leading or trailing blank");
      if (tok[1] == "num_cols" || tok[1] == "num_rows") {
        std::uint64_t v = 0;
        if (tok.size() != 3 || !CloudUnsigned(tok[2], kCloudMaxPoints, &v))
          return error(fmt::format("expected 'obj_info {} COUNT' with a count from 0 to {}", tok[1], kCloudMaxPoints));
        (tok[1] == "num_cols" ? grid.cols : grid.rows) = static_cast<double>(v);
      }
      continue;
    }
    if (key == "end_header") {
      if (tok.size() != 1) return error("text after end_header");
      ended = true;
    } else if (key == "format") {
      if (!format.empty()) return error("format given twice");
      if (tok.size() != 3 || tok[2] != "1.0" ||
          (tok[1] != "ascii" && tok[1] != "binary_little_endian" && tok[1] != "binary_big_endian"))
        return error("expected 'format ascii 1.0', 'format binary_little_endian 1.0' or "
                     "'format binary_big_endian 1.0'");
      format = tok[1];
    } else if (key == "element") {
      if (format.empty()) return error("element before the format line");
      std::uint64_t count = 0;
      if (tok.size() != 3 || !CloudUnsigned(tok[2], kCloudMaxPoints, &count))
        return error(fmt::format("expected 'element NAME COUNT' with a count from 0 to {}", kCloudMaxPoints));
      for (const PlyElement& e : elements)
        if (e.name == tok[1]) return error(fmt::format("element '{}' declared twice", EchoInput(tok[1])));
      if (tok[1] == "range_grid")
        return error("organized PLY clouds (element range_grid) are not supported; expected a list of vertices");
      elements.push_back(PlyElement{tok[1], count, lines.line_no(), {}});
    } else if (key == "property") {
      if (elements.empty()) return error("property before any element");
      if (++n_properties > kCloudMaxFields)
        return error(fmt::format("more than {} properties", kCloudMaxFields));
      PlyProperty p;
      const bool list = tok.size() >= 2 && tok[1] == "list";
      if (list) {
        int count_size = 0;
        bool real = false, count_signed = false;
        if (tok.size() != 5 || !PlyType(tok[2], &count_size, &real, &count_signed) || real ||
            !PlyType(tok[3], &p.size, &p.real, &p.is_signed))
          return error("expected 'property list COUNT_TYPE TYPE NAME' with an integer COUNT_TYPE");
        p.count_size = count_size;
        p.is_signed = count_signed;
        p.name = tok[4];
      } else {
        if (tok.size() != 3 || !PlyType(tok[1], &p.size, &p.real, &p.is_signed))
          return error("expected 'property TYPE NAME' with TYPE one of char, uchar, short, ushort, int, "
                       "uint, float, double (or int8 ... float64)");
        p.name = tok[2];
      }
      PlyElement& e = elements.back();
      for (const PlyProperty& q : e.properties)
        if (q.name == p.name)
          return error(fmt::format("property '{}' declared twice in element '{}'", EchoInput(p.name),
                                   EchoInput(e.name)));
      if (list && e.name == "vertex")
        return error(fmt::format("the vertex element has a list property '{}'; expected scalar properties",
                                 EchoInput(p.name)));
      e.properties.push_back(p);
    } else {
      return error(fmt::format("'{}' is not a PLY header keyword; expected format, comment, element, "
                               "property or end_header", EchoInput(key)));
    }
  }
  if (!ended) return Status(StatusCode::kParseError, "the PLY header has no end_header line", path, lines.line_no());
  if (format.empty()) return error("the PLY header has no format line");
  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : elements)
    if (e.name == "vertex") vertex = &e;
  if (!vertex) return error("the PLY header declares no vertex element");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const PlyProperty& p : vertex->properties) found = found || p.name == axis;
    if (!found)
      return Status(StatusCode::kParseError,
                    fmt::format("the vertex element has no property '{}'; expected x, y and z", axis), path,
                    vertex->line);
  }
  if (vertex->count == 0)
    return Status(StatusCode::kParseError, "the vertex element declares no points", path, vertex->line);
  const std::size_t header_end_line = lines.line_no();
  TPCAL_RETURN_IF_ERROR(format == "ascii"
                            ? CheckPlyAscii(lines, elements, path, &grid, notes)
                            : CheckPlyBinary(bytes.substr(lines.pos()), elements, format == "binary_big_endian", path,
                                             &grid));
  // PCL sizes the cloud width x height when obj_info num_cols/num_rows or the camera viewport
  // give both (PCL's own writer does), and allocates that many points: they must be the vertices.
  const double width = std::max(grid.cols, grid.viewport_x);
  const double height = std::max(grid.rows, grid.viewport_y);
  if (width > 0 && height > 0 && width * height != static_cast<double>(vertex->count))
    return Status(StatusCode::kParseError,
                  fmt::format("a grid of {:g} x {:g} points (obj_info num_cols/num_rows, camera viewportx/viewporty) "
                              "for {} vertices; expected a grid of the vertices",
                              width, height, vertex->count),
                  path, header_end_line);
  return Status::Ok();
}

}  // namespace tpcal::pipeline::internal
