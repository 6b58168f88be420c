// QIF 3.0 results reader on libxml2's SAX2 parser (see qif_reader.h for the rules).
#include "pipeline/io/qif_reader.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>
#include <libxml/parser.h>
#include <libxml/parserInternals.h>
#include <libxml/xmlIO.h>
#include <libxml/xmlerror.h>
#include <libxml/xmlversion.h>

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "core/ascii.h"
#include "core/base64.h"
#include "core/input_echo.h"
#include "core/parallel.h"
#include "core/units.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

// A <MeasuredPointSet>: its points are xyz_[first, first + n) of the parser, in file units,
// and its normals (if any) normal_[normal_first, normal_first + n_normal).
struct QifPointSet {
  std::size_t line = 0;
  std::size_t count_attr = 0;  // 0: no count attribute
  std::size_t first = 0, n = 0;
  std::size_t normal_first = 0, n_normal = 0;
  std::optional<bool> compensated;
  std::optional<double> probe_radius;   // file units
  bool referenced = false;
};

// Probe centres the reader moves onto the surface: not compensated, a radius and normals.
bool MovedByReader(const QifPointSet& s) {
  return s.compensated.has_value() && !*s.compensated && s.probe_radius.has_value() && s.n_normal != 0;
}

// Points to emit: a range (1-based, inclusive) of a set, with the feature they are labelled by.
struct QifEmit {
  const QifPointSet* set;
  std::size_t first, last;
  int feature;
};

struct QifRef {
  enum class Kind { kWhole, kRange, kSingle } kind = Kind::kWhole;
  std::string set_id;
  std::size_t first = 0, last = 0;  // 1-based, inclusive (range / single)
  std::size_t line = 0;
};

struct QifMeasurement {
  std::size_t line = 0;
  std::string item_id;
  std::vector<QifRef> refs;
};

struct QifItem {
  std::size_t line = 0;
  std::string name;
  bool has_name = false;
};

bool EndsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

std::string_view TrimXml(std::string_view s) {
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// QIF's base64 point and normal arrays: <PointsBinary>/<NormalsBinary> (NIST's QIF checks) and
// <BinaryPoints>/<BinaryNormals> (the QIF 3.0 schema bindings); both spellings are read.
bool IsBinaryList(std::string_view name) {
  return name == "PointsBinary" || name == "BinaryPoints" || name == "NormalsBinary" || name == "BinaryNormals";
}
bool IsNormalsList(std::string_view name) { return name == "NormalsBinary" || name == "BinaryNormals"; }

std::string QifEcho(std::string_view s) { return "'" + EchoInput(TrimXml(s), 40) + "'"; }

std::optional<double> QifNumber(std::string_view s) {
  s = TrimXml(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0;
  auto r = fast_float::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
    return std::nullopt;
  return v;
}

std::optional<std::size_t> QifIndex(std::string_view s) {
  s = TrimXml(s);
  if (s.empty() || s.size() > 18) return std::nullopt;
  std::size_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + static_cast<std::size_t>(c - '0');
  }
  return v;
}

// Length unit name (lower case) -> mm per unit.
std::optional<double> KnownUnitMm(std::string_view unit) {
  const std::string name = AsciiLower(unit);
  if (name == "mm" || name == "millimeter" || name == "millimetre") return 1.0;
  if (name == "cm" || name == "centimeter" || name == "centimetre") return 10.0;
  if (name == "m" || name == "meter" || name == "metre") return 1000.0;
  if (name == "in" || name == "inch" || name == "inches") return kMmPerInch;
  if (name == "ft" || name == "foot" || name == "feet") return 12.0 * kMmPerInch;
  if (name == "um" || name == "micrometer" || name == "micrometre" || name == "micron") return 1e-3;
  return std::nullopt;
}

// Line of a <!DOCTYPE in the prologue (before the root element), or 0.
std::size_t DoctypeLine(std::string_view t) {
  std::size_t i = 0, line = 1;
  auto skip_to = [&](std::string_view end) {
    const std::size_t e = t.find(end, i);
    const std::size_t stop = e == std::string_view::npos ? t.size() : e + end.size();
    for (; i < stop; ++i) line += t[i] == '\n' ? 1 : 0;
  };
  while (i < t.size()) {
    const char c = t[i];
    if (c == '\n') ++line;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || static_cast<unsigned char>(c) >= 0x80) {
      ++i;  // blanks, a byte-order mark
    } else if (t.compare(i, 4, "<!--") == 0) {
      skip_to("-->");
    } else if (t.compare(i, 2, "<?") == 0) {
      skip_to("?>");
    } else {
      return t.compare(i, 9, "<!DOCTYPE") == 0 ? line : 0;
    }
  }
  return 0;
}

// The attributes of a start tag as SAX2 gives them: five pointers per attribute (local name,
// prefix, namespace, value begin, value end), values with character references replaced.
struct XmlAttrs {
  const xmlChar** a = nullptr;
  int n = 0;

  // The value of the unprefixed attribute `name`, "" if absent.
  std::string Get(std::string_view name) const {
    for (int k = 0; k < n; ++k) {
      const xmlChar** at = a + 5 * k;
      if (at[1] == nullptr && name == reinterpret_cast<const char*>(at[0]))
        return std::string(reinterpret_cast<const char*>(at[3]), static_cast<std::size_t>(at[4] - at[3]));
    }
    return {};
  }
};

// The document as libxml2 pulls it through its read callback: the file's bytes, except that the
// rest of a block parsed straight from the file is handed over as its newlines only, so libxml2
// keeps counting lines without scanning (and copying) the numbers again. Offsets in what was
// handed over map back to file offsets.
class QifFeed {
 public:
  explicit QifFeed(std::string_view file = {}) : file_(file) {}

  // Fills `out` with up to `len` bytes; 0 at the end.
  int Read(char* out, int len) {
    const std::size_t want = static_cast<std::size_t>(std::max(len, 0));
    std::size_t n = 0;
    while (n < want) {
      if (pos_ >= skip_b_ && pos_ < skip_e_) {
        const std::size_t k = std::min(want - n, skip_newlines_);
        std::memset(out + n, '\n', k);
        n += k;
        delivered_ += k;
        skip_newlines_ -= k;
        if (skip_newlines_ == 0) {
          pos_ = skip_e_;
          shifts_.emplace_back(delivered_, pos_ - delivered_);
        }
        continue;
      }
      const std::size_t stop = pos_ < skip_b_ ? skip_b_ : file_.size();
      const std::size_t k = std::min(want - n, stop - pos_);
      if (k == 0) break;
      std::memcpy(out + n, file_.data() + pos_, k);
      pos_ += k;
      n += k;
      delivered_ += k;
    }
    return static_cast<int>(n);
  }

  // The file's bytes [b, e), parsed already and holding `newlines` line ends, are handed over as
  // those line ends from where libxml2 has read to (worth it from 64 KiB on).
  void Skip(std::size_t b, std::size_t e, std::size_t newlines) {
    if (b < pos_) newlines -= static_cast<std::size_t>(std::count(file_.data() + b, file_.data() + std::min(pos_, e), '\n'));
    b = std::max(b, pos_);
    if (e <= b || e - b < (std::size_t{1} << 16)) return;
    skip_b_ = b;
    skip_e_ = e;
    skip_newlines_ = newlines;
  }

  std::size_t Delivered() const { return delivered_; }

  // File offset of an offset into what was handed over (inside a skipped block: an offset in it).
  std::size_t FileOffset(std::size_t handed) const {
    auto it = std::upper_bound(shifts_.begin(), shifts_.end(), std::make_pair(handed, SIZE_MAX));
    return it == shifts_.begin() ? handed : handed + std::prev(it)->second;
  }

 private:
  std::string_view file_;
  std::size_t pos_ = 0, delivered_ = 0;  // file bytes read, bytes handed over
  std::size_t skip_b_ = 0, skip_e_ = 0, skip_newlines_ = 0;
  std::vector<std::pair<std::size_t, std::size_t>> shifts_;  // (handed-over offset, file - handed) from there on
};

// The streaming pass: collects items, measurements, point sets and units, then Assemble().
class QifParser {
 public:
  QifParser(std::string source, const QifReadOptions& options) : source_(std::move(source)), options_(options) {}

  Result<QifFile> Run(std::string_view text);

  static void OnXmlError(void* self, const xmlError* error) {
    auto* p = static_cast<QifParser*>(self);
    if (p->xml_error_line_ != 0 || error == nullptr || error->level < XML_ERR_ERROR) return;  // the first error
    p->xml_error_line_ = error->line > 0 ? static_cast<std::size_t>(error->line) : 1;
    std::string msg = error->message != nullptr ? error->message : "malformed XML";
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    p->xml_error_ = msg;
  }

 private:
  Status Error(std::size_t line, std::string what) const {
    return Status(StatusCode::kParseError, std::move(what), source_, line);
  }
  std::string_view Parent(std::size_t up = 1) const {
    return stack_.size() > up ? stack_[stack_.size() - 1 - up] : std::string_view{};
  }
  bool Under(std::string_view name) const {
    for (std::string_view s : stack_)
      if (s == name) return true;
    return false;
  }

  // SAX2 callbacks (user data: the parser); after a failure they do nothing.
  static void SaxStart(void* self, const xmlChar* local, const xmlChar* prefix, const xmlChar* uri, int n_ns,
                       const xmlChar** ns, int n_attrs, int n_defaulted, const xmlChar** attrs);
  static void SaxEnd(void* self, const xmlChar* local, const xmlChar* prefix, const xmlChar* uri);
  static void SaxText(void* self, const xmlChar* text, int len);
  static void SaxComment(void* self, const xmlChar* text);
  static void SaxCdata(void* self, const xmlChar* text, int len);
  static void SaxPi(void* self, const xmlChar* target, const xmlChar* data);
  std::size_t ParserLine() const { return static_cast<std::size_t>(std::max(1, ctxt_->input->line)); }
  void Fail(Status s);  // keeps the first failure and stops libxml2

  Status OnElement(std::string_view name, const XmlAttrs& attrs);
  Status OnStart(const XmlAttrs& attrs, std::string_view name, std::size_t line);
  Status OnEnd(std::string_view name, std::size_t line);
  Status OnBlockText(std::string_view text);  // text of <Points>/<Normals>, in pieces
  void ParsePlainBlock();
  std::optional<std::size_t> RawOffset(const xmlChar* at) const;
  Status FlushCarry();
  Status OnNumbers(std::string_view text);
  bool ParsePlainParallel(std::string_view text, std::size_t pieces);
  // One number of the current <Points>/<Normals> (`line`: its line); a completed triple is
  // stored, a normal checked first (its length is the only failure).
  Status Take(double v, std::size_t line) {
    if (in_triple_ == 0) triple_line_ = line;
    triple_[in_triple_++] = v;
    if (in_triple_ < 3) return Status::Ok();
    in_triple_ = 0;
    if (block_ == Block::kNormals) return TakeNormal();
    xyz_.emplace_back(triple_[0], triple_[1], triple_[2]);
    xyz_line_.push_back(triple_line_);
    ++cur_set_->n;
    return Status::Ok();
  }
  Status TakeNormal();
  Status StartBinary(const XmlAttrs& attrs, std::string_view name, std::size_t line);
  Status TakeBinary(std::string_view name);
  Status FinishSet();
  void ReserveFor(std::vector<Eigen::Vector3d>* v);
  Result<QifFile> Assemble();
  void EmitPoints(const std::vector<QifEmit>& plan, double mm_per_unit, PointSet* ps);

  std::string source_;
  QifReadOptions options_;
  std::size_t text_bytes_ = 0;  // size of the document, bounds reservations
  xmlParserCtxtPtr ctxt_ = nullptr;
  Status failure_ = Status::Ok();
  bool saw_root_ = false;
  std::vector<std::string_view> stack_;  // local names (libxml2 dictionary, live with the parser)
  std::string text_;                     // text of the current simple element
  std::size_t xml_error_line_ = 0;
  std::string xml_error_;

  // units
  bool in_primary_linear_ = false;
  std::size_t unit_line_ = 0;
  std::string unit_name_, si_unit_name_;
  std::optional<double> factor_;
  bool have_unit_ = false;

  std::map<std::string, QifItem> items_;
  std::string cur_item_;
  std::vector<QifMeasurement> measurements_;
  bool in_measurement_ = false;
  QifRef cur_ref_;

  std::map<std::string, QifPointSet> sets_;
  std::vector<std::string> set_order_;
  // Points of every set in file order (file units), their lines, and the normals (unit).
  std::vector<Eigen::Vector3d> xyz_, normal_;
  std::vector<std::size_t> xyz_line_;
  std::string cur_set_id_;
  QifPointSet* cur_set_ = nullptr;
  // <Points> / <Normals> text being parsed
  enum class Block { kNone, kPoints, kNormals } block_ = Block::kNone;
  std::size_t block_line_ = 0;  // current line inside the block
  std::size_t triple_line_ = 0;
  double triple_[3] = {0, 0, 0};
  int in_triple_ = 0;
  std::string carry_;  // a number cut where one piece of block text ends and the next begins
  // <BinaryPoints> / <BinaryNormals> being read: its base64 text, line and attributes
  bool in_binary_ = false;
  std::string binary_;
  std::size_t binary_line_ = 0, binary_count_ = 0, binary_size_ = 0;
  QifFeed feed_;  // the document as libxml2 reads it
  std::string_view raw_;
  // The current <Points>/<Normals> text was parsed from the file by ParsePlainBlock: libxml2's
  // character callbacks up to the next markup are that text again (in libxml2's own buffer, or in
  // a copy when CR LF line ends send it down its slow path) and are dropped.
  bool block_parsed_ = false;
};

Status QifParser::OnStart(const XmlAttrs& attrs, std::string_view name, std::size_t line) {
  text_.clear();
  const std::string_view parent = stack_.empty() ? std::string_view{} : stack_.back();
  if (name == "LinearUnit" && parent == "PrimaryUnits" && Under("FileUnits")) {
    in_primary_linear_ = true;
    unit_line_ = line;
  } else if (EndsWith(name, "FeatureItem") && parent == "FeatureItems") {
    cur_item_ = attrs.Get("id");
    if (cur_item_.empty()) return Error(line, fmt::format("<{}> without an id attribute: expected id=\"N\"", name));
    QifItem& item = items_[cur_item_];
    item.line = line;
  } else if (EndsWith(name, "FeatureMeasurement") && parent == "MeasuredFeatures") {
    in_measurement_ = true;
    measurements_.push_back({line, {}, {}});
  } else if (in_measurement_ && Parent(0) == "PointList") {
    QifRef ref;
    ref.line = line;
    if (name == "WholePointSetId") {
      ref.kind = QifRef::Kind::kWhole;
    } else if (name == "RangePointSetId") {
      ref.kind = QifRef::Kind::kRange;
      const std::string range = attrs.Get("range");
      const std::size_t sp = range.find_first_of(" \t");
      auto a = QifIndex(std::string_view(range).substr(0, sp));
      auto b = sp == std::string::npos ? std::nullopt : QifIndex(TrimXml(std::string_view(range).substr(sp)));
      if (!a || !b || *a < 1 || *b < *a)
        return Error(line, fmt::format("<RangePointSetId range=\"{}\">: expected range=\"first last\", "
                                       "1-based point indices, first <= last", range));
      ref.first = *a;
      ref.last = *b;
    } else if (name == "SinglePointSetId") {
      ref.kind = QifRef::Kind::kSingle;
      const std::string index = attrs.Get("index");
      auto k = QifIndex(index);
      if (!k || *k < 1)
        return Error(line, fmt::format("<SinglePointSetId index=\"{}\">: expected a 1-based point index", index));
      ref.first = ref.last = *k;
    } else {
      return Error(line, fmt::format("<{}> in a <PointList>: expected WholePointSetId, RangePointSetId or "
                                     "SinglePointSetId", name));
    }
    cur_ref_ = ref;
  } else if (name == "MeasuredPointSet" && parent == "MeasuredPointSets") {
    cur_set_id_ = attrs.Get("id");
    if (cur_set_id_.empty()) return Error(line, "<MeasuredPointSet> without an id attribute: expected id=\"N\"");
    if (sets_.count(cur_set_id_) != 0)
      return Error(line, fmt::format("<MeasuredPointSet id=\"{}\"> appears twice: expected unique ids", cur_set_id_));
    cur_set_ = &sets_[cur_set_id_];
    set_order_.push_back(cur_set_id_);
    cur_set_->line = line;
    cur_set_->first = xyz_.size();
    cur_set_->normal_first = normal_.size();
    const std::string count = attrs.Get("count");
    if (!count.empty()) {
      auto c = QifIndex(count);
      if (!c) return Error(line, fmt::format("<MeasuredPointSet count=\"{}\">: expected a point count", count));
      cur_set_->count_attr = *c;
    }
  } else if (cur_set_ != nullptr && parent == "MeasuredPointSet") {
    if (name == "Points" || name == "Normals") {
      block_ = name == "Points" ? Block::kPoints : Block::kNormals;
      block_line_ = line;
      in_triple_ = 0;
      block_parsed_ = false;
      if (block_ == Block::kNormals ? cur_set_->n_normal != 0 : cur_set_->n != 0)
        return Error(line, fmt::format("a second list of {}: expected one per MeasuredPointSet",
                                       block_ == Block::kNormals ? "normals" : "points"));
      ReserveFor(block_ == Block::kPoints ? &xyz_ : &normal_);
      ParsePlainBlock();
      return Status::Ok();
    } else if (IsBinaryList(name)) {
      return StartBinary(attrs, name, line);
    }
  }
  return Status::Ok();
}

inline bool QifBlank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// The token [b, e) as a finite number (an optional leading '+', then what fast_float reads).
inline bool QifToken(const char* b, const char* e, double* v) {
  const char* nb = (*b == '+' && e - b > 1) ? b + 1 : b;
  auto res = fast_float::from_chars(nb, e, *v);
  return res.ec == std::errc() && res.ptr == e && std::isfinite(*v);
}

Status QifParser::TakeNormal() {
  const Eigen::Vector3d t(triple_[0], triple_[1], triple_[2]);
  const double len = t.norm();
  if (!(len > 1e-12) || std::abs(len - 1.0) > 1e-3)
    return Error(triple_line_, fmt::format("normal ({} {} {}) of MeasuredPointSet id=\"{}\" has length {:.6g}: "
                                           "expected a unit vector", t.x(), t.y(), t.z(), cur_set_id_, len));
  normal_.push_back(std::abs(len - 1.0) > 1e-14 ? Eigen::Vector3d(t / len) : t);  // as the CSV reader
  ++cur_set_->n_normal;
  return Status::Ok();
}

// Numbers of a <Points>/<Normals> text, one at a time, counting lines as it goes.
Status QifParser::OnNumbers(std::string_view text) {
  const char* p = text.data();
  const char* end = p + text.size();
  while (true) {
    while (p < end && QifBlank(*p)) {
      if (*p == '\n') ++block_line_;
      ++p;
    }
    if (p >= end) return Status::Ok();
    const char* tb = p;
    while (p < end && !QifBlank(*p)) ++p;
    double v = 0;
    if (!QifToken(tb, p, &v))
      return Error(block_line_, fmt::format("{} in <{}> of MeasuredPointSet id=\"{}\": expected numbers, three per point",
                                            QifEcho(std::string_view(tb, static_cast<std::size_t>(p - tb))),
                                            block_ == Block::kPoints ? "Points" : "Normals", cur_set_id_));
    TPCAL_RETURN_IF_ERROR(Take(v, block_line_));
  }
}

// Pieces of `text` for the parallel parse: about `n` of them, cut at blanks.
std::vector<std::string_view> SplitAtBlanks(std::string_view text, std::size_t n) {
  std::vector<std::string_view> parts;
  std::size_t b = 0;
  for (std::size_t k = 1; k <= n; ++k) {
    std::size_t e = k == n ? text.size() : std::max(b, text.size() * k / n);
    while (e < text.size() && !QifBlank(text[e])) ++e;
    parts.push_back(text.substr(b, e - b));
    b = e;
  }
  return parts;
}

// A large plain block on all threads, in two passes: each piece counts its tokens and newlines,
// then parses its numbers straight into their places in xyz_ (or normal_): the same values and
// lines as OnNumbers. False, with nothing changed, when a token is not a number, the block does
// not hold whole triples or a normal is off unit length: OnNumbers then says which.
bool QifParser::ParsePlainParallel(std::string_view text, std::size_t pieces) {
  const std::vector<std::string_view> parts = SplitAtBlanks(text, pieces);
  std::vector<std::size_t> tokens(parts.size(), 0), newlines(parts.size(), 0);
  ParallelForEach(parts.size(), true, [&](std::size_t k) {
    bool in_token = false;
    std::size_t n_tokens = 0, n_newlines = 0;  // local: the pieces' counters share a cache line
    for (char c : parts[k]) {
      const bool blank = QifBlank(c);
      n_tokens += !blank && !in_token;
      n_newlines += c == '\n';
      in_token = !blank;
    }
    tokens[k] = n_tokens;
    newlines[k] = n_newlines;
  });
  std::size_t total = 0;
  for (std::size_t t : tokens) total += t;
  if (total % 3 != 0) return false;
  const bool points = block_ == Block::kPoints;
  std::vector<Eigen::Vector3d>& dst = points ? xyz_ : normal_;
  const std::size_t base = dst.size(), n_new = total / 3;
  dst.resize(base + n_new);
  if (points) xyz_line_.resize(base + n_new);
  std::vector<char> ok(parts.size(), 1);
  std::vector<std::size_t> first_token(parts.size(), 0), first_line(parts.size(), block_line_);
  for (std::size_t k = 1; k < parts.size(); ++k) {
    first_token[k] = first_token[k - 1] + tokens[k - 1];
    first_line[k] = first_line[k - 1] + newlines[k - 1];
  }
  ParallelForEach(parts.size(), true, [&](std::size_t k) {
    const char* p = parts[k].data();
    const char* end = p + parts[k].size();
    std::size_t t = first_token[k], line = first_line[k];
    while (true) {
      while (p < end && QifBlank(*p)) line += *p++ == '\n';
      if (p >= end) return;
      const char* tb = p;
      while (p < end && !QifBlank(*p)) ++p;
      double v = 0;
      if (!QifToken(tb, p, &v)) {
        ok[k] = 0;
        return;
      }
      dst[base + t / 3][static_cast<Eigen::Index>(t % 3)] = v;
      if (points && t % 3 == 0) xyz_line_[base + t / 3] = line;
      ++t;
    }
  });
  bool good = std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
  for (std::size_t i = base; good && !points && i < dst.size(); ++i) {
    const double len = dst[i].norm();  // as TakeNormal
    good = len > 1e-12 && std::abs(len - 1.0) <= 1e-3;
    if (good && std::abs(len - 1.0) > 1e-14) dst[i] /= len;
  }
  if (!good) {
    dst.resize(base);
    if (points) xyz_line_.resize(base);
    return false;
  }
  (points ? cur_set_->n : cur_set_->n_normal) += n_new;
  block_line_ = first_line.back() + newlines.back();
  return true;
}

// At the first <Points> (<Normals>) block, room for the triples the document can plausibly hold
// (>= 24 bytes each: "x y z" at about 8 bytes a number): one allocation for a scan, no copies
// as it grows; pages never written cost nothing.
void QifParser::ReserveFor(std::vector<Eigen::Vector3d>* v) {
  if (v->capacity() != 0) return;
  const std::size_t n = text_bytes_ / 24 + 16;
  v->reserve(n);
  if (v == &xyz_) xyz_line_.reserve(n);
}

// A <BinaryPoints>/<BinaryNormals> (QIF ArrayBinaryType) starts: count and sizeElement checked.
Status QifParser::StartBinary(const XmlAttrs& attrs, std::string_view name, std::size_t line) {
  const bool normals = IsNormalsList(name);
  if (normals ? cur_set_->n_normal != 0 : cur_set_->n != 0)
    return Error(line, fmt::format("a second list of {}: expected one per MeasuredPointSet", normals ? "normals" : "points"));
  const std::string size = attrs.Get("sizeElement"), count = attrs.Get("count");
  if (size != "8" && size != "4")
    return Error(line, fmt::format("<{} sizeElement=\"{}\">: expected 8 (64-bit IEEE numbers) or 4 (32-bit)", name,
                                   EchoInput(size, 40)));
  auto c = QifIndex(count);
  if (!count.empty() && !c)
    return Error(line, fmt::format("<{} count=\"{}\">: expected a number of elements", name, EchoInput(count, 40)));
  in_binary_ = true;
  binary_.clear();
  binary_line_ = line;
  binary_count_ = c.value_or(0);
  binary_size_ = size == "8" ? 8 : 4;
  return Status::Ok();
}

// Element k of a binary array: little-endian IEEE 754 of binary_size_ bytes.
double BinaryElement(const std::string& bytes, std::size_t k, std::size_t size) {
  std::uint64_t u = 0;
  for (std::size_t b = 0; b < size; ++b)
    u |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[k * size + b])) << (8 * b);
  if (size == 8) return std::bit_cast<double>(u);
  return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)));
}

// The decoded array as points (file units, the line of its start tag) or unit normals: x y z per
// point; `count` may give the elements (3 per point) or the points.
Status QifParser::TakeBinary(std::string_view name) {
  const bool normals = IsNormalsList(name);
  std::size_t bad = 0;
  const std::size_t text_size = binary_.size();
  const std::optional<std::string> bytes = DecodeBase64(binary_, &bad);
  std::string().swap(binary_);
  if (!bytes && bad == text_size)
    return Error(binary_line_, fmt::format("<{}> of MeasuredPointSet id=\"{}\": its base64 text ends inside a group "
                                           "of 4 characters: expected whole groups (with = padding)", name, cur_set_id_));
  if (!bytes)
    return Error(binary_line_, fmt::format("<{}> of MeasuredPointSet id=\"{}\": character {} of its text is not "
                                           "base64: expected RFC 4648 base64", name, cur_set_id_, bad + 1));
  const std::size_t triple = 3 * binary_size_;
  if (bytes->size() % triple != 0)
    return Error(binary_line_, fmt::format("<{}> of MeasuredPointSet id=\"{}\" holds {} bytes: expected whole x y z "
                                           "triples of {}-byte numbers", name, cur_set_id_, bytes->size(), binary_size_));
  const std::size_t n = bytes->size() / triple;
  if (binary_count_ != 0 && binary_count_ != 3 * n && binary_count_ != n)
    return Error(binary_line_, fmt::format("<{} count=\"{}\"> holds {} triples: expected count to give its {} "
                                           "elements (or {} points)", name, binary_count_, n, 3 * n, n));
  std::vector<Eigen::Vector3d>& dst = normals ? normal_ : xyz_;
  dst.reserve(dst.size() + n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) triple_[k] = BinaryElement(*bytes, 3 * i + static_cast<std::size_t>(k), binary_size_);
    if (!std::isfinite(triple_[0]) || !std::isfinite(triple_[1]) || !std::isfinite(triple_[2]))
      return Error(binary_line_, fmt::format("<{}> triple {} of MeasuredPointSet id=\"{}\" is not finite: expected "
                                             "numbers", name, i + 1, cur_set_id_));
    if (normals) {
      triple_line_ = binary_line_;
      TPCAL_RETURN_IF_ERROR(TakeNormal());
    } else {
      xyz_.emplace_back(triple_[0], triple_[1], triple_[2]);
      xyz_line_.push_back(binary_line_);
      ++cur_set_->n;
    }
  }
  return Status::Ok();
}

Status QifParser::FinishSet() {
  QifPointSet& s = *cur_set_;
  if (s.n == 0) return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" has no <Points>: expected x y z triples", cur_set_id_));
  if (s.count_attr != 0 && s.count_attr != s.n)
    return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" says count=\"{}\" but holds {} points: expected "
                                     "them to agree", cur_set_id_, s.count_attr, s.n));
  if (s.n_normal != 0 && s.n_normal != s.n)
    return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" has {} points and {} normals: expected one normal "
                                     "per point", cur_set_id_, s.n, s.n_normal));
  if (s.compensated.has_value() && !*s.compensated) {
    if (!s.probe_radius.has_value() && !options_.accept_uncompensated)
      return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" is not probe-compensated (<Compensated>false) and "
                                       "gives no <ProbeRadius>: expected compensated points or the probe radius",
                                       cur_set_id_));
    if (s.n_normal == 0 && !options_.accept_uncompensated)
      return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" is not probe-compensated (<Compensated>false, "
                                       "ProbeRadius {}) and has no <Normals> to compensate along: expected "
                                       "compensated points or normals",
                                       cur_set_id_, s.probe_radius.value_or(0.0)));
  }
  cur_set_ = nullptr;
  return Status::Ok();
}

Status QifParser::OnEnd(std::string_view name, std::size_t line) {
  const std::string_view parent = Parent(1);
  const std::string_view text = TrimXml(text_);
  if (in_primary_linear_) {
    if (name == "LinearUnit") {
      in_primary_linear_ = false;
      have_unit_ = true;
    } else if (name == "UnitName") {
      unit_name_ = std::string(text);
    } else if (name == "SIUnitName") {
      si_unit_name_ = std::string(text);
    } else if (name == "Factor" && parent == "UnitConversion") {
      auto f = QifNumber(text);
      if (!f || *f <= 0) return Error(line, fmt::format("<Factor> {}: expected a positive number (metres per unit)", QifEcho(text)));
      factor_ = *f;
    }
  } else if (!cur_item_.empty() && EndsWith(name, "FeatureItem") && parent == "FeatureItems") {
    cur_item_.clear();
  } else if (!cur_item_.empty() && name == "FeatureName" && EndsWith(parent, "FeatureItem")) {
    QifItem& item = items_[cur_item_];
    item.name = std::string(text);
    item.has_name = !item.name.empty();
  } else if (in_measurement_ && EndsWith(name, "FeatureMeasurement") && parent == "MeasuredFeatures") {
    in_measurement_ = false;
  } else if (in_measurement_ && name == "FeatureItemId" && EndsWith(parent, "FeatureMeasurement")) {
    measurements_.back().item_id = std::string(text);
  } else if (in_measurement_ && parent == "PointList" &&
             (name == "WholePointSetId" || name == "RangePointSetId" || name == "SinglePointSetId")) {
    if (text.empty()) return Error(cur_ref_.line, fmt::format("empty <{}>: expected a MeasuredPointSet id", name));
    cur_ref_.set_id = std::string(text);
    measurements_.back().refs.push_back(cur_ref_);
  } else if (cur_set_ != nullptr) {
    if (name == "MeasuredPointSet") return FinishSet();
    if (parent == "MeasuredPointSet") {
      if (name == "Points" || name == "Normals") {
        if (in_triple_ != 0)
          return Error(triple_line_, fmt::format("<{}> of MeasuredPointSet id=\"{}\" ends inside a triple: expected "
                                                 "three numbers per point", name, cur_set_id_));
        block_ = Block::kNone;
      } else if (IsBinaryList(name)) {
        in_binary_ = false;
        return TakeBinary(name);
      } else if (name == "Compensated") {
        if (text == "true" || text == "1") cur_set_->compensated = true;
        else if (text == "false" || text == "0") cur_set_->compensated = false;
        else return Error(line, fmt::format("<Compensated> {}: expected true or false", QifEcho(text)));
      } else if (name == "ProbeRadius") {
        auto v = QifNumber(text);
        if (!v || *v < 0) return Error(line, fmt::format("<ProbeRadius> {}: expected a length >= 0", QifEcho(text)));
        cur_set_->probe_radius = *v;
      }
    }
  }
  return Status::Ok();
}

void QifParser::Fail(Status s) {
  if (failure_.ok()) failure_ = std::move(s);
  xmlStopParser(ctxt_);
}

void QifParser::SaxStart(void* self, const xmlChar* local, const xmlChar*, const xmlChar*, int, const xmlChar**,
                         int n_attrs, int, const xmlChar** attrs) {
  auto* p = static_cast<QifParser*>(self);
  p->block_parsed_ = false;
  if (!p->failure_.ok()) return;
  const std::string_view name = local != nullptr ? reinterpret_cast<const char*>(local) : "";
  if (Status s = p->OnElement(name, XmlAttrs{attrs, n_attrs}); !s.ok()) p->Fail(std::move(s));
}

Status QifParser::OnElement(std::string_view name, const XmlAttrs& attrs) {
  const std::size_t line = ParserLine();
  if (!saw_root_) {
    saw_root_ = true;
    if (name != "QIFDocument") return Error(line, fmt::format("root element <{}>: expected <QIFDocument> (QIF 3.0)", name));
  }
  if (block_ != Block::kNone) return Error(line, fmt::format("<{}> inside <Points>/<Normals>: expected only numbers", name));
  if (in_binary_) return Error(line, fmt::format("<{}> inside <{}>: expected only base64 text", name, Parent(0)));
  TPCAL_RETURN_IF_ERROR(OnStart(attrs, name, line));  // sees its parent on top of the stack
  stack_.push_back(name);
  return Status::Ok();
}

void QifParser::SaxEnd(void* self, const xmlChar*, const xmlChar*, const xmlChar*) {
  auto* p = static_cast<QifParser*>(self);
  p->block_parsed_ = false;
  if (!p->failure_.ok() || p->stack_.empty()) return;
  Status s = p->block_ != Block::kNone ? p->FlushCarry() : Status::Ok();
  if (s.ok()) s = p->OnEnd(p->stack_.back(), p->ParserLine());
  p->stack_.pop_back();
  if (!s.ok()) p->Fail(std::move(s));
}

void QifParser::SaxText(void* self, const xmlChar* text, int len) {
  auto* p = static_cast<QifParser*>(self);
  if (!p->failure_.ok() || len <= 0) return;
  const std::string_view value(reinterpret_cast<const char*>(text), static_cast<std::size_t>(len));
  if (p->in_binary_) {
    p->binary_.append(value);
  } else if (p->block_ != Block::kNone) {
    if (p->block_parsed_) return;
    if (Status s = p->OnBlockText(value); !s.ok()) p->Fail(std::move(s));
  } else if (p->text_.size() < 4096) {
    p->text_.append(value);
  }
}

void QifParser::SaxCdata(void* self, const xmlChar* text, int len) {
  static_cast<QifParser*>(self)->block_parsed_ = false;
  SaxText(self, text, len);
}

void QifParser::SaxPi(void* self, const xmlChar*, const xmlChar*) { static_cast<QifParser*>(self)->block_parsed_ = false; }

void QifParser::SaxComment(void* self, const xmlChar* text) {
  auto* p = static_cast<QifParser*>(self);
  p->block_parsed_ = false;
  if (!p->failure_.ok() || p->block_ == Block::kNone || text == nullptr) return;
  if (Status s = p->FlushCarry(); !s.ok()) return p->Fail(std::move(s));  // a comment ends a number
  for (const xmlChar* c = text; *c != 0; ++c) p->block_line_ += *c == '\n' ? 1 : 0;
}

// libxml2 gives a text in pieces (one for a plain ASCII <Points> text, more around CR LF, entity
// references and non-ASCII bytes); a number cut at a piece's end is carried to the next piece.
Status QifParser::OnBlockText(std::string_view text) {
  if (!carry_.empty()) {
    std::size_t k = 0;
    while (k < text.size() && !QifBlank(text[k])) ++k;
    carry_.append(text.substr(0, k));
    if (k == text.size()) return Status::Ok();
    TPCAL_RETURN_IF_ERROR(FlushCarry());
    text.remove_prefix(k);
  }
  std::size_t tail = text.size();
  while (tail > 0 && !QifBlank(text[tail - 1])) --tail;
  TPCAL_RETURN_IF_ERROR(OnNumbers(text.substr(0, tail)));
  carry_.assign(text.substr(tail));
  return Status::Ok();
}

// File offset of `at`, a position in libxml2's input buffer; none when libxml2 converts the
// file's encoding (its buffer then no longer holds the file's bytes).
std::optional<std::size_t> QifParser::RawOffset(const xmlChar* at) const {
  const xmlParserInputPtr in = ctxt_->input;
  if (in == nullptr || in->buf == nullptr || in->buf->encoder != nullptr || at < in->base || at > in->end)
    return std::nullopt;
  const std::size_t read = feed_.Delivered();
  const std::size_t behind = static_cast<std::size_t>(in->end - at);
  if (behind > read) return std::nullopt;
  return feed_.FileOffset(read - behind);
}

// Called at a <Points>/<Normals> start tag: the text after it, up to the next '<', is parsed
// straight from the file's bytes (in parallel when large) and SaxText then skips it. Any text
// that does not parse so (a character reference, a lone CR that libxml2 reads as a line end, a
// bad number) is undone here and reaches OnBlockText piece by piece from libxml2, which gives
// the same points, lines and errors.
void QifParser::ParsePlainBlock() {
  const std::optional<std::size_t> at = RawOffset(ctxt_->input->cur);  // libxml2 stands on the '>'
  if (!at || *at >= raw_.size() || raw_[*at] != '>') return;
  const std::size_t b = *at + 1;
  const std::size_t e = std::min(raw_.find('<', b), raw_.size());
  const std::string_view block = raw_.substr(b, e - b);
  for (std::size_t cr = block.find('\r'); cr != std::string_view::npos; cr = block.find('\r', cr + 1))
    if (cr + 1 == block.size() || block[cr + 1] != '\n') return;
  const std::size_t n_xyz = xyz_.size(), n_normal = normal_.size(), set_n = cur_set_->n, set_nn = cur_set_->n_normal;
  const std::size_t line = block_line_;
  constexpr std::size_t kPieceBytes = std::size_t{1} << 17;  // 128 KiB: a piece is worth a task
  const std::size_t threads = options_.threads > 0 ? static_cast<std::size_t>(options_.threads) : HardwareThreads();
  const std::size_t pieces = std::min(threads, block.size() / kPieceBytes);
  if ((pieces > 1 && ParsePlainParallel(block, pieces)) || OnNumbers(block).ok()) {
    block_parsed_ = true;
    feed_.Skip(b, e, block_line_ - line);
    return;
  }
  xyz_.resize(n_xyz);
  xyz_line_.resize(n_xyz);
  normal_.resize(n_normal);
  cur_set_->n = set_n;
  cur_set_->n_normal = set_nn;
  block_line_ = line;
  in_triple_ = 0;
}

Status QifParser::FlushCarry() {
  if (carry_.empty()) return Status::Ok();
  const std::string token = std::move(carry_);
  carry_.clear();
  return OnNumbers(token);
}

Result<QifFile> QifParser::Run(std::string_view text) {
  if (text.size() > static_cast<std::size_t>(INT_MAX))
    return Error(0, "file larger than 2 GiB: expected a smaller QIF file (libxml2 limit)");
  // No DTD: QIF uses XML Schema, and XML_PARSE_HUGE (needed for a scan's <Points>) lifts
  // libxml2's entity-expansion limits, so a document type declaration is refused up front.
  if (auto doctype = DoctypeLine(text); doctype != 0)
    return Error(doctype, "<!DOCTYPE ...>: expected no document type declaration (QIF 3.0 uses XML Schema)");
  if (text.empty()) return Error(1, "malformed XML (the file is empty): expected a well-formed QIF document");
  text_bytes_ = text.size();
  static std::once_flag init;
  std::call_once(init, [] { xmlInitParser(); });
  xmlSAXHandler sax;
  std::memset(&sax, 0, sizeof(sax));
  sax.initialized = XML_SAX2_MAGIC;
  sax.startElementNs = &QifParser::SaxStart;
  sax.endElementNs = &QifParser::SaxEnd;
  sax.characters = sax.ignorableWhitespace = &QifParser::SaxText;
  sax.cdataBlock = &QifParser::SaxCdata;
  sax.comment = &QifParser::SaxComment;
  sax.processingInstruction = &QifParser::SaxPi;
#if LIBXML_VERSION >= 21200
  sax.serror = &QifParser::OnXmlError;
#else
  sax.serror = [](void* self, xmlErrorPtr e) { QifParser::OnXmlError(self, e); };
#endif
  // libxml2 pulls the text in 4 kB pieces through a read callback: its buffer stays small and
  // warm (a memory input of 2.9 copies the whole file into fresh memory first).
  raw_ = text;
  feed_ = QifFeed(text);
  auto read = [](void* ctx, char* out, int len) -> int { return static_cast<QifFeed*>(ctx)->Read(out, len); };
  ctxt_ = xmlCreateIOParserCtxt(&sax, this, read, nullptr, &feed_, XML_CHAR_ENCODING_NONE);
  if (ctxt_ == nullptr || ctxt_->sax == nullptr) return Error(1, "cannot start the XML parser: expected an XML document");
  struct Closer {
    xmlParserCtxtPtr c;
    ~Closer() { xmlFreeParserCtxt(c); }
  } closer{ctxt_};
  xmlCtxtUseOptions(ctxt_, XML_PARSE_NONET | XML_PARSE_HUGE | XML_PARSE_BIG_LINES);
  const int ret = xmlParseDocument(ctxt_);
  if (!failure_.ok()) return failure_;
  if (ret != 0 || !ctxt_->wellFormed || xml_error_line_ != 0) {
    const std::size_t line = xml_error_line_ != 0 ? xml_error_line_ : ParserLine();
    return Error(line, fmt::format("malformed XML ({}): expected a well-formed QIF document",
                                   xml_error_.empty() ? "parse error" : xml_error_));
  }
  if (!saw_root_) return Error(1, "no XML element: expected a QIF 3.0 document (<QIFDocument>)");
  return Assemble();
}

// The planned points into `ps` in mm. A plan that is every point in file order, none moved by
// the reader (a scan, a plain CMM export), takes the parsed arrays without a copy; any other plan
// gathers them, moving probe centres by -radius along their normals.
void QifParser::EmitPoints(const std::vector<QifEmit>& plan, double mm_per_unit, PointSet* ps) {
  bool in_order = true, all_normals = true;
  std::size_t next = 0, total = 0;
  for (const QifEmit& e : plan) {
    const QifPointSet& s = *e.set;
    in_order = in_order && s.first + e.first - 1 == next && !MovedByReader(s) &&
               (s.n_normal == 0 || s.normal_first == s.first);
    next = s.first + e.last;
    total += e.last - e.first + 1;
    all_normals = all_normals && s.n_normal != 0;
  }
  ps->feature.reserve(total);
  for (const QifEmit& e : plan) ps->feature.insert(ps->feature.end(), e.last - e.first + 1, e.feature);
  if (in_order && next == xyz_.size() && (!all_normals || normal_.size() == xyz_.size())) {
    ps->xyz_mm = std::move(xyz_);
    if (mm_per_unit != 1.0)
      for (Eigen::Vector3d& p : ps->xyz_mm) p *= mm_per_unit;
    ps->line = std::move(xyz_line_);
    if (all_normals) ps->normal = std::move(normal_);
    return;
  }
  std::vector<double> compensation_mm;
  bool any_compensated = false;
  ps->xyz_mm.reserve(total);
  ps->line.reserve(total);
  if (all_normals) ps->normal.reserve(total);
  compensation_mm.reserve(total);
  for (const QifEmit& e : plan) {
    const QifPointSet& s = *e.set;
    const bool moved = MovedByReader(s);
    const double r = moved ? *s.probe_radius : 0.0;
    any_compensated = any_compensated || (moved && r != 0.0);
    for (std::size_t i = e.first - 1; i < e.last; ++i) {
      Eigen::Vector3d p = xyz_[s.first + i];
      if (moved) p -= r * normal_[s.normal_first + i];
      ps->xyz_mm.push_back(p * mm_per_unit);
      ps->line.push_back(xyz_line_[s.first + i]);
      compensation_mm.push_back(r * mm_per_unit);
      if (all_normals) ps->normal.push_back(normal_[s.normal_first + i]);
    }
  }
  if (any_compensated) {
    PointAttribute a;
    a.name = "probe_compensation_mm";
    a.values = std::move(compensation_mm);
    ps->attributes.push_back(std::move(a));
  }
}

Result<QifFile> QifParser::Assemble() {
  QifFile out;
  QifReport& rep = out.report;
  if (!have_unit_)
    return Error(1, "no <FileUnits><PrimaryUnits><LinearUnit>: expected the file's length unit (tpcal does not guess it)");
  if (factor_.has_value()) {
    if (!si_unit_name_.empty() && si_unit_name_ != "meter" && si_unit_name_ != "metre")
      return Error(unit_line_, fmt::format("<SIUnitName> '{}': expected meter for a linear unit", si_unit_name_));
    rep.mm_per_unit = *factor_ * 1000.0;
  } else {
    auto mm = KnownUnitMm(unit_name_);
    if (!mm)
      return Error(unit_line_, fmt::format("unknown length unit '{}' without <UnitConversion><Factor>: expected mm, cm, "
                                           "m, inch, ft or um, or a factor to metres", unit_name_));
    rep.mm_per_unit = *mm;
  }
  rep.unit_name = unit_name_;
  rep.point_sets = sets_.size();
  if (sets_.empty())
    return Error(1, "no <MeasuredPointSet>: expected measured points (a QIF results file with <MeasuredPointSets>)");

  std::vector<QifEmit> plan;
  PointSet& ps = out.file.points;
  ps.source = source_;
  std::map<std::string, std::size_t> covered;  // set id -> points emitted from it
  for (const QifMeasurement& m : measurements_) {
    if (m.refs.empty()) continue;  // a constructed or fitted-only feature: no points
    if (m.item_id.empty())
      return Error(m.line, "feature measurement without <FeatureItemId>: expected the feature item it measures");
    auto it = items_.find(m.item_id);
    if (it == items_.end())
      return Error(m.line, fmt::format("<FeatureItemId>{}</FeatureItemId> names no feature item: expected the id of a "
                                       "<...FeatureItem> in <FeatureItems>", m.item_id));
    if (!it->second.has_name)
      return Error(it->second.line, fmt::format("feature item id=\"{}\" has no <FeatureName>: expected the name tpcal "
                                                "labels its points with", m.item_id));
    const int feature = ps.InternFeature(it->second.name);
    for (const QifRef& ref : m.refs) {
      auto s = sets_.find(ref.set_id);
      if (s == sets_.end()) {
        if (options_.lenient_references) continue;
        return Error(ref.line, fmt::format("point list names MeasuredPointSet id=\"{}\", which the file does not hold: "
                                           "expected the id of a <MeasuredPointSet>", ref.set_id));
      }
      const std::size_t n = s->second.n;
      std::size_t first = 1, last = n;
      if (ref.kind != QifRef::Kind::kWhole) {
        first = ref.first;
        last = ref.last;
        if (last > n)
          return Error(ref.line, fmt::format("point {} of MeasuredPointSet id=\"{}\" asked for, it has {} points: "
                                             "expected indices 1..{}", last, ref.set_id, n, n));
      }
      s->second.referenced = true;
      covered[ref.set_id] += last - first + 1;
      plan.push_back({&s->second, first, last, feature});
    }
  }
  for (const std::string& id : set_order_) {
    QifPointSet& s = sets_[id];
    if (s.referenced) {
      if (covered[id] < s.n) rep.dropped_points += s.n - covered[id];
      continue;
    }
    if (!options_.lenient_references)
      return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" belongs to no feature: expected a feature "
                                       "measurement whose <PointList> names it", id));
    ++rep.unreferenced_sets;
    plan.push_back({&s, 1, s.n, PointSet::kUnlabelled});
  }
  EmitPoints(plan, rep.mm_per_unit, &ps);
  for (const auto& [id, s] : sets_) {
    if (s.compensated.has_value() && !*s.compensated) {
      if (MovedByReader(s)) ++rep.sets_compensated_by_reader;
      else ++rep.sets_read_as_centres;
    }
  }
  if (ps.xyz_mm.empty()) return Error(1, "no point belongs to a feature: expected feature measurements with <PointList>s");
  out.file.info.format = PointFormat::kQif;
  out.file.info.source_units = std::abs(rep.mm_per_unit - kMmPerInch) < 1e-9 ? LengthUnit::kInch : LengthUnit::kMm;
  return out;
}

}  // namespace

Result<QifFile> ParseQif(std::string_view text, const std::string& source_name, const QifReadOptions& qif_options) {
  QifParser parser(source_name, qif_options);
  return parser.Run(text);
}

Result<PointFile> ParsePointQif(std::string_view text, const std::string& source_name, const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  QifReadOptions qif;
  qif.threads = options.threads;
  auto q = ParseQif(text, source_name, qif);
  if (!q.ok()) return q.status();
  q->file.info.bytes = text.size();
  return std::move(q->file);
}

Result<PointFile> ReadPointQif(const std::string& path, const PointReadOptions& options) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParsePointQif(bytes->view(), path, options);
}

}  // namespace tpcal::pipeline
