// What `tpcal identify BALLBAR --instrument ballbar` writes: the tpcal.identification/1 JSON
// (docs/formats/identify_json.md, section "Ball bar") and the text summary of a double-ball-bar
// test: per rotary axis the six error motions at each measured angle with u and what the
// installations cannot separate (kinematics/ballbar_identification.h), per ISO 230-4 circle the
// figures of the circular test (kinematics/circular_test_analysis.h).
#pragma once

#include <string>
#include <vector>

#include "kinematics/ballbar_identification.h"
#include "kinematics/circular_test_analysis.h"

namespace tpcal::pipeline {

// One rotary axis: the identification from every installation that turns it.
struct BallbarAxisReport {
  explicit BallbarAxisReport(kinematics::BallbarIdentification r) : result(std::move(r)) {}
  std::string axis;                        // "C", "B", "A"
  std::vector<std::string> installations;  // names, index order of the identification
  std::vector<std::size_t> lines;          // source line of each reading, the result's order
  kinematics::BallbarIdentification result;
  // With BallbarRequest::map_response_to: the maps a unit of each of those errors would give
  // (entries x names, display units; kinematics::BallbarMapResponse), and the names kept.
  std::vector<std::string> response_to;
  Eigen::MatrixXd map_response;
};

// One circular test of two linear axes (an installation of kind circle).
struct BallbarCircleReport {
  std::string installation;
  std::vector<std::size_t> lines;  // source line of each reading, the result's order
  kinematics::CircularTestResult result;
};

struct BallbarReport {
  std::string source;        // the ball-bar file
  std::string setup_source;  // the set-up YAML
  std::string machine;       // machine type name
  int readings = 0;
  std::vector<BallbarAxisReport> axes;       // in the order the axes first appear in the file
  std::vector<BallbarCircleReport> circles;  // in the order the installations first appear
  // tpcal.errors/1 (kinematics/errors_yaml.md) of the rotary axes' tables, for `simulate --errors`
  // and `diagnose --reference`; comments state the convention and the entries left at 0 because
  // the installations cannot determine them. Empty when there is no rotary installation.
  std::string errors_yaml;
};

std::string BallbarJson(const BallbarReport& report);
std::string BallbarText(const BallbarReport& report);

}  // namespace tpcal::pipeline
