// Test support (tests and studies only): the seed 002 turning piece on the nominal A/C table and
// random Table 2 error sets, as the identification tests and studies use them.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

#include "core/point_set.h"
#include "kinematics/identification.h"

#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline::test_support {

inline kinematics::MachineModel AcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

// The default (seed 002) turning piece, built once.
inline const testpieces::TestPiece& Turning() {
  static const testpieces::TestPiece piece = [] {
    auto p = testpieces::MakeTestPiece(testpieces::PieceConfig{}, AcTable());
    EXPECT_TRUE(p.ok()) << p.status().ToString();
    return *p;
  }();
  return piece;
}

// Random Table 2 errors and X-Y squareness E_C(0X)Y (the turning piece's identification set):
// magnitude U(10, 50) um or urad, random sign (display units).
inline std::map<std::string, double> RandomTable2(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mag(10.0, 50.0);
  std::bernoulli_distribution sign(0.5);
  std::map<std::string, double> truth;
  auto draw = [&] {
    const double s = sign(rng) ? 1.0 : -1.0;  // drawn before the magnitude under every compiler
    return s * mag(rng);
  };
  for (const auto& name : kinematics::Seed002Set(AcTable())) truth[name] = draw();
  truth["E_C(0X)Y"] = draw();
  return truth;
}

// Catalog parameters in display units (um, urad) as an ErrorState (mm, rad).
inline kinematics::ErrorState ToErrorState(const std::map<std::string, double>& display) {
  const auto machine = AcTable();
  kinematics::ErrorState errors(machine);
  for (const auto& [name, value] : display) {
    auto info = kinematics::LookupParameter(machine, name);
    EXPECT_TRUE(info.ok()) << name;
    const double internal = info->quantity == kinematics::Quantity::kAngle ? value * 1e-6 : value * 1e-3;
    EXPECT_TRUE(errors.SetParameter(machine, name, internal).ok()) << name;
  }
  return errors;
}

// 1 % of the points (at least 1) pushed along their normal by 10-50 sigma, random sign (issue 18's
// gross outliers); returns their indices.
inline std::set<std::size_t> AddGrossOutliers(PointSet* points, double sigma_um, std::mt19937_64& rng) {
  const std::size_t m = std::max<std::size_t>(1, points->size() / 100);
  std::uniform_int_distribution<std::size_t> pick(0, points->size() - 1);
  std::uniform_real_distribution<double> size(10.0, 50.0);
  std::set<std::size_t> chosen;
  while (chosen.size() < m) chosen.insert(pick(rng));
  for (std::size_t i : chosen) {
    const double sign = rng() % 2 ? 1.0 : -1.0;  // drawn before the size under every compiler
    points->xyz_mm[i] += 1e-3 * sign * size(rng) * sigma_um * points->normal[i];
  }
  return chosen;
}

// Largest |value - reference| / u_reference over the identifiable parameters.
inline double LargestShiftInU(const kinematics::IdentificationResult& reference,
                              const kinematics::IdentificationResult& other) {
  double worst = 0.0;
  for (std::size_t k = 0; k < reference.parameters.size(); ++k) {
    const auto& p = reference.parameters[k];
    if (p.identifiable && p.u > 0) worst = std::max(worst, std::abs(other.parameters[k].value - p.value) / p.u);
  }
  return worst;
}

}  // namespace tpcal::pipeline::test_support
