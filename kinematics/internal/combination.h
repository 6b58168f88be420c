// Named linear combinations of parameters, for identifiability reports.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace tpcal::kinematics::internal {

// "dy_AR(-90) + dz_AR(-90)", "a - 0.4007 b": coefficients of magnitude 1 are not printed;
// entries below 1e-6 (of the largest, which is 1) are left out of the text.
std::string FormatCombination(const std::vector<std::string>& names, const std::vector<double>& c);

// Scales c so that its largest |entry| is +1; entries below 1e-10 become exactly 0.
void NormaliseCombination(Eigen::VectorXd* c);

// Basis of the vectors supported on `subset` (indices into n) orthogonal to the columns of
// `null_space` (n x m): the estimable combinations among non-identifiable parameters. Each
// returned vector has size n and is normalised by NormaliseCombination.
std::vector<Eigen::VectorXd> EstimableCombinations(const Eigen::MatrixXd& null_space, const std::vector<int>& subset);

}  // namespace tpcal::kinematics::internal
