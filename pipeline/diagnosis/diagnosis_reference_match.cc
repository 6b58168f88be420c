#include "pipeline/diagnosis/diagnosis_reference_match.h"

#include <fmt/format.h>
#include <algorithm>
#include <map>

#include "core/status.h"

namespace tpcal::pipeline::diagnosis_internal {
namespace {

using FeatureObservations = std::map<std::string, std::vector<std::size_t>>;

// Observations per feature name, in file order.
FeatureObservations ObservationsOfFeature(const testpieces::MeasuredObservations& m) {
  FeatureObservations of_feature;
  for (std::size_t i = 0; i < m.observations.size(); ++i)
    of_feature[m.feature_names[static_cast<std::size_t>(m.observations[i].group)]].push_back(i);
  return of_feature;
}

const Eigen::Vector3d& NominalOf(const testpieces::MeasuredObservations& m, std::size_t k) {
  return m.observations[k].cut.nominal_point_mm;
}

// The measured observations `mi` of one feature matched with its reference observations `rj`.
void MatchFeature(const testpieces::MeasuredObservations& mo, const std::vector<std::size_t>& mi,
                  const testpieces::MeasuredObservations& ro, const std::vector<std::size_t>& rj, double tol_mm,
                  ReferenceMatching* out) {
  DiagnosisResult::ReferenceMatch& rm = out->summary;
  bool by_order = mi.size() == rj.size();
  for (std::size_t k = 0; by_order && k < mi.size(); ++k)
    by_order = (NominalOf(mo, mi[k]) - NominalOf(ro, rj[k])).norm() <= tol_mm;
  for (std::size_t k = 0; k < mi.size(); ++k) {
    std::size_t best = rj.front();
    double best_d = (NominalOf(mo, mi[k]) - NominalOf(ro, best)).norm();
    if (by_order) {
      best = rj[k];
      best_d = (NominalOf(mo, mi[k]) - NominalOf(ro, best)).norm();
    } else {
      for (std::size_t j : rj) {  // first nearest in file order
        const double d = (NominalOf(mo, mi[k]) - NominalOf(ro, j)).norm();
        if (d < best_d) best = j, best_d = d;
      }
      if (best_d > tol_mm) continue;
    }
    out->match[mi[k]] = static_cast<long>(best);
    rm.max_offset_mm = std::max(rm.max_offset_mm, best_d);
    (by_order ? rm.matched_by_order : rm.matched_by_nearest) += 1;
  }
}

}  // namespace

ReferenceMatching MatchReferencePoints(const testpieces::MeasuredObservations& mo,
                                       const testpieces::MeasuredObservations& ro, double tol_mm) {
  const FeatureObservations ref_of_feature = ObservationsOfFeature(ro);
  const FeatureObservations meas_of_feature = ObservationsOfFeature(mo);
  ReferenceMatching out;
  out.match.assign(mo.observations.size(), -1);
  for (const auto& [name, mi] : meas_of_feature) {
    const auto it = ref_of_feature.find(name);
    if (it != ref_of_feature.end()) MatchFeature(mo, mi, ro, it->second, tol_mm, &out);
  }
  return out;
}

testpieces::MeasuredObservations KeepMatched(const testpieces::MeasuredObservations& mo, const PointSet& measured,
                                             const Eigen::VectorXd& ref_dev_um, double tol_mm,
                                             ReferenceMatching* matching, std::vector<double>* dev,
                                             std::vector<std::string>* skipped) {
  testpieces::MeasuredObservations kept;
  std::map<int, int> group_map;
  for (std::size_t i = 0; i < mo.observations.size(); ++i) {
    const auto& o = mo.observations[i];
    const std::size_t pi = mo.point_index[i];
    const long match = matching->match[i];
    if (match < 0) {
      ++matching->summary.unmatched;
      skipped->push_back(Status(StatusCode::kInvalidArgument, "no reference point of feature " +
                                                           mo.feature_names[static_cast<std::size_t>(o.group)] +
                                                           fmt::format(" within {} mm of its nominal position", tol_mm))
                             .WithLocation(measured.source, measured.LineOf(pi))
                             .ToString());
      continue;
    }
    auto [g, inserted] = group_map.try_emplace(o.group, static_cast<int>(kept.feature_names.size()));
    if (inserted) kept.feature_names.push_back(mo.feature_names[static_cast<std::size_t>(o.group)]);
    kinematics::Observation ok = o;
    ok.group = g->second;
    kept.observations.push_back(ok);
    kept.point_index.push_back(pi);
    dev->push_back(ref_dev_um(static_cast<Eigen::Index>(match)));
  }
  return kept;
}

}  // namespace tpcal::pipeline::diagnosis_internal
