// Evaluated characteristics: named numbers with units (um, urad, mm, deg), the features used,
// and for circularity the sampled profile. Sign conventions: gdt/location.h (concentricity,
// position, plane distance), gdt/orientation.h (parallelism, squareness), gdt/form.h
// (profile), gdt/hole_pattern.h (hole angles). Value names per type: gdt/PLAN_FORMAT.md.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"
#include "gdt/fitted_feature.h"
#include "gdt/plan.h"

namespace tpcal::gdt {

struct NamedValue {
  std::string name;  // carries its unit: "dx_um", "da_urad", "distance_mm"
  double value = 0;
  std::string unit;  // "um", "urad", "mm", "deg"
};

// One sample of a circularity profile (seed 002: dr_Si(C)), output units.
struct ProfileSample {
  double theta_deg = 0;  // [0, 360), about the circle centre from datum +X (gdt/form.h)
  double dr_um = 0;      // radial deviation from the LS circle, positive outward
  std::size_t point_index = 0;  // index into the PointSet (pitch circles: member index)
};

struct CharacteristicResult {
  std::string name;
  CharacteristicType type = CharacteristicType::kFlatness;
  std::string symbol;
  std::string description;
  std::vector<std::string> features;  // toleranced feature first, then the datum if any
  std::optional<FormCriterion> criterion;  // form characteristics: the criterion of the main value
  std::vector<NamedValue> values;
  std::vector<ProfileSample> profile;  // circularity only, sorted by theta
  std::string note;  // e.g. a minimum-zone value that is not certified optimal, and why

  // The value named `name`, or nullopt.
  std::optional<double> Value(const std::string& name) const;
};

// Evaluates one characteristic from fitted features (by name) and all points in the datum
// frame (indexed by FittedFeature::point_indices). Errors cite the characteristic; the
// caller adds the plan location.
Result<CharacteristicResult> EvaluateCharacteristic(const CharacteristicSpec& spec,
                                                    const std::map<std::string, const FittedFeature*>& features,
                                                    std::span<const Eigen::Vector3d> points_datum);

}  // namespace tpcal::gdt
