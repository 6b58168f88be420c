// Point-level effects the validation of the diagnosis (diagnosis_validate.h) injects into a
// simulated piece, at unit size (um along each plan point's outward normal; the validation scales
// them): what real CMM files hold besides machine errors, and effects the catalogue has no
// candidate for.
//   outliers        1 % of the points (at least 1), +-1 each (dust on a probe hit, a mis-trigger);
//   local_defect    one patch of one feature: a burr (2-3 neighbouring hits, outward), a chip
//                   (4-6 hits, inward) or a dent (5-8 hits, inward), at most a quarter of the
//                   feature's points; 1 at its centre falling to 0.7 at its edge;
//   fixture_bend    the part bent by its clamping: a bow along the part's Z, quadratic in X or Y
//                   over the part's extent, peak 1 (mean removed);
//   spindle_growth  a growth of the tool along the part's Z that changes with each operation (its
//                   own spindle speed): a random step per operation, largest 1.
// Each returns the offsets per plan point; `detail` says what was drawn.
#pragma once

#include <Eigen/Core>
#include <random>
#include <string>

#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {

Eigen::VectorXd OutlierOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail);
Eigen::VectorXd LocalDefectOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail);
Eigen::VectorXd FixtureBendOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail);
Eigen::VectorXd SpindleGrowthOffsets(const testpieces::ProbingPlan& plan, std::mt19937_64& rng, std::string* detail);

}  // namespace tpcal::pipeline
