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

}  // namespace tpcal::pipeline
