// Small yaml-cpp helpers for the kinematics YAML readers (included by .cc files only; yaml-cpp
// stays out of the public headers). Every failure is a kParseError with the file and the 1-based
// line of the offending node.
#pragma once

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include "core/input_echo.h"
#include "core/status.h"
#include "core/text_file.h"

namespace tpcal::kinematics::yaml_internal {

inline std::size_t Line(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.line >= 0 ? static_cast<std::size_t>(m.line) + 1 : 0;
}

inline Status Error(const std::string& source, const YAML::Node& n, const std::string& message) {
  return Status(StatusCode::kParseError, message, source, Line(n));
}

// Keys and text values reach messages (and names reach reports): printable UTF-8, bounded.
inline constexpr std::size_t kMaxKeyBytes = 128;
inline constexpr std::size_t kMaxTextBytes = 256;
// A text value may hold tabs; a key (a name) may not.
inline bool Printable(const std::string& s, std::size_t max_bytes, bool allow_tab = true) {
  if (s.size() > max_bytes || FirstInvalidUtf8(s) != std::string::npos) return false;
  for (char c : s)
    if ((static_cast<unsigned char>(c) < 0x20 && !(allow_tab && c == '\t')) || c == 0x7F) return false;
  return true;
}

// Keys of a map in document order, with their key nodes (for line numbers).
struct MapEntry {
  std::string key;
  YAML::Node key_node;
  YAML::Node value;
};
inline Result<std::vector<MapEntry>> Entries(const std::string& source, const YAML::Node& map,
                                             const std::string& what) {
  if (!map.IsMap()) return Error(source, map, what + ": expected a map");
  std::vector<MapEntry> out;
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (!it->first.IsScalar()) return Error(source, it->first, what + ": keys must be plain names");
    const std::string key = it->first.Scalar();
    if (!Printable(key, kMaxKeyBytes, /*allow_tab=*/false))
      return Error(source, it->first, what + ": key '" + EchoInput(key) + "': expected a printable name of at most " +
                                          std::to_string(kMaxKeyBytes) + " bytes");
    if (!seen.insert(key).second) {
      return Error(source, it->first, what + ": duplicate key '" + EchoInput(key) + "'");
    }
    out.push_back(MapEntry{key, it->first, it->second});
  }
  return out;
}

// Fails on the first key not in `allowed`.
inline Status CheckKeys(const std::string& source, const std::vector<MapEntry>& entries,
                        const std::set<std::string>& allowed, const std::string& what) {
  for (const MapEntry& e : entries) {
    if (!allowed.count(e.key)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      return Error(source, e.key_node, "unknown key '" + EchoInput(e.key) + "' in " + what + " (expected: " + list + ")");
    }
  }
  return Status::Ok();
}

inline const MapEntry* Find(const std::vector<MapEntry>& entries, const std::string& key) {
  for (const MapEntry& e : entries) {
    if (e.key == key) return &e;
  }
  return nullptr;
}

inline Result<double> Double(const std::string& source, const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar()) return Error(source, n, what + ": expected a number");
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    return Error(source, n, what + ": expected a number, got '" + EchoInput(n.Scalar()) + "'");
  }
  if (!std::isfinite(v)) return Error(source, n, what + ": expected a finite number");
  return v;
}

inline Result<int> Int(const std::string& source, const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar()) return Error(source, n, what + ": expected an integer");
  try {
    return n.as<int>();
  } catch (const YAML::Exception&) {
    return Error(source, n, what + ": expected an integer, got '" + EchoInput(n.Scalar()) + "'");
  }
}

inline Result<bool> Bool(const std::string& source, const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar()) return Error(source, n, what + ": expected true or false");
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    return Error(source, n, what + ": expected true or false, got '" + EchoInput(n.Scalar()) + "'");
  }
}

inline Result<std::string> String(const std::string& source, const YAML::Node& n,
                                  const std::string& what) {
  if (!n.IsScalar()) return Error(source, n, what + ": expected a text value");
  if (!Printable(n.Scalar(), kMaxTextBytes))
    return Error(source, n, what + ": '" + EchoInput(n.Scalar()) + "': expected printable text of at most " +
                                std::to_string(kMaxTextBytes) + " bytes");
  return n.Scalar();
}

inline Result<std::vector<double>> Doubles(const std::string& source, const YAML::Node& n,
                                           const std::string& what) {
  if (!n.IsSequence()) return Error(source, n, what + ": expected a list of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    Result<double> v = Double(source, n[i], what + "[" + std::to_string(i) + "]");
    TPCAL_RETURN_IF_ERROR(v);
    out.push_back(*v);
  }
  return out;
}

inline Result<Eigen::Vector3d> Vector3(const std::string& source, const YAML::Node& n,
                                       const std::string& what) {
  Result<std::vector<double>> v = Doubles(source, n, what);
  TPCAL_RETURN_IF_ERROR(v);
  if (v->size() != 3) return Error(source, n, what + ": expected [x, y, z]");
  return Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]);
}

// The vector under `key` of a map ([x, y, z], mm); a missing key is an error at `where`.
inline Result<Eigen::Vector3d> Vector3At(const std::string& source, const std::vector<MapEntry>& entries,
                                         const YAML::Node& where, const std::string& key, const std::string& what) {
  const MapEntry* e = Find(entries, key);
  if (!e) return Error(source, where, what + ": missing '" + key + "' ([x, y, z], mm)");
  return Vector3(source, e->value, what + "." + key);
}

// A name (at `what`.name) that is also a field of an instrument's CSV file, which splits at
// commas, trims blanks and skips lines starting with '#' (pipeline/io/internal/instrument_csv.h):
// printable text (String), not empty, no comma, no leading '#', no leading or trailing blank.
// `csv_file` names the file in the message ("the probed-point file").
inline Result<std::string> CsvName(const std::string& source, const YAML::Node& n, const std::string& what,
                                   const std::string& csv_file) {
  Result<std::string> s = String(source, n, what + ".name");
  TPCAL_RETURN_IF_ERROR(s);
  if (s->empty()) return Error(source, n, what + ".name: expected a non-empty name");
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  if (s->find(',') != std::string::npos || s->front() == '#' || blank(s->front()) || blank(s->back()))
    return Error(source, n,
                 what + ".name '" + EchoInput(*s) +
                     "': expected no comma, no leading '#' and no leading or trailing blank (the name is a field of " +
                     csv_file + ")");
  return s;
}

// Shortest text that reads back to the same double (at most 17 significant digits; ".nan" if it
// cannot be written).
inline std::string FormatDouble(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string(".nan");
}

// "[x, y, z]" in FormatDouble's numbers (a YAML flow sequence).
inline std::string FormatVector3(const Eigen::Vector3d& v) {
  return "[" + FormatDouble(v.x()) + ", " + FormatDouble(v.y()) + ", " + FormatDouble(v.z()) + "]";
}

// A YAML double-quoted scalar of a Printable text: '"' and '\\' escaped, tab written as \t.
inline std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\t') {
      out += "\\t";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

// Parses text; a YAML syntax error becomes a kParseError at its line.
inline Result<YAML::Node> Parse(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    return Status(StatusCode::kParseError, "YAML nested " + std::to_string(e.depth()) + " levels deep; expected a "
                  "configuration, not nested lists or maps", source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  } catch (const YAML::ParserException& e) {
    return Status(StatusCode::kParseError, "YAML syntax: " + EchoInput(e.msg, 2 * kMaxEchoBytes), source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, "YAML: " + EchoInput(e.what(), 2 * kMaxEchoBytes), source);
  }
}

// A FIFO or device is refused without blocking; above 16 MiB is an error (core/text_file.h).
inline Result<std::string> ReadFile(const std::string& path) { return ReadTextFile(path, "cannot open file"); }

}  // namespace tpcal::kinematics::yaml_internal
