// Small helpers shared by the JSON writers of the pipeline (include only from .cc files: it
// pulls in nlohmann/json). Numbers are written by nlohmann's shortest round-trip format, so
// the same values give the same bytes.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/frames.h"

namespace tpcal::pipeline {

template <typename Derived>
nlohmann::ordered_json Vec(const Eigen::MatrixBase<Derived>& v) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v(i));
  return a;
}

// `value` when it is known, else null (a coefficient the data cannot determine is written as
// null, never as a number).
template <typename T>
nlohmann::ordered_json OrNull(bool known, const T& value) {
  return known ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

// {"rotation": [[r00, r01, r02], ...], "translation_mm": [x, y, z]}
inline nlohmann::ordered_json RigidJson(const Rigid3& t) {
  nlohmann::ordered_json rot = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r) rot.push_back(Vec(t.linear().row(r)));
  return {{"rotation", rot}, {"translation_mm", Vec(t.translation())}};
}

}  // namespace tpcal::pipeline
