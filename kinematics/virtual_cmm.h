// Virtual CMM: turns simulated actual surface points (part frame) into what a CMM would report:
// Gaussian probing noise along the nominal normal, an optional probe-radius error, and an
// optional random rigid placement of the part on the CMM table (returned, so tests can check
// that nothing downstream assumes the CMM frame is the part frame).
#pragma once

#include <random>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/status.h"

namespace tpcal::kinematics {

struct VirtualCmmOptions {
  double noise_sigma_um = 0.0;         // 1-sigma probing noise along the normal, >= 0
  // Actual minus calibrated probe-ball radius: every reported point moves outward along its
  // normal by this much (outer diameters read larger, holes smaller).
  double probe_radius_error_um = 0.0;
  bool random_placement = false;       // else cmm_from_part = identity
  double max_translation_mm = 300.0;   // placement translation, each component in [-max, max]
  bool any_orientation = true;         // uniform rotation in SO(3); else about CMM Z only
  Status Validate() const;
};

struct VirtualCmmResult {
  PointSet points;      // CMM frame; normals rotated; labels, lines and attributes kept
  Rigid3 cmm_from_part = Rigid3::Identity();
};

// `actual_in_part` must carry unit normals (nominal outward normals, part frame). Draws from
// `rng` in a fixed order: placement first (if any), then one normal deviate per point, all drawn
// by core/portable_random.h (the same values with any standard library).
Result<VirtualCmmResult> MeasureWithVirtualCmm(const PointSet& actual_in_part,
                                               const VirtualCmmOptions& options,
                                               std::mt19937_64& rng);

}  // namespace tpcal::kinematics
