#include "pipeline/seed002_comparison.h"

#include <vector>

namespace tpcal::pipeline {

Result<Seed002ColumnsComparison> CompareSeed002Columns(const kinematics::Seed002Items& table1,
                                                       const kinematics::Seed002Items& item_u,
                                                       const kinematics::Seed002Geometry& geometry,
                                                       std::span<const kinematics::ParameterEstimate> probing,
                                                       double alpha) {
  auto solved = kinematics::SolveSeed002(table1, geometry, kinematics::Seed002Equations::kKinematics, item_u);
  if (!solved.ok()) return solved.status();
  std::vector<kinematics::ParameterEstimate> piece;
  for (const kinematics::ClosedFormParameter& p : solved->parameters) {
    kinematics::ParameterEstimate e;
    e.name = p.name, e.unit = p.unit, e.identifiable = p.identifiable, e.value = p.value, e.u = p.u;
    piece.push_back(std::move(e));
  }
  kinematics::Identifiability identifiability;
  identifiability.num_parameters = static_cast<int>(piece.size());
  identifiability.rank = solved->rank;
  identifiability.estimable = solved->combinations;
  Seed002ColumnsComparison out;
  out.agreement = CompareWithReference(probing, piece, identifiability, alpha);
  out.agreement.instrument = "seed 002 probing test";
  out.agreement.source = "seed 002 Table 2";
  out.piece = std::move(solved).value();
  return out;
}

}  // namespace tpcal::pipeline
