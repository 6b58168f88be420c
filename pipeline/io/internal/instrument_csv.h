// Internal to tpcal::pipeline: the one header-and-row reader of the instruments' CSV files
// (`tpcal probepts v1`, `tpcal ballbar v1`, `tpcal ballpos v1`; docs/formats/probepts.md,
// ballbar.md, ballpos.md). Each format names its columns and its messages; the reader checks the
// version line, `# units: mm`, the header (unknown, repeated and required columns), splits every row
// into its fields and parses the number fields; the format's code fills its own rows.
//
//   # tpcal NAME v1
//   # units: mm
//   column,column,...      (any order; blanks around fields are trimmed)
//   field,field,...        (blank lines and lines starting with '#' are skipped)
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline::internal {

// Longest line of an instrument CSV file (ReadFileBytes' limit).
inline constexpr std::size_t kInstrumentCsvMaxLineBytes = std::size_t{1} << 16;

// The id of the rotary command columns A_deg, B_deg, C_deg (InstrumentCsvFormat::rotary).
inline constexpr int kInstrumentCsvRotary = -1;

// A column a format knows: its header name, the format's id for it (>= 0), whether the header must
// have it, and whether its field is text (handed over as it is) rather than a finite number.
struct InstrumentCsvColumn {
  const char* name;
  int id;
  bool required;
  bool text;
};

struct InstrumentCsvFormat {
  const char* first_line;  // "# tpcal probepts v1"
  std::vector<InstrumentCsvColumn> columns;
  bool rotary;  // A_deg, B_deg, C_deg are columns too (number, id kInstrumentCsvRotary), at least one required
  const char* expected_columns;  // the list an unknown column's message names: "(expected " + this + ")"
  const char* header_needs;      // the message of a header without a required column
  const char* no_rows;           // the message of a file without rows ("no probed points")
  // Quotes input bytes (a column name, a field) in messages, at most max_bytes of them.
  std::string (*echo)(std::string_view bytes, std::size_t max_bytes);
};

// A column of the file's header: the format's id (kInstrumentCsvRotary for A_deg, B_deg, C_deg)
// and the rotary axis ('A', 'B', 'C'; 0 for other columns).
struct InstrumentCsvHeaderColumn {
  int id = 0;
  char axis = 0;
};

struct InstrumentCsvHeader {
  std::vector<InstrumentCsvHeaderColumn> columns;  // in file order
  std::vector<char> rotary_axes;                   // the rotary columns, in header order
  bool plan = false;                               // a `# plan:` comment line was present
  bool Has(int id) const;
};

// What a format makes of each row. The reader calls `begin` with the row's 1-based line, then in
// column order `text` with a text column's field (its failure is reported as "field N: " + its
// message) or `number` with a number column's finite value, then `end` for checks of the whole row.
struct InstrumentCsvRows {
  std::function<void(std::size_t line)> begin;
  std::function<Status(const InstrumentCsvHeaderColumn& column, std::string_view field)> text;
  std::function<void(const InstrumentCsvHeaderColumn& column, double value)> number;
  std::function<Status()> end;
};

// Reads `text` as a file of `format`, handing every row to `rows`; returns the header. Errors
// (kParseError, source:line), the first in file order: a first line other than format.first_line,
// a `# units:` other than mm, an unknown or repeated column, a header without a required column (or
// without a rotary column when format.rotary), a row with another number of fields, a number field
// that is not a finite number ("field N: expected a finite number, got '...'"), the failures of
// `rows`, no rows (format.no_rows, at the last line).
Result<InstrumentCsvHeader> ReadInstrumentCsv(std::string_view text, const std::string& source,
                                              const InstrumentCsvFormat& format, const InstrumentCsvRows& rows);

// Shortest text that reads back to the same double (at most 17 significant digits; "nan" if
// it cannot be written).
std::string FormatCsvNumber(double v);

}  // namespace tpcal::pipeline::internal
