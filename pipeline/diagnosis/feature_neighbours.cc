#include "pipeline/diagnosis/feature_neighbours.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <map>

#include "core/parallel.h"

namespace tpcal::pipeline {
namespace {

// The k nearest of one group's points (indices into the group), by PCL's kd-tree (FLANN).
void NeighboursInGroup(std::span<const kinematics::Observation> obs, const std::vector<int>& members, int k,
                       std::vector<std::vector<int>>* out) {
  const int m = static_cast<int>(members.size());
  if (m < 2) return;
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(members.size());
  for (int i : members) {
    const Eigen::Vector3d& p = obs[static_cast<std::size_t>(i)].cut.nominal_point_mm;
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  const int want = std::min(k + 1, m);  // the point itself comes back too
  std::vector<int> idx;
  std::vector<float> d2;
  for (int a = 0; a < m; ++a) {
    idx.clear();
    tree.nearestKSearch((*cloud)[static_cast<std::size_t>(a)], want, idx, d2);
    auto& list = (*out)[static_cast<std::size_t>(members[static_cast<std::size_t>(a)])];
    for (int b : idx)
      if (b != a && static_cast<int>(list.size()) < k) list.push_back(members[static_cast<std::size_t>(b)]);
  }
}

}  // namespace

std::vector<std::vector<int>> FeatureNeighbours(std::span<const kinematics::Observation> observations, int k) {
  std::vector<std::vector<int>> out(observations.size());
  std::map<int, std::vector<int>> by_group;
  for (std::size_t i = 0; i < observations.size(); ++i) by_group[observations[i].group].push_back(static_cast<int>(i));
  std::vector<const std::vector<int>*> groups;
  for (const auto& [group, members] : by_group) groups.push_back(&members);
  // Groups write disjoint entries of `out` (a diagnosis screens 4 times).
  ParallelForEach(groups.size(), observations.size() >= kParallelMinPoints,
                  [&](std::size_t g) { NeighboursInGroup(observations, *groups[g], k, &out); });
  return out;
}

}  // namespace tpcal::pipeline
