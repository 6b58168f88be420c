// QIF 3.0 results reader on libxml2's xmlTextReader (see qif_reader.h for the rules).
#include "pipeline/io/qif_reader.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>
#include <libxml/xmlerror.h>
#include <libxml/xmlreader.h>
#include <libxml/xmlversion.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include "core/ascii.h"
#include "core/units.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

struct QifPointSet {
  std::size_t line = 0;
  std::size_t count_attr = 0;  // 0: no count attribute
  std::vector<Eigen::Vector3d> xyz;     // file units
  std::vector<std::size_t> xyz_line;
  std::vector<Eigen::Vector3d> normal;  // unit
  std::optional<bool> compensated;
  std::optional<double> probe_radius;   // file units
  bool referenced = false;
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

std::string QifEcho(std::string_view s) {
  s = TrimXml(s);
  if (s.size() <= 40) return fmt::format("'{}'", s);
  return fmt::format("'{}...'", s.substr(0, 37));
}

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

  Status OnStart(xmlTextReaderPtr r, std::string_view name, std::size_t line);
  Status OnEnd(std::string_view name, std::size_t line);
  Status OnNumbers(std::string_view text);
  Status Take(double v, std::size_t line);  // one number of the current <Points>/<Normals>
  Status FinishSet();
  Result<QifFile> Assemble();

  std::string source_;
  QifReadOptions options_;
  std::size_t text_bytes_ = 0;  // size of the document, bounds reservations
  std::vector<std::string_view> stack_;  // local names (libxml2 dictionary, live with the reader)
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
  std::string cur_set_id_;
  QifPointSet* cur_set_ = nullptr;
  // <Points> / <Normals> text being parsed
  enum class Block { kNone, kPoints, kNormals } block_ = Block::kNone;
  std::size_t block_line_ = 0;  // current line inside the block
  std::size_t triple_line_ = 0;
  double triple_[3] = {0, 0, 0};
  int in_triple_ = 0;
};

std::string Attr(xmlTextReaderPtr r, const char* name) {
  xmlChar* v = xmlTextReaderGetAttribute(r, reinterpret_cast<const xmlChar*>(name));
  if (v == nullptr) return {};
  std::string out(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return out;
}

Status QifParser::OnStart(xmlTextReaderPtr r, std::string_view name, std::size_t line) {
  text_.clear();
  const std::string_view parent = stack_.empty() ? std::string_view{} : stack_.back();
  if (name == "LinearUnit" && parent == "PrimaryUnits" && Under("FileUnits")) {
    in_primary_linear_ = true;
    unit_line_ = line;
  } else if (EndsWith(name, "FeatureItem") && parent == "FeatureItems") {
    cur_item_ = Attr(r, "id");
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
      const std::string range = Attr(r, "range");
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
      const std::string index = Attr(r, "index");
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
    cur_set_id_ = Attr(r, "id");
    if (cur_set_id_.empty()) return Error(line, "<MeasuredPointSet> without an id attribute: expected id=\"N\"");
    if (sets_.count(cur_set_id_) != 0)
      return Error(line, fmt::format("<MeasuredPointSet id=\"{}\"> appears twice: expected unique ids", cur_set_id_));
    cur_set_ = &sets_[cur_set_id_];
    set_order_.push_back(cur_set_id_);
    cur_set_->line = line;
    const std::string count = Attr(r, "count");
    if (!count.empty()) {
      auto c = QifIndex(count);
      if (!c) return Error(line, fmt::format("<MeasuredPointSet count=\"{}\">: expected a point count", count));
      cur_set_->count_attr = *c;
      const std::size_t reserve = std::min<std::size_t>(*c, text_bytes_ / 6 + 1);  // a triple takes >= 6 bytes
      cur_set_->xyz.reserve(reserve);
      cur_set_->xyz_line.reserve(reserve);
    }
  } else if (cur_set_ != nullptr && parent == "MeasuredPointSet") {
    if (name == "Points" || name == "Normals") {
      block_ = name == "Points" ? Block::kPoints : Block::kNormals;
      block_line_ = line;
      in_triple_ = 0;
      if (block_ == Block::kNormals && !cur_set_->normal.empty())
        return Error(line, "a second <Normals>: expected one per MeasuredPointSet");
      if (block_ == Block::kNormals) cur_set_->normal.reserve(cur_set_->xyz.size());
    } else if (name == "PointsBinary" || name == "NormalsBinary") {
      return Error(line, fmt::format("<{}> (base64 binary points) is not supported: expected <Points> text "
                                     "(x y z triples)", name));
    }
  }
  return Status::Ok();
}

// Numbers of a <Points>/<Normals> text node, counting lines as it goes.
// Numbers of one piece of <Points>/<Normals> text: values, the newlines before each (within
// the piece), the piece's newlines, and the first token that is not a finite number.
struct NumberScan {
  std::vector<double> values;
  std::vector<std::uint32_t> line_of;
  std::size_t newlines = 0;
  bool bad = false;
  std::string_view bad_token;
  std::size_t bad_line = 0;
};

inline bool QifBlank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

void ScanNumbers(std::string_view text, NumberScan* out) {
  const char* p = text.data();
  const char* end = p + text.size();
  out->values.reserve(text.size() / 8 + 1);
  out->line_of.reserve(text.size() / 8 + 1);
  while (true) {
    while (p < end && QifBlank(*p)) {
      if (*p == '\n') ++out->newlines;
      ++p;
    }
    if (p >= end) return;
    const char* b = p;
    while (p < end && !QifBlank(*p)) ++p;
    const char* nb = (*b == '+' && p - b > 1) ? b + 1 : b;
    double v = 0;
    auto res = fast_float::from_chars(nb, p, v);
    if (res.ec != std::errc() || res.ptr != p || !std::isfinite(v)) {
      out->bad = true;
      out->bad_token = std::string_view(b, static_cast<std::size_t>(p - b));
      out->bad_line = out->newlines;
      return;
    }
    out->values.push_back(v);
    out->line_of.push_back(static_cast<std::uint32_t>(out->newlines));
  }
}

Status QifParser::Take(double v, std::size_t line) {
  if (in_triple_ == 0) triple_line_ = line;
  triple_[in_triple_++] = v;
  if (in_triple_ < 3) return Status::Ok();
  in_triple_ = 0;
  const Eigen::Vector3d t(triple_[0], triple_[1], triple_[2]);
  if (block_ == Block::kPoints) {
    cur_set_->xyz.push_back(t);
    cur_set_->xyz_line.push_back(triple_line_);
    return Status::Ok();
  }
  const double len = t.norm();
  if (!(len > 1e-12) || std::abs(len - 1.0) > 1e-3)
    return Error(triple_line_, fmt::format("normal ({} {} {}) of MeasuredPointSet id=\"{}\" has length {:.6g}: "
                                           "expected a unit vector", t.x(), t.y(), t.z(), cur_set_id_, len));
  cur_set_->normal.push_back(std::abs(len - 1.0) > 1e-14 ? Eigen::Vector3d(t / len) : t);  // as the CSV reader
  return Status::Ok();
}

// Large texts (a scan's <Points>) are scanned in parallel pieces split at blanks, then taken in
// file order, so values, lines and the first error are those of a serial scan.
Status QifParser::OnNumbers(std::string_view text) {
  constexpr std::size_t kParallelBytes = std::size_t{1} << 22;
  std::size_t pieces = 1;
  if (text.size() >= kParallelBytes) {
    const std::size_t hw = options_.threads > 0 ? static_cast<std::size_t>(options_.threads)
                                                : std::max(1u, std::thread::hardware_concurrency());
    pieces = std::min(hw, text.size() / (kParallelBytes / 4));
  }
  if (pieces == 1) {  // serial: straight into the point set
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
      const char* nb = (*tb == '+' && p - tb > 1) ? tb + 1 : tb;
      double v = 0;
      auto res = fast_float::from_chars(nb, p, v);
      if (res.ec != std::errc() || res.ptr != p || !std::isfinite(v))
        return Error(block_line_, fmt::format("{} in <{}> of MeasuredPointSet id=\"{}\": expected numbers, three per point",
                                              QifEcho(std::string_view(tb, static_cast<std::size_t>(p - tb))),
                                              block_ == Block::kPoints ? "Points" : "Normals", cur_set_id_));
      TPCAL_RETURN_IF_ERROR(Take(v, block_line_));
    }
  }
  std::vector<std::string_view> parts;
  std::size_t b = 0;
  for (std::size_t k = 1; k <= pieces; ++k) {
    std::size_t e = k == pieces ? text.size() : std::max(b, text.size() * k / pieces);
    while (e < text.size() && !QifBlank(text[e])) ++e;
    parts.push_back(text.substr(b, e - b));
    b = e;
  }
  std::vector<NumberScan> scans(parts.size());
  {
    std::vector<std::thread> workers;
    for (std::size_t k = 1; k < parts.size(); ++k) workers.emplace_back(ScanNumbers, parts[k], &scans[k]);
    ScanNumbers(parts[0], &scans[0]);
    for (std::thread& w : workers) w.join();
  }
  for (const NumberScan& sc : scans) {
    for (std::size_t j = 0; j < sc.values.size(); ++j) TPCAL_RETURN_IF_ERROR(Take(sc.values[j], block_line_ + sc.line_of[j]));
    if (sc.bad)
      return Error(block_line_ + sc.bad_line,
                   fmt::format("{} in <{}> of MeasuredPointSet id=\"{}\": expected numbers, three per point",
                               QifEcho(sc.bad_token), block_ == Block::kPoints ? "Points" : "Normals", cur_set_id_));
    block_line_ += sc.newlines;
  }
  return Status::Ok();
}

Status QifParser::FinishSet() {
  QifPointSet& s = *cur_set_;
  if (s.xyz.empty()) return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" has no <Points>: expected x y z triples", cur_set_id_));
  if (s.count_attr != 0 && s.count_attr != s.xyz.size())
    return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" says count=\"{}\" but holds {} points: expected "
                                     "them to agree", cur_set_id_, s.count_attr, s.xyz.size()));
  if (!s.normal.empty() && s.normal.size() != s.xyz.size())
    return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" has {} points and {} normals: expected one normal "
                                     "per point", cur_set_id_, s.xyz.size(), s.normal.size()));
  if (s.compensated.has_value() && !*s.compensated) {
    if (!s.probe_radius.has_value() && !options_.accept_uncompensated)
      return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" is not probe-compensated (<Compensated>false) and "
                                       "gives no <ProbeRadius>: expected compensated points or the probe radius",
                                       cur_set_id_));
    if (s.normal.empty() && !options_.accept_uncompensated)
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

Result<QifFile> QifParser::Run(std::string_view text) {
  if (text.size() > static_cast<std::size_t>(INT_MAX))
    return Error(0, "file larger than 2 GiB: expected a smaller QIF file (libxml2 limit)");
  // No DTD: QIF uses XML Schema, and XML_PARSE_HUGE (needed for a scan's <Points>) lifts
  // libxml2's entity-expansion limits, so a document type declaration is refused up front.
  if (auto doctype = DoctypeLine(text); doctype != 0)
    return Error(doctype, "<!DOCTYPE ...>: expected no document type declaration (QIF 3.0 uses XML Schema)");
  text_bytes_ = text.size();
  xmlTextReaderPtr r = xmlReaderForMemory(text.data(), static_cast<int>(text.size()), source_.c_str(), nullptr,
                                          XML_PARSE_NONET | XML_PARSE_HUGE | XML_PARSE_BIG_LINES);
  if (r == nullptr) return Error(1, "cannot start the XML reader: expected an XML document");
  struct Closer {
    xmlTextReaderPtr r;
    ~Closer() { xmlFreeTextReader(r); }
  } closer{r};
#if LIBXML_VERSION >= 21200
  xmlTextReaderSetStructuredErrorHandler(r, &QifParser::OnXmlError, this);
#else
  xmlTextReaderSetStructuredErrorHandler(
      r, [](void* self, xmlErrorPtr e) { QifParser::OnXmlError(self, e); }, this);
#endif
  bool saw_root = false;
  int ret = 0;
  while ((ret = xmlTextReaderRead(r)) == 1) {
    const int type = xmlTextReaderNodeType(r);
    if (type == XML_READER_TYPE_ELEMENT) {
      const char* n = reinterpret_cast<const char*>(xmlTextReaderConstLocalName(r));
      const std::string_view name = n != nullptr ? std::string_view(n) : std::string_view{};
      const std::size_t line = static_cast<std::size_t>(std::max(1L, xmlGetLineNo(xmlTextReaderCurrentNode(r))));
      if (!saw_root) {
        saw_root = true;
        if (name != "QIFDocument")
          return Error(line, fmt::format("root element <{}>: expected <QIFDocument> (QIF 3.0)", name));
      }
      if (block_ != Block::kNone)
        return Error(line, fmt::format("<{}> inside <Points>/<Normals>: expected only numbers", name));
      const bool empty = xmlTextReaderIsEmptyElement(r) == 1;
      TPCAL_RETURN_IF_ERROR(OnStart(r, name, line));  // sees its parent on top of the stack
      stack_.push_back(name);
      if (empty) {
        TPCAL_RETURN_IF_ERROR(OnEnd(name, line));
        stack_.pop_back();
      }
    } else if (type == XML_READER_TYPE_END_ELEMENT) {
      if (stack_.empty()) break;  // libxml2 reports the error
      const std::size_t line = static_cast<std::size_t>(std::max(1, xmlTextReaderGetParserLineNumber(r)));
      TPCAL_RETURN_IF_ERROR(OnEnd(stack_.back(), line));
      stack_.pop_back();
    } else if (type == XML_READER_TYPE_TEXT || type == XML_READER_TYPE_CDATA ||
               type == XML_READER_TYPE_WHITESPACE || type == XML_READER_TYPE_SIGNIFICANT_WHITESPACE ||
               type == XML_READER_TYPE_COMMENT) {
      const char* v = reinterpret_cast<const char*>(xmlTextReaderConstValue(r));
      const std::string_view value = v != nullptr ? std::string_view(v) : std::string_view{};
      if (block_ != Block::kNone) {
        if (type == XML_READER_TYPE_COMMENT) {
          for (char c : value) block_line_ += c == '\n' ? 1 : 0;
        } else {
          TPCAL_RETURN_IF_ERROR(OnNumbers(value));
        }
      } else if (type != XML_READER_TYPE_COMMENT && text_.size() < 4096) {
        text_.append(value);
      }
    }
  }
  if (ret < 0 || xml_error_line_ != 0) {
    const std::size_t line = xml_error_line_ != 0 ? xml_error_line_
                                                  : static_cast<std::size_t>(std::max(1, xmlTextReaderGetParserLineNumber(r)));
    return Error(line, fmt::format("malformed XML ({}): expected a well-formed QIF document",
                                   xml_error_.empty() ? "parse error" : xml_error_));
  }
  if (!saw_root) return Error(1, "no XML element: expected a QIF 3.0 document (<QIFDocument>)");
  return Assemble();
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

  PointSet& ps = out.file.points;
  ps.source = source_;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> compensation_mm;
  bool all_normals = true, any_compensated = false;
  const double scale = rep.mm_per_unit;
  std::size_t total = 0;
  for (const auto& [id, s] : sets_) total += s.xyz.size();
  ps.xyz_mm.reserve(total);
  ps.feature.reserve(total);
  ps.line.reserve(total);
  normals.reserve(total);
  compensation_mm.reserve(total);
  auto emit = [&](QifPointSet& s, std::size_t first, std::size_t last, int feature) {
    const bool moved = s.compensated.has_value() && !*s.compensated && s.probe_radius.has_value() && !s.normal.empty();
    const double r = moved ? *s.probe_radius : 0.0;
    any_compensated = any_compensated || (moved && r != 0.0);
    for (std::size_t k = first; k <= last; ++k) {
      const std::size_t i = k - 1;
      Eigen::Vector3d p = s.xyz[i];
      if (moved) p -= r * s.normal[i];
      ps.xyz_mm.push_back(p * scale);
      ps.feature.push_back(feature);
      ps.line.push_back(s.xyz_line[i]);
      compensation_mm.push_back(r * scale);
      if (s.normal.empty()) all_normals = false;
      else normals.push_back(s.normal[i]);
    }
  };

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
      const std::size_t n = s->second.xyz.size();
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
      emit(s->second, first, last, feature);
    }
  }
  for (const std::string& id : set_order_) {
    QifPointSet& s = sets_[id];
    if (s.referenced) {
      if (covered[id] < s.xyz.size()) rep.dropped_points += s.xyz.size() - covered[id];
      continue;
    }
    if (!options_.lenient_references)
      return Error(s.line, fmt::format("MeasuredPointSet id=\"{}\" belongs to no feature: expected a feature "
                                       "measurement whose <PointList> names it", id));
    ++rep.unreferenced_sets;
    emit(s, 1, s.xyz.size(), PointSet::kUnlabelled);
  }
  for (const auto& [id, s] : sets_) {
    if (s.compensated.has_value() && !*s.compensated) {
      if (s.probe_radius.has_value() && !s.normal.empty()) ++rep.sets_compensated_by_reader;
      else ++rep.sets_read_as_centres;
    }
  }
  if (ps.xyz_mm.empty()) return Error(1, "no point belongs to a feature: expected feature measurements with <PointList>s");
  if (all_normals) ps.normal = std::move(normals);
  if (any_compensated) {
    PointAttribute a;
    a.name = "probe_compensation_mm";
    a.values = std::move(compensation_mm);
    ps.attributes.push_back(std::move(a));
  }
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
