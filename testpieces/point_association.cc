#include "testpieces/point_association.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <utility>

#include "core/parallel.h"

namespace tpcal::testpieces {
namespace {

// Group (index into feature_names) of every point, numbered by first appearance in the file.
// Errors: an unlabelled point, a feature the piece does not have (file:line).
Status GroupPoints(const TestPiece& piece, const PointSet& measured, std::vector<int>* group,
                   std::vector<std::string>* feature_names) {
  std::map<int, int> group_of_label;  // PointSet feature index -> group
  group->resize(measured.size());
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const int label = measured.feature.empty() ? PointSet::kUnlabelled : measured.feature[i];
    if (label == PointSet::kUnlabelled)
      return Status(StatusCode::kInvalidArgument,
                    "point without a feature label: identification needs labelled points (segment raw scans first)",
                    measured.source, measured.LineOf(i));
    auto [it, inserted] = group_of_label.try_emplace(label, static_cast<int>(feature_names->size()));
    if (inserted) {
      const std::string& name = measured.feature_names[static_cast<std::size_t>(label)];
      if (!piece.Feature(name))
        return Status(StatusCode::kInvalidArgument, "feature '" + name + "' is not a feature of the " + piece.name,
                      measured.source, measured.LineOf(i));
      feature_names->push_back(name);
    }
    (*group)[i] = it->second;
  }
  return Status::Ok();
}

// Drops the unreached points (reached[i] == 0) and renumbers the groups by first appearance of
// a kept point.
MeasuredObservations KeepReached(MeasuredObservations all, const std::vector<char>& reached) {
  MeasuredObservations kept;
  std::map<int, int> group_map;
  for (std::size_t i = 0; i < all.observations.size(); ++i) {
    if (!reached[i]) continue;
    kinematics::Observation o = all.observations[i];
    auto [g, inserted] = group_map.try_emplace(o.group, static_cast<int>(kept.feature_names.size()));
    if (inserted) kept.feature_names.push_back(all.feature_names[static_cast<std::size_t>(o.group)]);
    o.group = g->second;
    kept.observations.push_back(o);
    kept.point_index.push_back(all.point_index[i]);
  }
  return kept;
}

}  // namespace

Result<MeasuredObservations> AssociatePoints(const TestPiece& piece, const PointSet& measured,
                                             const Rigid3& datum_from_cmm, UnreachedPoint unreached,
                                             std::vector<std::string>* skipped) {
  MeasuredObservations out;
  std::vector<int> group;
  TPCAL_RETURN_IF_ERROR(GroupPoints(piece, measured, &group, &out.feature_names));
  std::vector<const NominalFeature*> nominal;  // per group, looked up once
  std::vector<const FeatureCut*> cut_of;
  for (const std::string& name : out.feature_names) {
    nominal.push_back(piece.Feature(name));
    cut_of.push_back(piece.Cut(name));
  }
  // The cut of every point on all cores (each point its own slot).
  const std::size_t n = measured.size();
  out.observations.resize(n);
  out.point_index.resize(n);
  std::vector<std::pair<std::size_t, Status>> failures;  // (point, why), few
  std::mutex failures_mutex;
  std::vector<char> reached(n, 1);
  ParallelChunks(n, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto g = static_cast<std::size_t>(group[i]);
      const Eigen::Vector3d p_datum = datum_from_cmm * measured.xyz_mm[i];
      auto cut = cut_of[g] ? CutPointAtDatum(piece, *nominal[g], *cut_of[g], p_datum)
                           : CutPointAtDatum(piece, out.feature_names[g], p_datum);  // its error
      if (!cut.ok()) {
        reached[i] = 0;
        {
          std::lock_guard<std::mutex> lock(failures_mutex);
          failures.emplace_back(i, cut.status().WithLocation(measured.source, measured.LineOf(i)));
        }
        if (unreached == UnreachedPoint::kFail) return false;
        continue;
      }
      kinematics::Observation& o = out.observations[i];
      o.cut = *cut;
      o.measured_mm = piece.part_from_datum * p_datum;
      o.group = group[i];
      out.point_index[i] = i;
    }
    return true;
  });
  if (failures.empty()) return out;
  std::sort(failures.begin(), failures.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  if (unreached == UnreachedPoint::kFail) return failures.front().second;  // the first in file order
  if (skipped)
    for (const auto& f : failures) skipped->push_back(f.second.ToString());
  return KeepReached(std::move(out), reached);
}

}  // namespace tpcal::testpieces
