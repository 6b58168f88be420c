// Reader for the contract point CSV (and, with another tokenizer, plain xyz text): preamble
// and header in the calling thread, data rows in parallel chunks. See point_text_parser.h.
#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "core/ascii.h"
#include "core/input_echo.h"
#include "core/parallel.h"
#include "core/units.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/io/internal/point_table_header.h"
#include "pipeline/io/large_alloc.h"
#include "pipeline/io/point_io.h"
#include "pipeline/io/point_text_parser.h"

namespace tpcal::pipeline {
namespace internal {
namespace {

constexpr double kZeroNormalLength = 1e-12;  // below this a normal has no direction
// A normal whose length is this close to 1 is kept as read (bit-exact); farther (but within
// options.normal_tolerance) it is divided by its length. The result of that division is
// within a few ulp of unit length, so reading a written file again changes nothing.
constexpr double kAlreadyUnit = 1e-14;
constexpr std::size_t kMaxEcho = 40;  // characters of a bad cell quoted in a message
// Coordinates beyond this (1000 km) are not measurements; their squares would overflow the fits.
constexpr double kMaxAbsCoordinateMm = 1e9;

struct Context {
  TextDialect dialect;
  const Layout* layout;
  double scale;  // to mm
  double normal_tolerance;
  std::size_t first_data_line;  // 1-based line of the first line of the data region
};

inline bool IsBlank(char c) { return c == ' ' || c == '\t'; }
inline bool IsXyzSep(char c) { return c == ' ' || c == '\t' || c == ','; }

std::string_view TrimBlanks(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && IsBlank(s[b])) ++b;
  while (e > b && IsBlank(s[e - 1])) --e;
  return s.substr(b, e - b);
}

std::string Echo(std::string_view cell) {
  if (cell.size() <= kMaxEcho) return fmt::format("'{}'", EchoInput(cell));
  return fmt::format("'{}...'", EchoInput(cell.substr(0, kMaxEcho - 3)));
}

// Whole-cell number: optional '+', then what std::from_chars accepts (fast_float).
inline bool ParseNumber(const char* b, const char* e, double* out) {
  if (b != e && *b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  if (b == e) return false;
  auto r = fast_float::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e;
}

// As ParseNumber, and where the table allows it (Layout::decimal_comma) with a decimal comma.
inline bool ParseCellNumber(const char* b, const char* e, bool decimal_comma, double* out) {
  if (ParseNumber(b, e, out)) return true;
  if (!decimal_comma) return false;
  if (b != e && *b == '+') {
    ++b;
    if (b != e && (*b == '+' || *b == '-')) return false;
  }
  if (b == e) return false;
  auto r = fast_float::from_chars_advanced(b, e, *out, fast_float::parse_options(fast_float::chars_format::general, ','));
  return r.ec == std::errc() && r.ptr == e;
}

std::string LineTooLong() { return LongLineMessage(kMaxLineBytes); }

// A line that holds only blanks and commas (spreadsheets export empty rows as ",,,,").
bool OnlySeparators(std::string_view line) { return OnlyTableSeparators(line, ','); }

// ---- comments and directives -------------------------------------------------------------

struct Directive {
  enum class Kind { kNone, kUnits, kTag } kind = Kind::kNone;
  LengthUnit unit = LengthUnit::kMm;
  PointFileKind tag = PointFileKind::kUntagged;
};

// First word of a comment body and the rest after it.
std::pair<std::string_view, std::string_view> FirstWord(std::string_view body) {
  std::size_t e = 0;
  while (e < body.size() && !IsBlank(body[e]) && body[e] != ':' && body[e] != '=') ++e;
  return {body.substr(0, e), body.substr(e)};
}

bool IsUnitsDirective(std::string_view comment_body) {
  return AsciiLower(FirstWord(TrimBlanks(comment_body)).first) == "units";
}

// `body` is the comment without its '#'. Error message (empty if fine) through `error`.
Directive ParseComment(std::string_view body, std::string* error) {
  Directive d;
  body = TrimBlanks(body);
  auto [word, rest] = FirstWord(body);
  const std::string lword = AsciiLower(word);
  if (lword == "units") {
    rest = TrimBlanks(rest);
    if (!rest.empty() && (rest.front() == ':' || rest.front() == '=')) rest.remove_prefix(1);
    const std::string value = AsciiLower(TrimBlanks(rest));
    if (value == "mm") {
      d.kind = Directive::Kind::kUnits;
      d.unit = LengthUnit::kMm;
    } else if (value == "in") {
      d.kind = Directive::Kind::kUnits;
      d.unit = LengthUnit::kInch;
    } else {
      *error = fmt::format("unknown unit {} in the units comment (expected '# units: mm' or "
                           "'# units: in')", Echo(TrimBlanks(rest)));
    }
    return d;
  }
  if (lword == "tpcal") {
    // A tag is exactly `tpcal <kind> v<digits>`; other comments that start with "tpcal" are
    // ordinary comments.
    std::vector<std::string_view> words;
    std::string_view r = rest;
    while (true) {
      r = TrimBlanks(r);
      if (r.empty()) break;
      std::size_t e = 0;
      while (e < r.size() && !IsBlank(r[e])) ++e;
      words.push_back(r.substr(0, e));
      r.remove_prefix(e);
    }
    if (words.size() != 2 || words[1].size() < 2 || (words[1][0] != 'v' && words[1][0] != 'V'))
      return d;
    for (std::size_t i = 1; i < words[1].size(); ++i)
      if (words[1][i] < '0' || words[1][i] > '9') return d;
    const std::string kind = AsciiLower(words[0]);
    const std::string version(words[1].substr(1));
    if (kind == "points" && version == "1") {
      d.kind = Directive::Kind::kTag;
      d.tag = PointFileKind::kPoints;
    } else if (kind == "plan" && version == "1") {
      d.kind = Directive::Kind::kTag;
      d.tag = PointFileKind::kPlan;
    } else {
      *error = fmt::format("unsupported format tag '{}' (this reader knows 'tpcal points v1' "
                           "and 'tpcal plan v1')", EchoInput(body));
    }
  }
  return d;
}

// ---- tokenizers (used for the header, in error paths and for text attributes) ------------

void SplitXyz(std::string_view line, std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && IsXyzSep(line[i])) ++i;
    if (i == line.size()) return;
    std::size_t e = i;
    while (e < line.size() && !IsXyzSep(line[e])) ++e;
    cells->push_back(line.substr(i, e - i));
    i = e;
  }
}

// ---- layout of plain xyz text ------------------------------------------------------------

Layout XyzLayout(std::size_t ncols) {
  Layout layout;
  for (std::size_t c = 0; c < ncols; ++c) {
    layout.roles.push_back(static_cast<Role>(static_cast<int>(Role::kX) + static_cast<int>(c)));
    layout.attr_of_column.push_back(-1);
    layout.names.emplace_back(1, "xyzijk"[c]);
  }
  layout.has_normals = ncols == 6;
  layout.expected = layout.has_normals ? "x y z i j k" : "x y z";
  return layout;
}

// ---- chunk parsing ----------------------------------------------------------------------

struct ChunkOut {
  std::vector<Eigen::Vector3d> xyz;
  std::vector<Eigen::Vector3d> normal;
  std::vector<int> feature;             // chunk-local feature ids
  std::vector<std::size_t> line;        // chunk-local 0-based line index
  std::vector<std::string_view> names;  // chunk-local feature names, first appearance order
  std::vector<std::vector<double>> attr;
  std::vector<char> attr_text;  // attribute had a non-numeric cell in this chunk
  std::size_t lines = 0;        // lines consumed
  bool failed = false;
  std::size_t error_line = 0;   // chunk-local 0-based
  std::string error;
};

enum class LineResult { kPoint, kSkip, kError };

// Error path for a data row: decides between "skip" (a row of separators only), a cell-count
// error, and the specific cell error `cell_error` (may be empty if the count must be wrong).
LineResult RowError(std::string_view line, const Context& ctx, std::string cell_error,
                    ChunkOut* out) {
  if (OnlyTableSeparators(line, ctx.layout->sep)) return LineResult::kSkip;
  std::vector<std::string_view> cells;
  const std::size_t ncols = ctx.layout->roles.size();
  if (ctx.dialect == TextDialect::kCsv) {
    if (std::string e = SplitTableCells(line, ctx.layout->sep, &cells); !e.empty()) {
      out->error = std::move(e);
      return LineResult::kError;
    }
    if (cells.size() != ncols) {
      out->error = fmt::format("row has {} cells, header has {} ({})", cells.size(), ncols,
                               ctx.layout->expected);
      return LineResult::kError;
    }
  } else {
    SplitXyz(line, &cells);
    if (cells.size() != ncols) {
      out->error = fmt::format("line has {} values, expected {} ({}) as on the first data line "
                               "(line {})", cells.size(), ncols, ctx.layout->expected,
                               ctx.first_data_line);
      return LineResult::kError;
    }
  }
  // The fast path and SplitCsv tokenize alike, so a count or quote problem was caught above;
  // the fallback only guards against an empty message.
  out->error = cell_error.empty() ? fmt::format("malformed row (expected {})", ctx.layout->expected)
                                  : std::move(cell_error);
  return LineResult::kError;
}

std::string NumberError(const Layout& layout, std::size_t col, std::string_view cell) {
  const std::string name = EchoInput(layout.names[col]);
  if (cell.empty()) return fmt::format("column '{}': expected a number, got an empty cell", name);
  double v;
  if (ParseCellNumber(cell.data(), cell.data() + cell.size(), layout.decimal_comma(), &v) && !std::isfinite(v))
    return fmt::format("column '{}': expected a finite number, got {}", name, Echo(cell));
  return fmt::format("column '{}': expected a number, got {}", name, Echo(cell));
}

class ChunkParser {
 public:
  ChunkParser(const Context& ctx, ChunkOut* out) : ctx_(ctx), layout_(*ctx.layout), out_(out) {
    const std::size_t na = layout_.attr_names.size();
    out_->attr.assign(na, {});
    out_->attr_text.assign(na, 0);
    row_attr_.assign(na, 0.0);
    row_attr_bad_.assign(na, 0);
  }

  template <TextDialect D>
  void Run(std::string_view text) {
    Reserve(EstimateRows(text));
    const char* p = text.data();
    const char* const end = p + text.size();
    li_ = 0;
    while (p < end) {
      const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      const char* le = nl ? nl : end;
      const char* next = nl ? nl + 1 : end;
      if (static_cast<std::size_t>(le - p) > kMaxLineBytes) {
        out_->error = LineTooLong();
        out_->failed = true;
        out_->error_line = li_;
        out_->lines = li_;
        return;
      }
      if (le > p && le[-1] == '\r') --le;
      if (ParseLine<D>(p, le) == LineResult::kError) {
        out_->failed = true;
        out_->error_line = li_;
        out_->lines = li_;
        return;
      }
      p = next;
      ++li_;
    }
    out_->lines = li_;
  }

 private:
  // Rows in `text`, estimated from the line length of its first 64 KiB (+2 % and a margin),
  // so the arrays are allocated once instead of growing by doubling.
  static std::size_t EstimateRows(std::string_view text) {
    const std::string_view sample = text.substr(0, 64 * 1024);
    const std::size_t lines = static_cast<std::size_t>(std::count(sample.begin(), sample.end(), '\n'));
    if (lines == 0 || sample.size() == text.size()) return lines + 1;
    const double bytes_per_line = static_cast<double>(sample.size()) / static_cast<double>(lines);
    return static_cast<std::size_t>(static_cast<double>(text.size()) / bytes_per_line * 1.02) + 64;
  }

  void Reserve(std::size_t rows) {
    ReserveLarge(&out_->xyz, rows);
    if (layout_.has_normals) ReserveLarge(&out_->normal, rows);
    ReserveLarge(&out_->feature, rows);
    ReserveLarge(&out_->line, rows);
    for (auto& a : out_->attr) ReserveLarge(&a, rows);
  }

  // Feature id of `name`, or kBadLabel (out_->error set) if a new name is not UTF-8: labels
  // reach JSON reports, which hold UTF-8 only.
  static constexpr int kBadLabel = -2;
  int Intern(std::string_view name) {
    if (name.empty()) return PointSet::kUnlabelled;
    if (have_last_ && name == last_name_) return last_id_;
    auto [it, inserted] = ids_.try_emplace(name, static_cast<int>(out_->names.size()));
    if (inserted) {
      if (const std::size_t bad = FirstInvalidUtf8(name); bad != std::string_view::npos) {
        out_->error = fmt::format("feature label '{}' is not UTF-8 text (byte {} is 0x{:02X}); "
                                  "expected UTF-8 (export the file as UTF-8)",
                                  EchoInput(name), bad + 1, static_cast<unsigned char>(name[bad]));
        ids_.erase(it);
        return kBadLabel;
      }
      out_->names.push_back(name);
    }
    have_last_ = true;
    last_name_ = name;
    last_id_ = it->second;
    return last_id_;
  }

  template <TextDialect D>
  LineResult ParseLine(const char* p, const char* le) {
    const char* q = p;
    while (q < le && IsBlank(*q)) ++q;
    if (q == le) return LineResult::kSkip;
    const std::string_view line(p, static_cast<std::size_t>(le - p));
    if (*q == '#') {
      if (IsUnitsDirective(std::string_view(q + 1, static_cast<std::size_t>(le - q - 1)))) {
        out_->error = fmt::format("units comment after the {}: '# units:' must come before it",
                                  D == TextDialect::kCsv ? "header" : "first data line");
        return LineResult::kError;
      }
      return LineResult::kSkip;
    }
    const std::size_t ncols = layout_.roles.size();
    double v[6] = {0, 0, 0, 0, 0, 0};
    int feature = PointSet::kUnlabelled;
    const char* c = p;
    for (std::size_t col = 0; col < ncols; ++col) {
      const char* cb;
      const char* ce;
      if constexpr (D == TextDialect::kCsv) {
        const char sep = layout_.sep;
        while (c < le && IsCellBlank(*c, sep)) ++c;
        const char* after;
        if (c < le && *c == '"') {
          const char* close = static_cast<const char*>(
              std::memchr(c + 1, '"', static_cast<std::size_t>(le - c - 1)));
          if (!close) return RowError(line, ctx_, "", out_);
          cb = c + 1;
          ce = close;
          after = close + 1;
          while (after < le && IsCellBlank(*after, sep)) ++after;
          if (after < le && *after != sep) return RowError(line, ctx_, "", out_);
        } else {
          cb = c;
          const char* at = static_cast<const char*>(std::memchr(c, sep, static_cast<std::size_t>(le - c)));
          after = at ? at : le;
          ce = after;
          while (ce > cb && IsCellBlank(ce[-1], sep)) --ce;
        }
        if (col + 1 < ncols) {
          if (after == le) return RowError(line, ctx_, "", out_);
          c = after + 1;
        } else if (after != le) {
          return RowError(line, ctx_, "", out_);
        }
      } else {
        while (c < le && IsXyzSep(*c)) ++c;
        if (c == le) return RowError(line, ctx_, "", out_);
        cb = c;
        while (c < le && !IsXyzSep(*c)) ++c;
        ce = c;
        if (col + 1 == ncols) {
          while (c < le && IsXyzSep(*c)) ++c;
          if (c != le) return RowError(line, ctx_, "", out_);
        }
      }
      const Role role = layout_.roles[col];
      switch (role) {
        case Role::kFeature:
          feature = Intern(std::string_view(cb, static_cast<std::size_t>(ce - cb)));
          if (feature == kBadLabel) return LineResult::kError;
          break;
        case Role::kAttribute: {
          const int a = layout_.attr_of_column[col];
          if (!out_->attr_text[a]) {
            double x = 0.0;
            row_attr_bad_[a] = !(ParseCellNumber(cb, ce, layout_.decimal_comma(), &x) && std::isfinite(x));
            row_attr_[a] = x;
          }
          break;
        }
        case Role::kIgnore:
          break;
        default: {
          double& x = v[static_cast<int>(role) - static_cast<int>(Role::kX)];
          if (!ParseCellNumber(cb, ce, layout_.decimal_comma(), &x) || !std::isfinite(x))
            return RowError(line, ctx_,
                            NumberError(layout_, col, std::string_view(cb, static_cast<std::size_t>(ce - cb))),
                            out_);
        }
      }
    }
    if (layout_.has_normals) {
      Eigen::Vector3d n(v[3], v[4], v[5]);
      const double len = n.norm();
      if (len < kZeroNormalLength) {
        out_->error = fmt::format("normal (i,j,k) = ({:g},{:g},{:g}) has zero length; expected a "
                                  "unit vector", v[3], v[4], v[5]);
        return LineResult::kError;
      }
      const double dev = std::abs(len - 1.0);
      if (dev > ctx_.normal_tolerance) {
        out_->error = fmt::format("normal (i,j,k) = ({:g},{:g},{:g}) has length {:.6g}; expected "
                                  "a unit vector (length within {:g} of 1)",
                                  v[3], v[4], v[5], len, ctx_.normal_tolerance);
        return LineResult::kError;
      }
      if (dev > kAlreadyUnit) n /= len;
      out_->normal.push_back(n);
    }
    const Eigen::Vector3d xyz_mm(v[0] * ctx_.scale, v[1] * ctx_.scale, v[2] * ctx_.scale);
    if (!(xyz_mm.cwiseAbs().maxCoeff() <= kMaxAbsCoordinateMm)) {
      out_->error = fmt::format("point ({:g},{:g},{:g}) mm is beyond {:g} mm from the origin; "
                                "expected coordinates of a measured piece",
                                xyz_mm.x(), xyz_mm.y(), xyz_mm.z(), kMaxAbsCoordinateMm);
      return LineResult::kError;
    }
    out_->xyz.push_back(xyz_mm);
    out_->feature.push_back(feature);
    out_->line.push_back(li_);
    for (std::size_t a = 0; a < row_attr_.size(); ++a) {
      if (out_->attr_text[a]) continue;
      if (row_attr_bad_[a]) {
        out_->attr_text[a] = 1;
        std::vector<double>().swap(out_->attr[a]);
      } else {
        out_->attr[a].push_back(row_attr_[a]);
      }
    }
    return LineResult::kPoint;
  }

 private:
  const Context& ctx_;
  const Layout& layout_;
  ChunkOut* out_;
  std::unordered_map<std::string_view, int> ids_;
  bool have_last_ = false;
  std::string_view last_name_;
  int last_id_ = PointSet::kUnlabelled;
  std::vector<double> row_attr_;
  std::vector<char> row_attr_bad_;
  std::size_t li_ = 0;  // chunk-local 0-based index of the current line
};


// ---- preamble: comments, directives, header -----------------------------------------------

struct Preamble {
  LengthUnit units = LengthUnit::kMm;
  PointFileKind kind = PointFileKind::kUntagged;
  Layout layout;
  std::size_t data_begin = 0;       // byte offset of the data region
  std::size_t data_first_line = 0;  // 1-based line number of its first line
  std::size_t header_line = 0;      // CSV: the header; xyz: the first data line
};

Result<Preamble> ReadPreamble(std::string_view text, const std::string& source,
                              TextDialect dialect, LengthUnit default_units, const ColumnMap& columns) {
  auto error = [&](std::string msg, std::size_t line_no) {
    return Status(StatusCode::kParseError, std::move(msg), source, line_no);
  };
  Preamble pre;
  pre.units = default_units;
  std::size_t units_line = 0;
  std::size_t pos = 0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // UTF-8 byte-order mark
  const bool empty = pos == text.size();
  for (std::size_t line_no = 1; pos < text.size(); ++line_no) {
    const std::size_t nl = text.find('\n', pos);
    const std::size_t le = nl == std::string_view::npos ? text.size() : nl;
    const std::size_t next = nl == std::string_view::npos ? text.size() : nl + 1;
    std::string_view line = text.substr(pos, le - pos);
    if (line.size() > kMaxLineBytes) return error(LineTooLong(), line_no);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find('\r') != std::string_view::npos)
      return error("line ends are bare CR characters (classic Mac); expected LF or CRLF", line_no);
    const std::string_view trimmed = TrimBlanks(line);
    const bool blank = dialect == TextDialect::kXyz ? OnlySeparators(line) : trimmed.empty();
    if (blank) {
      pos = next;
      continue;
    }
    if (trimmed.front() == '#') {
      std::string message;
      const Directive d = ParseComment(trimmed.substr(1), &message);
      if (!message.empty()) return error(message, line_no);
      if (d.kind == Directive::Kind::kUnits) {
        if (units_line != 0 && d.unit != pre.units)
          return error(fmt::format("conflicting units comments (line {} says {})", units_line,
                                   pre.units == LengthUnit::kMm ? "mm" : "in"),
                       line_no);
        pre.units = d.unit;
        units_line = line_no;
      } else if (d.kind == Directive::Kind::kTag) {
        pre.kind = d.tag;
      }
      pos = next;
      continue;
    }
    pre.header_line = line_no;
    if (dialect == TextDialect::kCsv) {
      Result<Layout> layout = ParseTableHeader(line, source, line_no, columns);
      if (!layout.ok()) return layout.status();
      pre.layout = std::move(*layout);
      pre.data_begin = next;
      pre.data_first_line = line_no + 1;
    } else {
      std::vector<std::string_view> cells;
      SplitXyz(line, &cells);
      if (cells.size() != 3 && cells.size() != 6)
        return error(fmt::format("expected 3 values (x y z) or 6 (x y z i j k) per line, got {}",
                                 cells.size()),
                     line_no);
      pre.layout = XyzLayout(cells.size());
      pre.data_begin = pos;
      pre.data_first_line = line_no;
    }
    return pre;
  }
  if (dialect == TextDialect::kCsv) {
    if (empty)
      return error("empty file: expected a header line such as 'feature,x,y,z' and data rows", 0);
    return error("no header: the file has only comments and blank lines; expected a header "
                 "line such as 'feature,x,y,z' and data rows", 0);
  }
  return error(empty ? "empty file: expected lines of x y z [i j k]"
                     : "no points: the file has only comments and blank lines; expected lines "
                       "of x y z [i j k]",
               0);
}

// ---- chunking, threads, merge -------------------------------------------------------------

int ResolveThreads(int threads) {
  if (threads > 0) return threads;
  return static_cast<int>(HardwareThreads());
}

// Splits `data` into at most `n` pieces of at least `min_bytes`, each starting a line.
std::vector<std::string_view> SplitChunks(std::string_view data, int n, std::size_t min_bytes) {
  const std::size_t want = std::max<std::size_t>(
      1, std::min<std::size_t>(static_cast<std::size_t>(n), data.size() / std::max<std::size_t>(1, min_bytes)));
  std::vector<std::size_t> starts{0};
  for (std::size_t k = 1; k < want; ++k) {
    const std::size_t target = data.size() / want * k;
    if (target <= starts.back()) continue;
    const std::size_t nl = data.find('\n', target);
    if (nl == std::string_view::npos || nl + 1 >= data.size()) break;
    if (nl + 1 > starts.back()) starts.push_back(nl + 1);
  }
  std::vector<std::string_view> chunks;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const std::size_t e = k + 1 < starts.size() ? starts[k + 1] : data.size();
    chunks.push_back(data.substr(starts[k], e - starts[k]));
  }
  return chunks;
}

// Re-reads a chunk for the attributes kept as text (their numeric parse failed somewhere).
void ExtractText(std::string_view chunk, const Layout& layout, const std::vector<int>& text_attrs,
                 std::size_t offset, std::vector<PointAttribute>* attributes) {
  std::vector<std::string_view> cells;
  std::size_t pos = 0, idx = offset;
  while (pos < chunk.size()) {
    const std::size_t nl = chunk.find('\n', pos);
    const std::size_t le = nl == std::string_view::npos ? chunk.size() : nl;
    std::string_view line = chunk.substr(pos, le - pos);
    pos = nl == std::string_view::npos ? chunk.size() : nl + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (OnlyTableSeparators(line, layout.sep)) continue;
    if (TrimBlanks(line).front() == '#') continue;
    SplitTableCells(line, layout.sep, &cells);  // cannot fail: the line parsed
    for (int a : text_attrs)
      (*attributes)[static_cast<std::size_t>(a)].text[idx] = std::string(cells[layout.attr_column[a]]);
    ++idx;
  }
}

}  // namespace

Result<PointFile> ParsePointText(std::string_view text, const std::string& source,
                                 TextDialect dialect, const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (dialect != TextDialect::kCsv && !options.columns.empty()) return ColumnMappingNeedsTable(source);
  // The contract fixes mm as the CSV default; xyz text follows the caller's assumption.
  Result<Preamble> pre_or = ReadPreamble(
      text, source, dialect, dialect == TextDialect::kCsv ? LengthUnit::kMm : options.assumed_units, options.columns);
  if (!pre_or.ok()) return pre_or.status();
  const Preamble& pre = *pre_or;
  const Layout& layout = pre.layout;
  const Context ctx{dialect, &layout, pre.units == LengthUnit::kInch ? kMmPerInch : 1.0,
                    options.normal_tolerance, pre.data_first_line};

  const std::string_view data = text.substr(pre.data_begin);
  const std::vector<std::string_view> chunks =
      SplitChunks(data, ResolveThreads(options.threads), options.min_chunk_bytes);
  std::vector<ChunkOut> outs(chunks.size());
  ParallelForEach(chunks.size(), true, [&](std::size_t k) {
    try {
      ChunkParser parser(ctx, &outs[k]);
      if (dialect == TextDialect::kCsv)
        parser.Run<TextDialect::kCsv>(chunks[k]);
      else
        parser.Run<TextDialect::kXyz>(chunks[k]);
    } catch (const std::exception& e) {  // std::bad_alloc on huge inputs
      outs[k].failed = true;
      outs[k].error = fmt::format("cannot parse: {}", e.what());
    }
  });

  // First error in file order; line numbers of chunk k start after all lines of chunks < k.
  std::vector<std::size_t> base(chunks.size()), offset(chunks.size());
  std::size_t next_line = pre.data_first_line, total = 0;
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    base[k] = next_line;
    if (outs[k].failed)
      return Status(StatusCode::kParseError, outs[k].error, source, base[k] + outs[k].error_line);
    next_line += outs[k].lines;
    offset[k] = total;
    total += outs[k].xyz.size();
  }
  if (total == 0) {
    return Status(StatusCode::kParseError,
                  dialect == TextDialect::kCsv
                      ? "no points: expected at least one data row after the header"
                      : "no points: expected lines of x y z [i j k]",
                  source, pre.header_line);
  }

  PointFile file;
  file.info.format = dialect == TextDialect::kCsv ? PointFormat::kCsv : PointFormat::kXyz;
  file.info.kind = pre.kind;
  file.info.source_units = pre.units;
  file.info.bytes = text.size();
  file.info.chunks = static_cast<int>(chunks.size());
  PointSet& ps = file.points;
  ps.source = source;

  // Features: global ids in order of first appearance in the file.
  std::unordered_map<std::string_view, int> global_ids;
  std::vector<std::vector<int>> local_to_global(chunks.size());
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    for (std::string_view name : outs[k].names) {
      auto [it, inserted] = global_ids.try_emplace(name, static_cast<int>(ps.feature_names.size()));
      if (inserted) ps.feature_names.emplace_back(name);
      local_to_global[k].push_back(it->second);
    }
  }
  const std::size_t n_attr = layout.attr_names.size();
  std::vector<int> text_attrs;
  std::vector<char> is_text(n_attr, 0);
  for (std::size_t a = 0; a < n_attr; ++a) {
    for (const auto& o : outs) is_text[a] = is_text[a] || o.attr_text[a];
    PointAttribute attr;
    attr.name = layout.attr_names[a];
    if (is_text[a]) {
      attr.text.resize(total);
      text_attrs.push_back(static_cast<int>(a));
    } else if (chunks.size() > 1) {
      ReserveLarge(&attr.values, total);
      attr.values.resize(total);
    }
    ps.attributes.push_back(std::move(attr));
  }
  if (chunks.size() == 1) {
    // Serial parse: the chunk's arrays are the result (local ids are already global).
    ChunkOut& o = outs[0];
    ps.xyz_mm = std::move(o.xyz);
    ps.normal = std::move(o.normal);
    ps.feature = std::move(o.feature);
    ps.line = std::move(o.line);
    for (std::size_t& l : ps.line) l += base[0];
    for (std::size_t a = 0; a < n_attr; ++a)
      if (!is_text[a]) ps.attributes[a].values = std::move(o.attr[a]);
    if (!text_attrs.empty()) ExtractText(chunks[0], layout, text_attrs, 0, &ps.attributes);
    return file;
  }

  ReserveLarge(&ps.xyz_mm, total);
  ps.xyz_mm.resize(total);
  if (layout.has_normals) {
    ReserveLarge(&ps.normal, total);
    ps.normal.resize(total);
  }
  ReserveLarge(&ps.feature, total);
  ps.feature.resize(total);
  ReserveLarge(&ps.line, total);
  ps.line.resize(total);

  ParallelForEach(chunks.size(), true, [&](std::size_t k) {
    ChunkOut& o = outs[k];
    const std::size_t off = offset[k];
    std::copy(o.xyz.begin(), o.xyz.end(), ps.xyz_mm.begin() + static_cast<std::ptrdiff_t>(off));
    if (layout.has_normals)
      std::copy(o.normal.begin(), o.normal.end(), ps.normal.begin() + static_cast<std::ptrdiff_t>(off));
    const std::vector<int>& map = local_to_global[k];
    for (std::size_t i = 0; i < o.feature.size(); ++i) {
      const int f = o.feature[i];
      ps.feature[off + i] = f == PointSet::kUnlabelled ? f : map[static_cast<std::size_t>(f)];
      ps.line[off + i] = base[k] + o.line[i];
    }
    for (std::size_t a = 0; a < n_attr; ++a) {
      if (!is_text[a])
        std::copy(o.attr[a].begin(), o.attr[a].end(),
                  ps.attributes[a].values.begin() + static_cast<std::ptrdiff_t>(off));
    }
    if (!text_attrs.empty()) ExtractText(chunks[k], layout, text_attrs, off, &ps.attributes);
    o = ChunkOut();  // release chunk memory early
  });
  return file;
}

}  // namespace internal

Result<PointFile> ParsePointCsv(std::string_view text, const std::string& source_name,
                                const PointReadOptions& options) {
  return internal::ParsePointText(text, source_name, internal::TextDialect::kCsv, options);
}

Result<PointFile> ReadPointCsv(const std::string& path, const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  Result<FileBytes> bytes = ReadFileBytes(path, internal::kMaxLineBytes);
  if (!bytes.ok()) return bytes.status();
  return ParsePointCsv(bytes->view(), path, options);
}

}  // namespace tpcal::pipeline
