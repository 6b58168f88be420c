// DMIS output reader (see dmis_reader.h): statements joined over `$` continuations, comments
// dropped, then the FA point actuals, UNITS and FILNAM interpreted.
#include "pipeline/io/dmis_reader.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <system_error>
#include <vector>

#include "core/input_echo.h"
#include "core/units.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

struct DmisStatement {
  std::string text;  // blanks outside quotes removed
  std::size_t line = 0;
};

std::string UpperAscii(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return out;
}

std::string DmisEcho(std::string_view s) { return "'" + EchoInput(s, 60) + "'"; }

// Splits `text` into statements. Error: a `$` continuation at the end of the file.
Result<std::vector<DmisStatement>> SplitStatements(std::string_view text, const std::string& source) {
  std::vector<DmisStatement> out;
  DmisStatement cur;
  bool continuing = false;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    // Drop blanks outside quotes and the `$$` comment.
    std::string clean;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '\'') quoted = !quoted;
      if (!quoted && c == '$' && i + 1 < line.size() && line[i + 1] == '$') break;
      if (!quoted && (c == ' ' || c == '\t')) continue;
      clean.push_back(c);
    }
    if (!continuing) {
      cur.text.clear();
      cur.line = line_no;
    }
    if (!clean.empty() && clean.back() == '$') {
      clean.pop_back();
      cur.text += clean;
      continuing = true;
      continue;
    }
    cur.text += clean;
    continuing = false;
    if (!cur.text.empty()) out.push_back(cur);
  }
  if (continuing)
    return Status(StatusCode::kParseError,
                  "statement continued with '$' but the file ends: expected the rest of the statement on the next line",
                  source, cur.line);
  return out;
}

// Comma-separated fields outside quotes.
std::vector<std::string_view> SplitFields(std::string_view s) {
  std::vector<std::string_view> out;
  bool quoted = false;
  std::size_t b = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\'') quoted = !quoted;
    if (!quoted && s[i] == ',') {
      out.push_back(s.substr(b, i - b));
      b = i + 1;
    }
  }
  out.push_back(s.substr(b));
  return out;
}

std::optional<double> DmisNumber(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  auto r = fast_float::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}


enum class AngleUnit { kDegree, kRadian, kDms };

// The modal state point actuals are read in: UNITS and WKPLAN.
struct DmisModes {
  double mm_per_unit = 1.0;
  AngleUnit angle = AngleUnit::kDegree;
  int first_axis = 0;  // WKPLAN: 0 XYPLAN, 1 YZPLAN, 2 ZXPLAN, -1 another (a feature's plane)
  std::string wkplan;  // the last WKPLAN statement
};

// Position (file units) and vector of `FEAT/POINT,CART|POL,...` from its fields (fields[0] is
// POINT). A polar point (r, angle, height) lies in the work plane: the angle runs from the
// plane's first axis toward its second (X->Y, Y->Z, Z->X), the height along its normal; the
// vector stays i,j,k. Errors: not six numbers, a non-number, a polar point under ANGDMS or in a
// work plane other than XYPLAN, YZPLAN or ZXPLAN.
Status PointActual(const std::vector<std::string_view>& fields, const std::string& label, const DmisModes& modes,
                   std::size_t line, const std::string& source, Eigen::Vector3d& xyz, Eigen::Vector3d& n) {
  auto error = [&](std::string what) { return Status(StatusCode::kParseError, std::move(what), source, line); };
  const bool polar = fields.size() >= 2 && fields[1] == "POL";
  if (fields.size() < 2 || (fields[1] != "CART" && !polar))
    return error(fmt::format("FA({}): expected FEAT/POINT,CART,x,y,z,i,j,k or FEAT/POINT,POL,r,a,h,i,j,k", label));
  if (fields.size() != 8)
    return error(fmt::format("FA({}) has {} numbers after FEAT/POINT,{}: expected 6 ({},i,j,k)", label,
                             fields.size() - 2, fields[1], polar ? "r,a,h" : "x,y,z"));
  double v[6];
  for (int k = 0; k < 6; ++k) {
    auto x = DmisNumber(fields[2 + k]);
    if (!x)
      return error(fmt::format("FA({}): {} is not a number: expected {},i,j,k", label, DmisEcho(fields[2 + k]),
                               polar ? "r,a,h" : "x,y,z"));
    v[k] = *x;
  }
  n = Eigen::Vector3d(v[3], v[4], v[5]);
  if (!polar) {
    xyz = Eigen::Vector3d(v[0], v[1], v[2]);
    return Status();
  }
  if (modes.first_axis < 0)
    return error(fmt::format("FA({}): a polar point in {}: expected WKPLAN/XYPLAN, YZPLAN or ZXPLAN", label,
                             DmisEcho(modes.wkplan)));
  if (modes.angle == AngleUnit::kDms)
    return error(fmt::format("FA({}): a polar angle in UNITS ANGDMS: expected ANGDEC or ANGRAD", label));
  const double a_rad = modes.angle == AngleUnit::kDegree ? DegToRad(v[1]) : v[1];
  const int u = modes.first_axis;
  xyz[u] = v[0] * std::cos(a_rad);
  xyz[(u + 1) % 3] = v[0] * std::sin(a_rad);
  xyz[(u + 2) % 3] = v[2];
  return Status();
}

}  // namespace

std::string DmisFeatureOfLabel(std::string_view label) {
  const std::size_t us = label.rfind('_');
  if (us == std::string_view::npos || us == 0 || us + 1 == label.size()) return std::string(label);
  for (std::size_t i = us + 1; i < label.size(); ++i)
    if (label[i] < '0' || label[i] > '9') return std::string(label);
  return std::string(label.substr(0, us));
}

Result<DmisFile> ParseDmisOutput(std::string_view text, const std::string& source_name,
                                 const DmisReadOptions& dmis_options) {
  auto statements = SplitStatements(text, source_name);
  if (!statements.ok()) return statements.status();
  DmisFile out;
  PointSet& ps = out.file.points;
  ps.source = source_name;
  DmisModes modes;
  bool saw_inch = false;
  auto error = [&](std::size_t line, std::string what) {
    return Status(StatusCode::kParseError, std::move(what), source_name, line);
  };
  for (const DmisStatement& st : *statements) {
    const std::string up = UpperAscii(st.text);
    if (up.rfind("UNITS/", 0) == 0) {
      const auto f = SplitFields(std::string_view(up).substr(6));
      const std::string_view len = f[0];
      double& mm_per_unit = modes.mm_per_unit;
      if (len == "MM") mm_per_unit = 1.0;
      else if (len == "CM") mm_per_unit = 10.0;
      else if (len == "METER") mm_per_unit = 1000.0;
      else if (len == "INCH") mm_per_unit = kMmPerInch;
      else if (len == "FEET") mm_per_unit = 12.0 * kMmPerInch;
      else
        return error(st.line, fmt::format("UNITS/{}: expected a length unit MM, CM, METER, INCH or FEET", DmisEcho(len)));
      if (f.size() < 2 || (f[1] != "ANGDEC" && f[1] != "ANGDMS" && f[1] != "ANGRAD"))
        return error(st.line, fmt::format("{}: expected UNITS/<length>,ANGDEC|ANGDMS|ANGRAD", DmisEcho(st.text)));
      modes.angle = f[1] == "ANGDEC" ? AngleUnit::kDegree : f[1] == "ANGRAD" ? AngleUnit::kRadian : AngleUnit::kDms;
      out.report.units = mm_per_unit == kMmPerInch ? LengthUnit::kInch : LengthUnit::kMm;
      saw_inch = saw_inch || mm_per_unit == kMmPerInch;
      continue;
    }
    if (up.rfind("WKPLAN/", 0) == 0) {
      const std::string_view plane = std::string_view(up).substr(7);
      modes.first_axis = plane == "XYPLAN" ? 0 : plane == "YZPLAN" ? 1 : plane == "ZXPLAN" ? 2 : -1;
      modes.wkplan = st.text;
      continue;
    }
    if (up.rfind("FILNAM/", 0) == 0) {
      const auto f = SplitFields(std::string_view(st.text).substr(7));
      std::string_view name = f[0];
      if (name.size() >= 2 && name.front() == '\'' && name.back() == '\'') name = name.substr(1, name.size() - 2);
      out.report.filnam = std::string(name);
      continue;
    }
    if (up.rfind("FA(", 0) != 0) continue;  // MEAS, PTMEAS, OUTPUT, F(...) nominals, ...
    const std::size_t close = st.text.find(')');
    if (close == std::string::npos || close == 3)
      return error(st.line, fmt::format("{}: expected FA(label)=FEAT/...", DmisEcho(st.text)));
    const std::string label = st.text.substr(3, close - 3);
    const std::string shown = EchoInput(label);  // the label in messages
    const std::string_view rest = std::string_view(up).substr(close + 1);
    if (rest.rfind("=FEAT/", 0) != 0) continue;  // FA(x)=... of another kind (e.g. a tolerance actual)
    const auto fields = SplitFields(rest.substr(6));
    const std::string_view type = fields[0];
    if (type != "POINT") {
      ++out.report.skipped_actuals[std::string(type)];
      continue;
    }
    Eigen::Vector3d xyz, n;
    TPCAL_RETURN_IF_ERROR(PointActual(fields, shown, modes, st.line, source_name, xyz, n));
    const double len = n.norm();
    if (!(len > 1e-12) || std::abs(len - 1.0) > dmis_options.normal_tolerance)
      return error(st.line, fmt::format("FA({}): vector ({}, {}, {}) has length {:.6g}: expected a unit vector",
                                        shown, n.x(), n.y(), n.z(), len));
    const std::string feature = DmisFeatureOfLabel(label);
    if (!dmis_options.known_features.empty() &&
        std::find(dmis_options.known_features.begin(), dmis_options.known_features.end(), feature) ==
            dmis_options.known_features.end())
      return error(st.line, fmt::format("FA({}): feature '{}' is not in the plan: expected a label <feature>_<k> of "
                                        "one of its {} features", shown, EchoInput(feature), dmis_options.known_features.size()));
    ps.xyz_mm.push_back(xyz * modes.mm_per_unit);
    ps.normal.push_back(std::abs(len - 1.0) > 1e-14 ? Eigen::Vector3d(n / len) : n);  // as the CSV reader
    ps.feature.push_back(ps.InternFeature(feature));
    ps.line.push_back(st.line);
  }
  if (ps.empty())
    return error(1, "no FA(label)=FEAT/POINT,CART|POL,... actuals: expected DMIS output with measured points");
  out.file.info.format = PointFormat::kDmis;
  out.file.info.source_units = saw_inch ? LengthUnit::kInch : LengthUnit::kMm;
  out.file.info.bytes = text.size();
  return out;
}

Result<PointFile> ParsePointDmis(std::string_view text, const std::string& source_name,
                                 const PointReadOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  DmisReadOptions d;
  d.normal_tolerance = options.normal_tolerance;
  auto r = ParseDmisOutput(text, source_name, d);
  if (!r.ok()) return r.status();
  return std::move(r->file);
}

Result<PointFile> ReadPointDmis(const std::string& path, const PointReadOptions& options) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParsePointDmis(bytes->view(), path, options);
}

}  // namespace tpcal::pipeline
