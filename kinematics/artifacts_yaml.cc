#include "kinematics/artifacts_yaml.h"

#include <set>

#include "kinematics/internal/yaml_util.h"

namespace tpcal::kinematics {

namespace y = yaml_internal;

namespace {

// File-local names carry an Artifacts prefix: a unity build merges this file with the other
// kinematics readers (machine_yaml.cc has its own Parse, errors_yaml.cc its own Fmt).

constexpr const char* kArtifactsSchema = "tpcal.artifacts/1";

Result<ArtifactBox> ArtifactsBox(const std::string& src, const YAML::Node& node, const std::string& what) {
  Result<std::vector<y::MapEntry>> entries = y::Entries(src, node, what);
  TPCAL_RETURN_IF_ERROR(entries);
  TPCAL_RETURN_IF_ERROR(y::CheckKeys(src, *entries, {"name", "base_centre_mm", "size_mm", "rotation_deg"}, what));
  ArtifactBox box;
  const y::MapEntry* name = y::Find(*entries, "name");
  if (!name) return y::Error(src, node, what + ": missing 'name' (as in the probed-point file's artifact column)");
  Result<std::string> s = y::CsvName(src, name->value, what, "the probed-point file");
  TPCAL_RETURN_IF_ERROR(s);
  box.name = *s;
  Result<Eigen::Vector3d> base = y::Vector3At(src, *entries, node, "base_centre_mm", what);
  TPCAL_RETURN_IF_ERROR(base);
  box.base_centre_mm = *base;
  Result<Eigen::Vector3d> size = y::Vector3At(src, *entries, node, "size_mm", what);
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
  for (const ArtifactBox& b : set.boxes) {
    out += "  - {name: " + y::Quoted(b.name) + ", base_centre_mm: " + y::FormatVector3(b.base_centre_mm) +
           ", size_mm: " + y::FormatVector3(b.size_mm) + ", rotation_deg: " + y::FormatDouble(b.rotation_deg) + "}\n";
  }
  return out;
}

}  // namespace tpcal::kinematics
