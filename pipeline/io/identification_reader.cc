#include "pipeline/io/identification_reader.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/input_echo.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

using json = nlohmann::json;

Status IdParseError(const std::string& source, const std::string& what, std::size_t line = 0) {
  return Status(StatusCode::kParseError, what, source, line);
}

// 1-based line of byte offset `byte` (nlohmann counts bytes read, one past the fault).
std::size_t LineOfByte(std::string_view text, std::size_t byte) {
  byte = std::min(byte, text.size());
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(byte), '\n'));
}

// Where the DOM parse failed without saying: nlohmann's number overflow (406, a number beyond a
// double) is an out_of_range with no position; a second pass through SAX gets its byte.
class FaultSax : public json::json_sax_t {
 public:
  std::size_t byte = 0;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(json::number_integer_t) override { return true; }
  bool number_unsigned(json::number_unsigned_t) override { return true; }
  bool number_float(json::number_float_t, const json::string_t&) override { return true; }
  bool string(json::string_t&) override { return true; }
  bool binary(json::binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(json::string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string&, const json::exception&) override {
    byte = position;
    return false;
  }
};

std::string StringOr(const json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

Result<IdentifiedParameter> ParameterOf(const json& p, std::size_t i, const std::string& source) {
  const std::string where = "parameters[" + std::to_string(i) + "]";
  if (!p.is_object() || !p.contains("name") || !p["name"].is_string())
    return IdParseError(source, where + ": expected an object with a string \"name\"");
  IdentifiedParameter out;
  out.name = p["name"].get<std::string>();
  const std::string at = where + " (" + EchoInput(out.name) + ")";
  if (!p.contains("unit") || !p["unit"].is_string()) return IdParseError(source, at + ": expected a string \"unit\"");
  if (!p.contains("identifiable") || !p["identifiable"].is_boolean())
    return IdParseError(source, at + ": expected a boolean \"identifiable\"");
  out.unit = p["unit"].get<std::string>();
  out.identifiable = p["identifiable"].get<bool>();
  if (!out.identifiable) return out;
  for (const char* key : {"value", "u"}) {
    if (!p.contains(key) || !p[key].is_number())
      return IdParseError(source, at + ": expected a number \"" + key + "\" (the parameter is identifiable)");
  }
  out.value = p["value"].get<double>(), out.u = p["u"].get<double>();
  if (!std::isfinite(out.value) || !std::isfinite(out.u) || out.u < 0.0)
    return IdParseError(source, at + ": expected a finite value and u >= 0");
  return out;
}

std::vector<std::string> StringsOf(const json& j, const char* key, const std::string& prefix = "") {
  std::vector<std::string> out;
  auto it = j.find(key);
  if (it == j.end() || !it->is_array()) return out;
  for (const json& s : *it)
    if (s.is_string()) out.push_back(prefix + s.get<std::string>());
  return out;
}

// The u of each map entry that has one: {"coefficient": "E_XC.n3", "u": 0.12, ...}; the
// coefficients of those marked "identifiable": false.
void ReadMapU(const json& entries, IdentificationFile* out) {
  for (const json& e : entries) {
    if (e.is_object() && e.contains("coefficient") && e["coefficient"].is_string() && e.contains("identifiable") &&
        e["identifiable"].is_boolean() && !e["identifiable"].get<bool>())
      out->map_undetermined.push_back(e["coefficient"].get<std::string>());
    if (!e.is_object() || !e.contains("coefficient") || !e["coefficient"].is_string() || !e.contains("u") ||
        !e["u"].is_number())
      continue;
    const double u = e["u"].get<double>();
    if (std::isfinite(u) && u > 0.0) out->map_u.emplace_back(e["coefficient"].get<std::string>(), u);
  }
}

// A ball-bar axis's map response (`where` names the axis): "response_to" and each entry's
// "coefficient" and "response", one finite number per name. `first`: the first axis with errors,
// which sets whether the file has one; every later axis must agree (names, or absence).
Status ReadMapResponse(const json& axis, bool first, const std::string& where, const std::string& source,
                       IdentificationFile* out) {
  const bool has = axis.contains("response_to");
  if (!first && has != !out->map_unmodelled.empty())
    return IdParseError(source, where + ": expected \"response_to\" on every axis or on none");
  if (!has) return Status::Ok();
  const json& to = axis["response_to"];
  if (!to.is_array() || to.empty() || !std::all_of(to.begin(), to.end(), [](const json& n) { return n.is_string(); }))
    return IdParseError(source, where + ": expected \"response_to\" to be a non-empty array of error names");
  const std::vector<std::string> names = to.get<std::vector<std::string>>();
  if (!first && out->map_unmodelled != names)
    return IdParseError(source, where + ": expected the same \"response_to\" as the axes before it");
  out->map_unmodelled = names;
  const json& entries = axis["errors"];
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const json& e = entries[k];
    const std::string at = where + ".errors[" + std::to_string(k) + "]";
    if (!e.is_object() || !e.contains("coefficient") || !e["coefficient"].is_string())
      return IdParseError(source, at + ": expected a string \"coefficient\"");
    if (!e.contains("response") || !e["response"].is_array() || e["response"].size() != names.size())
      return IdParseError(source, at + fmt::format(": expected a \"response\" of {} numbers", names.size()));
    std::vector<double> row;
    for (const json& v : e["response"]) {
      if (!v.is_number() || !std::isfinite(v.get<double>()))
        return IdParseError(source, at + ": expected finite numbers in \"response\"");
      row.push_back(v.get<double>());
    }
    out->map_unmodelled_response.emplace_back(e["coefficient"].get<std::string>(), std::move(row));
  }
  return Status::Ok();
}

// The error-map fields of a probe_artifacts ("maps", "not_identifiable") or ballbar ("axes[]":
// "errors", "not_identifiable", "not_separable") file; the maps themselves are in "errors_yaml".
Status ReadMapFields(const json& doc, const std::string& source, IdentificationFile* out) {
  out->errors_yaml = doc["errors_yaml"].get<std::string>();
  if (doc.contains("maps") && doc["maps"].is_array()) {
    out->map_entries = static_cast<int>(doc["maps"].size());
    ReadMapU(doc["maps"], out);
  }
  out->not_identifiable = StringsOf(doc, "not_identifiable");
  if (!doc.contains("axes") || !doc["axes"].is_array()) return Status::Ok();
  bool first = true;
  for (std::size_t i = 0; i < doc["axes"].size(); ++i) {
    const json& a = doc["axes"][i];
    if (!a.is_object()) continue;
    if (a.contains("errors") && a["errors"].is_array()) {
      out->map_entries += static_cast<int>(a["errors"].size());
      ReadMapU(a["errors"], out);
      TPCAL_RETURN_IF_ERROR(ReadMapResponse(a, first, "axes[" + std::to_string(i) + "]", source, out));
      first = false;
    }
    for (auto& n : StringsOf(a, "not_identifiable")) out->not_identifiable.push_back(std::move(n));
    const std::string axis = StringOr(a, "axis");
    for (auto& f : StringsOf(a, "not_separable", axis + ": ")) out->not_separable.push_back(std::move(f));
  }
  return Status::Ok();
}

// "parameter_covariance" (optional): n rows of n finite numbers for the n parameters, symmetric
// and positive semi-definite (eigenvalues above -1e-9 of the largest, as the prior update asks).
Status ReadParameterCovariance(const json& doc, const std::string& source, IdentificationFile* out) {
  auto it = doc.find("parameter_covariance");
  if (it == doc.end() || it->is_null()) return Status::Ok();
  const std::size_t n = out->parameters.size();
  const std::string expected =
      fmt::format("\"parameter_covariance\": expected {} rows of {} finite numbers (one per parameter)", n, n);
  if (!it->is_array() || it->size() != n) return IdParseError(source, expected);
  std::vector<double> cov;
  cov.reserve(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    const json& row = (*it)[i];
    if (!row.is_array() || row.size() != n) return IdParseError(source, expected + fmt::format(": row {}", i));
    for (const json& v : row) {
      if (!v.is_number() || !std::isfinite(v.get<double>()))
        return IdParseError(source, expected + fmt::format(": row {}", i));
      cov.push_back(v.get<double>());
    }
  }
  double largest = 0.0;
  for (double v : cov) largest = std::max(largest, std::abs(v));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (std::abs(cov[i * n + k] - cov[k * n + i]) > 1e-9 * largest)
        return IdParseError(source, fmt::format("\"parameter_covariance\": expected a symmetric matrix (rows {} and {} "
                                                "differ)", k, i));
  if (n > 0) {
    const auto m = static_cast<Eigen::Index>(n);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::Map<const Eigen::MatrixXd>(cov.data(), m, m),
                                                             Eigen::EigenvaluesOnly);
    if (eig.eigenvalues().minCoeff() < -1e-9 * std::max(0.0, eig.eigenvalues().maxCoeff()))
      return IdParseError(source, fmt::format("\"parameter_covariance\": expected a positive semi-definite matrix "
                                              "(an eigenvalue is {:.3g})", eig.eigenvalues().minCoeff()));
  }
  out->parameter_covariance = std::move(cov);
  return Status::Ok();
}

}  // namespace

Result<IdentificationFile> ParseIdentificationJson(std::string_view text, const std::string& source) {
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    return IdParseError(source, "expected JSON (tpcal.identification/1)", LineOfByte(text, e.byte > 0 ? e.byte - 1 : 0));
  } catch (const json::out_of_range&) {
    FaultSax sax;
    json::sax_parse(text.begin(), text.end(), &sax);
    return IdParseError(source, "expected JSON (tpcal.identification/1) with numbers within the range of a double",
                        LineOfByte(text, sax.byte > 0 ? sax.byte - 1 : 0));
  }
  if (!doc.is_object() || StringOr(doc, "schema") != "tpcal.identification/1")
    return IdParseError(source, "expected \"schema\": \"tpcal.identification/1\"");
  const bool maps = doc.contains("errors_yaml") && doc["errors_yaml"].is_string();
  if (!maps && (!doc.contains("parameters") || !doc["parameters"].is_array()))
    return IdParseError(source, "expected a \"parameters\" array (or an error-map instrument's \"errors_yaml\")");
  IdentificationFile out;
  out.source = source;
  out.instrument = StringOr(doc, "instrument");
  out.machine = StringOr(doc, "machine");
  if (maps) TPCAL_RETURN_IF_ERROR(ReadMapFields(doc, source, &out));
  if (maps && !(doc.contains("parameters") && doc["parameters"].is_array())) return out;
  const json& params = doc["parameters"];
  for (std::size_t i = 0; i < params.size(); ++i) {
    auto p = ParameterOf(params[i], i, source);
    if (!p.ok()) return p.status();
    out.parameters.push_back(std::move(*p));
  }
  TPCAL_RETURN_IF_ERROR(ReadParameterCovariance(doc, source, &out));
  return out;
}

Result<IdentificationFile> ReadIdentificationJson(const std::string& path) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParseIdentificationJson(bytes->view(), path);
}

}  // namespace tpcal::pipeline
