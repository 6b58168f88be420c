// Nearest neighbours of each measured point among the points of its own feature, by nominal
// position (part frame): the local comparison of the outlier screen (outlier_screen.h).
#pragma once

#include <span>
#include <vector>

#include "kinematics/identification.h"

namespace tpcal::pipeline {

// For every observation, the indices (into `observations`) of up to `k` nearest other
// observations of the same group (Observation::group), nearest first, by the distance between
// their nominal points (CutPoint::nominal_point_mm). A group of one point gives an empty list.
// k must be >= 1.
std::vector<std::vector<int>> FeatureNeighbours(std::span<const kinematics::Observation> observations, int k);

// FeatureNeighbours of one set of observations, kept to be screened again (the identification's
// screen and the diagnosis's screens of the same observations; 0.25 s for 2e5 scan cells).
struct FeatureNeighbourGraph {
  int k = 0;
  std::vector<std::vector<int>> lists;
  // Whether it can be the graph of n observations at k neighbours (the caller vouches that they
  // are the same observations).
  bool Fits(std::size_t n, int k_wanted) const { return k == k_wanted && lists.size() == n; }
};

}  // namespace tpcal::pipeline
