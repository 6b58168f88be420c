#include "core/point_set.h"

#include <algorithm>

namespace tpcal {

bool PointSet::has_labels() const {
  return std::any_of(feature.begin(), feature.end(), [](int f) { return f != kUnlabelled; });
}

std::optional<int> PointSet::FeatureIndex(const std::string& name) const {
  auto it = std::find(feature_names.begin(), feature_names.end(), name);
  if (it == feature_names.end()) return std::nullopt;
  return static_cast<int>(it - feature_names.begin());
}

int PointSet::InternFeature(const std::string& name) {
  if (auto idx = FeatureIndex(name)) return *idx;
  feature_names.push_back(name);
  return static_cast<int>(feature_names.size() - 1);
}

std::vector<std::size_t> PointSet::IndicesOf(const std::string& name) const {
  std::vector<std::size_t> out;
  const auto idx = FeatureIndex(name);
  if (!idx) return out;
  for (std::size_t i = 0; i < feature.size(); ++i)
    if (feature[i] == *idx) out.push_back(i);
  return out;
}

std::vector<Eigen::Vector3d> PointSet::PointsOf(const std::string& name) const {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i : IndicesOf(name)) out.push_back(xyz_mm[i]);
  return out;
}

const PointAttribute* PointSet::Attribute(const std::string& name) const {
  for (const auto& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

}  // namespace tpcal
