// The header of a point table (see point_table_header.h).
#include "pipeline/io/internal/point_table_header.h"

#include <fmt/format.h>

#include <array>
#include <unordered_map>

#include "core/ascii.h"
#include "core/input_echo.h"

namespace tpcal::pipeline::internal {
namespace {

constexpr int kNamedRoles = 7;  // feature, x, y, z, i, j, k
constexpr std::array<const char*, kNamedRoles> kRoleName = {"feature", "x", "y", "z", "i", "j", "k"};

// Names other software writes for the feature label, in order of preference, and for the
// normal; used only when the contract name is absent (a `feature` column wins over a `name`
// column, which then stays an attribute).
constexpr std::array<std::string_view, 6> kFeatureAliases = {"name", "label", "feature_name", "feature name",
                                                             "featurename", "element"};
constexpr std::array<std::string_view, 3> kNormalAliases = {"nx", "ny", "nz"};

int RoleIndex(std::string_view role) {
  for (int r = 0; r < kNamedRoles; ++r)
    if (role == kRoleName[r]) return r;
  return -1;
}

// Column of each named role (-1: absent): a mapped role its mapped column (-2 when the header has
// none), the others the contract name first, then its aliases, among the columns no mapping
// took. The normal's aliases count only as a whole triple and only without any of i,j,k, so
// `i,ny,nz` is not read as one normal (it fails as a normal lacking j,k).
std::array<int, kNamedRoles> FindRoles(const std::vector<std::string>& lower_names, const ColumnMap& columns) {
  std::array<int, kNamedRoles> column;
  column.fill(-1);
  std::vector<bool> mapped(lower_names.size(), false);
  auto find = [&](std::string_view name) {
    for (std::size_t c = 0; c < lower_names.size(); ++c)
      if (!mapped[c] && lower_names[c] == name) return static_cast<int>(c);
    return -1;
  };
  std::array<bool, kNamedRoles> by_map{};
  for (const auto& [role, name] : columns) {
    const int r = RoleIndex(role);
    if (r < 0) continue;  // PointReadOptions::Validate refuses it
    by_map[r] = true;
    column[r] = find(AsciiLower(name));
    if (column[r] >= 0) mapped[static_cast<std::size_t>(column[r])] = true;
    else column[r] = -2;
  }
  for (int r = 0; r < kNamedRoles; ++r)
    if (!by_map[r]) column[r] = find(kRoleName[r]);
  for (std::size_t a = 0; !by_map[0] && column[0] < 0 && a < kFeatureAliases.size(); ++a)
    column[0] = find(kFeatureAliases[a]);
  if (!by_map[4] && !by_map[5] && !by_map[6] && column[4] < 0 && column[5] < 0 && column[6] < 0) {
    std::array<int, 3> alias;
    for (int d = 0; d < 3; ++d) alias[d] = find(kNormalAliases[d]);
    if (alias[0] >= 0 && alias[1] >= 0 && alias[2] >= 0)
      for (int d = 0; d < 3; ++d) column[4 + d] = alias[d];
  }
  return column;
}

bool HasRequiredColumns(std::string_view line, char sep, const ColumnMap& columns) {
  std::vector<std::string_view> cells;
  if (!SplitTableCells(line, sep, &cells).empty()) return false;
  std::vector<std::string> lower;
  for (std::string_view c : cells) lower.push_back(AsciiLower(c));
  const std::array<int, kNamedRoles> column = FindRoles(lower, columns);
  return column[0] >= 0 && column[1] >= 0 && column[2] >= 0 && column[3] >= 0;
}

char DetectSeparator(std::string_view line, const ColumnMap& columns) {
  if (HasRequiredColumns(line, ',', columns)) return ',';
  for (char sep : {';', '\t'})
    if (line.find(sep) != std::string_view::npos && HasRequiredColumns(line, sep, columns)) return sep;
  return ',';
}

}  // namespace

bool IsTableRole(std::string_view role) { return RoleIndex(role) >= 0; }

Status ColumnMappingNeedsTable(const std::string& source) {
  return Status(StatusCode::kInvalidArgument,
                "a column mapping (--column, columns:) applies to CSV and TSV tables only: this file's columns are "
                "fixed by its format",
                source);
}

std::string_view TrimCell(std::string_view s, char sep) {
  std::size_t b = 0, e = s.size();
  while (b < e && IsCellBlank(s[b], sep)) ++b;
  while (e > b && IsCellBlank(s[e - 1], sep)) --e;
  return s.substr(b, e - b);
}

bool OnlyTableSeparators(std::string_view line, char sep) {
  for (char c : line)
    if (!IsCellBlank(c, sep) && c != sep) return false;
  return true;
}

std::string SplitTableCells(std::string_view line, char sep, std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (true) {
    while (i < n && IsCellBlank(line[i], sep)) ++i;
    if (i < n && line[i] == '"') {
      const std::size_t close = line.find('"', i + 1);
      if (close == std::string_view::npos)
        return fmt::format("cell {} has an opening quote but no closing quote", cells->size() + 1);
      cells->push_back(line.substr(i + 1, close - i - 1));
      std::size_t j = close + 1;
      while (j < n && IsCellBlank(line[j], sep)) ++j;
      if (j < n && line[j] == '"')
        return fmt::format("cell {} contains a doubled quote (\"\"), which this reader does not "
                           "support", cells->size());
      if (j < n && line[j] != sep)
        return fmt::format("cell {} has text after its closing quote", cells->size());
      if (j == n) return "";
      i = j + 1;
    } else {
      const std::size_t at = line.find(sep, i);
      const std::size_t e = at == std::string_view::npos ? n : at;
      cells->push_back(TrimCell(line.substr(i, e - i), sep));
      if (at == std::string_view::npos) return "";
      i = at + 1;
    }
  }
}

Result<Layout> ParseTableHeader(std::string_view line, const std::string& source, std::size_t line_no,
                                const ColumnMap& columns) {
  auto error = [&](std::string msg) {
    return Status(StatusCode::kParseError, std::move(msg), source, line_no);
  };
  Layout layout;
  layout.sep = DetectSeparator(line, columns);
  std::vector<std::string_view> cells;
  if (std::string e = SplitTableCells(line, layout.sep, &cells); !e.empty()) return error("header: " + e);
  if (cells.size() > kMaxTableColumns)
    return error(fmt::format("header has {} columns; expected at most {}", cells.size(), kMaxTableColumns));
  std::vector<std::string> lower;
  std::unordered_map<std::string, std::size_t> seen;  // lower-case name -> column
  for (std::size_t c = 0; c < cells.size(); ++c) {
    lower.push_back(AsciiLower(cells[c]));
    if (cells[c].empty()) {
      if (c + 1 == cells.size() && c > 0) continue;  // a trailing separator
      return error(fmt::format("header column {} has no name (expected names such as "
                               "feature,x,y,z)", c + 1));
    }
    if (auto [it, inserted] = seen.emplace(lower.back(), c); !inserted)
      return error(fmt::format("duplicate header column '{}' (columns {} and {})", EchoInput(cells[c]),
                               it->second + 1, c + 1));
  }
  std::array<int, kNamedRoles> column = FindRoles(lower, columns);
  for (const auto& [role, name] : columns) {
    if (const int r = RoleIndex(role); r >= 0 && column[r] == -2)
      return error(fmt::format("header has no column '{}' (the column mapping's {}={}); got '{}'", EchoInput(name),
                               role, EchoInput(name), EchoInput(TrimCell(line, ','))));
  }
  for (int r = 0; r < 4; ++r) {
    if (column[r] < 0)
      return error(fmt::format("header lacks the required column '{}' (expected feature,x,y,z "
                               "in any order, optionally i,j,k, separated by ',' ';' or tabs; got '{}')",
                               kRoleName[r], EchoInput(TrimCell(line, ','))));
  }
  const int n_normal = (column[4] >= 0) + (column[5] >= 0) + (column[6] >= 0);
  if (n_normal != 0 && n_normal != 3) {
    std::string have, lack;
    for (int r = 4; r < kNamedRoles; ++r) {
      std::string& dst = column[r] >= 0 ? have : lack;
      if (!dst.empty()) dst += ",";
      dst += kRoleName[r];
    }
    return error(fmt::format("header has normal column(s) {} but not {} (normals need all of "
                             "i,j,k)", have, lack));
  }
  layout.has_normals = n_normal == 3;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    layout.names.emplace_back(cells[c]);
    layout.attr_of_column.push_back(-1);
    Role role = cells[c].empty() ? Role::kIgnore : Role::kAttribute;
    for (int r = 0; r < kNamedRoles; ++r)
      if (column[r] == static_cast<int>(c)) role = static_cast<Role>(r);
    if (role == Role::kAttribute) {
      layout.attr_of_column.back() = static_cast<int>(layout.attr_names.size());
      layout.attr_names.emplace_back(cells[c]);
      layout.attr_column.push_back(c);
    }
    layout.roles.push_back(role);
  }
  const std::string sep = layout.sep == '\t' ? "<tab>" : std::string(1, layout.sep);
  std::string expected;
  for (int r = 0; r < (layout.has_normals ? kNamedRoles : 4); ++r) {  // an alias as written
    const std::size_t c = static_cast<std::size_t>(column[r]);
    expected += (r ? sep : "") + (lower[c] == kRoleName[r] ? std::string(kRoleName[r]) : std::string(cells[c]));
  }
  for (const auto& a : layout.attr_names) expected += sep + a;
  layout.expected = EchoInput(expected, 2 * kMaxEchoBytes);
  return layout;
}

}  // namespace tpcal::pipeline::internal
