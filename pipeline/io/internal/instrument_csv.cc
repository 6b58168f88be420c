#include "pipeline/io/internal/instrument_csv.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "core/input_echo.h"

namespace tpcal::pipeline::internal {
namespace {

// File-local names carry an InstrumentCsv prefix: a unity build merges this file with the other
// readers of pipeline/io.

std::string_view InstrumentCsvTrim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> InstrumentCsvSplit(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i < line.size() && line[i] != ',') continue;
    out.push_back(InstrumentCsvTrim(line.substr(start, i - start)));
    start = i + 1;
  }
  return out;
}

std::optional<double> InstrumentCsvNumber(std::string_view s) {
  double v = 0.0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

Result<InstrumentCsvHeader> InstrumentCsvParseHeader(std::string_view line, const std::string& source,
                                                     std::size_t line_no, const InstrumentCsvFormat& format) {
  InstrumentCsvHeader header;
  std::vector<std::string_view> seen;
  for (std::string_view name : InstrumentCsvSplit(line)) {
    for (std::string_view s : seen)
      if (s == name)
        return Status(StatusCode::kParseError, "column '" + format.echo(name, kMaxEchoBytes) + "' repeated", source,
                      line_no);
    seen.push_back(name);
    if (format.rotary && (name == "A_deg" || name == "B_deg" || name == "C_deg")) {
      header.columns.push_back({kInstrumentCsvRotary, name[0]});
      header.rotary_axes.push_back(name[0]);
      continue;
    }
    const InstrumentCsvColumn* known = nullptr;
    for (const InstrumentCsvColumn& c : format.columns)
      if (name == c.name) known = &c;
    if (!known)
      return Status(StatusCode::kParseError,
                    "unknown column '" + format.echo(name, 40) + "' (expected " + format.expected_columns + ")", source,
                    line_no);
    header.columns.push_back({known->id, 0});
  }
  // No column is repeated, so all required ones are present when as many are.
  std::size_t required = 0, present = 0;
  for (const InstrumentCsvColumn& c : format.columns)
    if (c.required) ++required, present += header.Has(c.id);
  if (present != required || (format.rotary && header.rotary_axes.empty()))
    return Status(StatusCode::kParseError, format.header_needs, source, line_no);
  return header;
}

const InstrumentCsvColumn& InstrumentCsvColumnOf(const InstrumentCsvFormat& format, int id) {
  for (const InstrumentCsvColumn& c : format.columns)
    if (c.id == id) return c;
  return format.columns.front();  // not reached: the header holds the format's ids only
}

Status InstrumentCsvParseRow(std::string_view line, const InstrumentCsvHeader& header, const std::string& source,
                             std::size_t line_no, const InstrumentCsvFormat& format, const InstrumentCsvRows& rows) {
  const auto fields = InstrumentCsvSplit(line);
  const std::vector<InstrumentCsvHeaderColumn>& cols = header.columns;
  if (fields.size() != cols.size())
    return Status(StatusCode::kParseError,
                  "expected " + std::to_string(cols.size()) + " fields, got " + std::to_string(fields.size()), source,
                  line_no);
  rows.begin(line_no);
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const std::string field_no = "field " + std::to_string(k + 1);
    if (cols[k].id != kInstrumentCsvRotary && InstrumentCsvColumnOf(format, cols[k].id).text) {
      if (Status s = rows.text(cols[k], fields[k]); !s.ok())
        return Status(s.code(), field_no + ": " + s.message(), source, line_no);
      continue;
    }
    const std::optional<double> v = InstrumentCsvNumber(fields[k]);
    if (!v)
      return Status(StatusCode::kParseError,
                    field_no + ": expected a finite number, got '" + format.echo(fields[k], 40) + "'", source, line_no);
    rows.number(cols[k], *v);
  }
  if (Status s = rows.end(); !s.ok()) return Status(s.code(), s.message(), source, line_no);
  return Status::Ok();
}

}  // namespace

bool InstrumentCsvHeader::Has(int id) const {
  for (const InstrumentCsvHeaderColumn& c : columns)
    if (c.id == id) return true;
  return false;
}

Result<InstrumentCsvHeader> ReadInstrumentCsv(std::string_view text, const std::string& source,
                                              const InstrumentCsvFormat& format, const InstrumentCsvRows& rows) {
  std::optional<InstrumentCsvHeader> header;
  bool plan = false;
  std::size_t line_no = 0, row_count = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = InstrumentCsvTrim(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++line_no;
    if (line_no == 1) {
      if (line != format.first_line)
        return Status(StatusCode::kParseError, std::string("expected '") + format.first_line + "' on the first line",
                      source, 1);
      continue;
    }
    if (line.empty()) continue;
    if (line.front() == '#') {
      const std::string_view body = InstrumentCsvTrim(line.substr(1));
      if (body.rfind("units:", 0) == 0 && InstrumentCsvTrim(body.substr(6)) != "mm")
        return Status(StatusCode::kParseError, "units: only mm is supported", source, line_no);
      if (body.rfind("plan:", 0) == 0) plan = true;
      continue;
    }
    if (!header) {
      auto h = InstrumentCsvParseHeader(line, source, line_no, format);
      if (!h.ok()) return h.status();
      header = std::move(*h);
      continue;
    }
    if (Status s = InstrumentCsvParseRow(line, *header, source, line_no, format, rows); !s.ok()) return s;
    ++row_count;
  }
  if (line_no == 0)
    return Status(StatusCode::kParseError, std::string("empty file: expected '") + format.first_line + "'", source, 1);
  if (row_count == 0) return Status(StatusCode::kParseError, format.no_rows, source, line_no);
  header->plan = plan;
  return std::move(*header);
}

std::string FormatCsvNumber(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

}  // namespace tpcal::pipeline::internal
