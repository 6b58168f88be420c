// Internal to tpcal::pipeline: the header of a point table (docs/formats/points.md, "Tables from
// other software"): which separator the file uses (',' ; or tab), which column holds the feature
// label, x, y, z and the normal (the contract names, or the aliases other software writes, such as
// `name` for `feature`), and which columns are kept as attributes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/status.h"

namespace tpcal::pipeline::internal {

// Hostile sizes fail at the header before memory grows with them (docs/formats/points.md).
inline constexpr std::size_t kMaxTableColumns = 1024;

enum class Role : std::uint8_t { kFeature, kX, kY, kZ, kI, kJ, kK, kAttribute, kIgnore };

struct Layout {
  char sep = ',';                        // cell separator: ',' ';' or '\t'
  std::vector<Role> roles;               // per column
  std::vector<int> attr_of_column;       // attribute index per column, -1 if none
  std::vector<std::string> names;        // per column, as written
  std::vector<std::string> attr_names;   // per attribute
  std::vector<std::size_t> attr_column;  // column of each attribute
  bool has_normals = false;
  std::string expected;  // e.g. "feature,x,y,z,i,j,k" or "x y z", for messages

  // Outside a ','-separated table a number may use a decimal comma ("12,5").
  bool decimal_comma() const { return sep != ','; }
};

// Blank characters around a cell: spaces, and tabs unless the tab separates cells.
inline bool IsCellBlank(char c, char sep) { return c == ' ' || (c == '\t' && sep != '\t'); }

std::string_view TrimCell(std::string_view s, char sep);

// A line holding only blanks and separators (spreadsheets export empty rows as ",,,,").
bool OnlyTableSeparators(std::string_view line, char sep);

// A role name of a column mapping: feature, x, y, z, i, j or k.
bool IsTableRole(std::string_view role);

// A column mapping (PointReadOptions::columns): role -> the header's name for it.
using ColumnMap = std::vector<std::pair<std::string, std::string>>;

// kInvalidArgument naming `source`: a column mapping was given for a file that is not a table.
Status ColumnMappingNeedsTable(const std::string& source);

// Splits a table line into trimmed, unquoted cells. Returns an error message or "".
std::string SplitTableCells(std::string_view line, char sep, std::vector<std::string_view>* cells);

// The header line `line` (line `line_no` of `source`): the separator is ',' unless ',' leaves a
// required column out and ';' or a tab gives them all. A mapped role takes the column `columns`
// names for it (an error if the header has no such column). Errors name the file and line.
Result<Layout> ParseTableHeader(std::string_view line, const std::string& source, std::size_t line_no,
                                const ColumnMap& columns = {});

}  // namespace tpcal::pipeline::internal
