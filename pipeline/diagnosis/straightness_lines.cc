#include "pipeline/diagnosis/straightness_lines.h"

#include <Eigen/Dense>
#include <cmath>

#include "kinematics/axis_state.h"

namespace tpcal::pipeline::diagnosis_internal {

const std::vector<std::string>& StraightnessSymbols() {
  static const std::vector<std::string> symbols = {"E_YX", "E_ZX", "E_XY", "E_ZY", "E_XZ", "E_YZ"};
  return symbols;
}

std::string ReferenceLineItem(const std::string& symbol) {
  return "{linear_error_motion: {symbol: " + symbol + ", coefficients_um_per_mm_pow: [0, 0], powers: [0, 1]}}";
}

void RemoveReferenceLines(std::span<const kinematics::Observation> obs, const kinematics::ErrorState& errors,
                          const std::vector<int>& coefficients,
                          const std::map<std::string, std::pair<int, int>>& line_columns, Eigen::MatrixXd* J) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  for (std::size_t j = 0; j < coefficients.size(); ++j) {
    const auto& info = errors.coefficient_info(coefficients[j]);
    const auto& term = errors.terms()[static_cast<std::size_t>(info.term)];
    const auto line = line_columns.find(term.label);
    if (term.kind != kinematics::TermKind::kPolynomial || line == line_columns.end()) continue;
    const int power = term.powers[static_cast<std::size_t>(info.index)];
    if (power < 2) continue;
    // q^k on [1, q - mean] by least squares (centred for conditioning), then back to [1, q].
    Eigen::VectorXd q(n);
    for (Eigen::Index i = 0; i < n; ++i) q(i) = kinematics::Position(obs[static_cast<std::size_t>(i)].cut.axes, term.argument);
    const double mean = q.mean();
    const Eigen::VectorXd qc = q.array() - mean;
    const Eigen::VectorXd qk = q.array().pow(power);
    const double slope = qc.squaredNorm() > 0 ? qc.dot(qk) / qc.squaredNorm() : 0.0;
    const double offset = qk.mean() - slope * mean;
    J->col(static_cast<Eigen::Index>(j)) -= offset * J->col(line->second.first) + slope * J->col(line->second.second);
  }
}

}  // namespace tpcal::pipeline::diagnosis_internal
