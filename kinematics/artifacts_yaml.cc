#include "kinematics/artifacts_yaml.h"

#include <charconv>
#include <set>

#include "kinematics/internal/yaml_util.h"

namespace tpcal::kinematics {

namespace y = yaml_internal;

namespace {

// File-local names carry an Artifacts prefix: a unity build merges this file with the other
// kinematics readers (machine_yaml.cc has its own Parse, errors_yaml.cc its own Fmt).

constexpr const char* kArtifactsSchema = "tpcal.artifacts/1";

// Shortest text that reads back to the same double (at most 17 significant digits).
std::string ArtifactsFmt(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, end) : std::string(".nan");
}

// A YAML double-quoted scalar of a printable name (y::Printable: no control byte but tab).
std::string ArtifactsQuoted(const std::string& s) {
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

// A name is written as a field of the probed-point CSV (pipeline/io/probepts_io.h), which splits
// at commas, trims blanks and skips lines starting with '#'.
bool ArtifactsNameFitsCsv(const std::string& name) {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  return name.find(',') == std::string::npos && name.front() != '#' && !blank(name.front()) && !blank(name.back());
}

Result<Eigen::Vector3d> ArtifactsVector(const std::string& src, const std::vector<y::MapEntry>& entries,
                                        const YAML::Node& where, const std::string& key, const std::string& what) {
  const y::MapEntry* e = y::Find(entries, key);
  if (!e) return y::Error(src, where, what + ": missing '" + key + "' ([x, y, z], mm)");
  return y::Vector3(src, e->value, what + "." + key);
}

Result<ArtifactBox> ArtifactsBox(const std::string& src, const YAML::Node& node, const std::string& what) {
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, node, what);
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries, {"name", "base_centre_mm", "size_mm", "rotation_deg"}, what));
  ArtifactBox box;
  const y::MapEntry* name = y::Find(*entries, "name");
  if (!name) return y::Error(src, node, what + ": missing 'name' (as in the probed-point file's artifact column)");
  Result<std::string> s = y::String(src, name->value, what + ".name");
  TPCAL_RETURN_IF_ERROR(s);
  if (s->empty()) return y::Error(src, name->value, what + ".name: expected a non-empty name");
  if (!ArtifactsNameFitsCsv(*s)) {
    return y::Error(src, name->value,
                    what + ".name '" + EchoInput(*s) +
                        "': expected no comma, no leading '#' and no leading or trailing blank (the name is a "
                        "field of the probed-point file)");
  }
  box.name = *s;
  Result<Eigen::Vector3d> base = ArtifactsVector(src, *entries, node, "base_centre_mm", what);
  TPCAL_RETURN_IF_ERROR(base);
  box.base_centre_mm = *base;
  Result<Eigen::Vector3d> size = ArtifactsVector(src, *entries, node, "size_mm", what);
  TPCAL_RETURN_IF_ERROR(size);
  if (!(size->minCoeff() > 0.0)) {
    return y::Error(src, y::Find(*entries, "size_mm")->value, what + ".size_mm: every extent must be > 0");
  }
  box.size_mm = *size;
  if (const y::MapEntry* r = y::Find(*entries, "rotation_deg")) {
    Result<double> v = y::Double(src, r->value, what + ".rotation_deg");
    TPCAL_RETURN_IF_ERROR(v);
    box.rotation_deg = *v;
  } else {
    box.rotation_deg = 0.0;
  }
  return box;
}

Result<ArtifactSet> ArtifactsParse(const std::string& src, const YAML::Node& root) {
  if (root.IsNull()) return Status(StatusCode::kParseError, "empty file: expected 'artifacts:' with a list of boxes", src, 1);
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, root, "artifact file");
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries, {"schema", "artifacts"}, "artifact file"));
  if (const y::MapEntry* e = y::Find(*entries, "schema")) {
    Result<std::string> s = y::String(src, e->value, "schema");
    TPCAL_RETURN_IF_ERROR(s);
    if (*s != kArtifactsSchema) {
      return y::Error(src, e->value, "schema: expected " + std::string(kArtifactsSchema) + ", got " + EchoInput(*s));
    }
  }
  const y::MapEntry* list = y::Find(*entries, "artifacts");
  if (!list) return y::Error(src, root, "artifact file: missing 'artifacts' (a list of boxes)");
  if (!list->value.IsSequence()) return y::Error(src, list->value, "artifacts: expected a list of boxes");
  if (list->value.size() == 0) return y::Error(src, list->key_node, "artifacts: no artifacts");
  ArtifactSet set;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list->value.size(); ++i) {
    const YAML::Node node = list->value[i];
    Result<ArtifactBox> box = ArtifactsBox(src, node, "artifacts[" + std::to_string(i) + "]");
    TPCAL_RETURN_IF_ERROR(box);
    if (!names.insert(box->name).second) {
      return y::Error(src, node, "artifacts[" + std::to_string(i) + "]: name '" + EchoInput(box->name) + "' repeated");
    }
    set.boxes.push_back(std::move(*box));
  }
  return set;
}

}  // namespace

Result<ArtifactSet> ParseArtifactsYaml(std::string_view text, const std::string& source) {
  Result<YAML::Node> root = y::Parse(std::string(text), source);
  TPCAL_RETURN_IF_ERROR(root);
  try {
    return ArtifactsParse(source, *root);
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, "YAML: " + EchoInput(e.what(), 2 * kMaxEchoBytes), source,
                  e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line) + 1 : 0);
  }
}

Result<ArtifactSet> LoadArtifactsYaml(const std::string& path) {
  Result<std::string> text = y::ReadFile(path);
  TPCAL_RETURN_IF_ERROR(text);
  return ParseArtifactsYaml(*text, path);
}

std::string FormatArtifactsYaml(const ArtifactSet& set) {
  std::string out = std::string("schema: ") + kArtifactsSchema + "\nartifacts:\n";
  const auto vec = [](const Eigen::Vector3d& v) {
    return "[" + ArtifactsFmt(v.x()) + ", " + ArtifactsFmt(v.y()) + ", " + ArtifactsFmt(v.z()) + "]";
  };
  for (const ArtifactBox& b : set.boxes) {
    out += "  - {name: " + ArtifactsQuoted(b.name) + ", base_centre_mm: " + vec(b.base_centre_mm) +
           ", size_mm: " + vec(b.size_mm) + ", rotation_deg: " + ArtifactsFmt(b.rotation_deg) + "}\n";
  }
  return out;
}

}  // namespace tpcal::kinematics
