// PointSet: probed or scanned points, measured or simulated alike (nothing downstream can
// tell which). Coordinates in mm in the frame of the file (CMM frame for measured data).
// Per-point arrays are parallel: index i of every non-empty array refers to the same point.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace tpcal {

// An extra column of a point file, kept per point. Numeric columns fill `values`; a column
// holding any non-numeric cell fills `text` instead (values then empty).
struct PointAttribute {
  std::string name;
  std::vector<double> values;
  std::vector<std::string> text;
  bool is_numeric() const { return text.empty(); }
};

struct PointSet {
  std::string source;                    // file name or description, for messages
  std::vector<Eigen::Vector3d> xyz_mm;   // point coordinates, mm
  std::vector<Eigen::Vector3d> normal;   // unit outward normals; empty when the file had none
  std::vector<int> feature;              // index into feature_names; kUnlabelled for raw scans
  std::vector<std::string> feature_names;  // in order of first appearance
  std::vector<std::size_t> line;         // 1-based source line per point; empty if not from text
  std::vector<PointAttribute> attributes;  // extra columns in file order

  static constexpr int kUnlabelled = -1;

  std::size_t size() const { return xyz_mm.size(); }
  bool empty() const { return xyz_mm.empty(); }
  bool has_normals() const { return !normal.empty(); }
  bool has_labels() const;  // true if any point carries a feature label

  // Index of a feature name, or nullopt.
  std::optional<int> FeatureIndex(const std::string& name) const;
  // Index of `name`, adding it to feature_names if new.
  int InternFeature(const std::string& name);
  // Indices of the points of a feature (empty if unknown).
  std::vector<std::size_t> IndicesOf(const std::string& name) const;
  // Coordinates of the points of a feature, in file order.
  std::vector<Eigen::Vector3d> PointsOf(const std::string& name) const;
  // Numeric attribute column by name, or nullptr.
  const PointAttribute* Attribute(const std::string& name) const;
  // Source line of point i, or 0.
  std::size_t LineOf(std::size_t i) const { return i < line.size() ? line[i] : 0; }
};

}  // namespace tpcal
