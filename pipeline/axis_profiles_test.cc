// Error-motion and straightness profiles from simulated pieces whose error motions are known.
// Truths: a C-axis radial error motion E_XC at A = 0 (2nd and 3rd harmonics, 2 and 1 um) on the
// turning piece; a quadratic straightness E_YX of X (and the squareness E_C(0X)Y) on the ISO
// 10791-7 M1 piece. Noise-free simulations: the tolerances cover first-order modelling only
// (second-order terms < 1e-3 um at these magnitudes) and profile interpolation between probed
// angles (0.02 um).
#include "pipeline/axis_profiles.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/piece_loader.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

TEST(AxisProfiles, CRadialErrorMotionAtA0FromS1AndS4) {
  auto setup = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  kinematics::ErrorState errors(setup->machine);
  kinematics::ErrorTerm radial;
  radial.kind = kinematics::TermKind::kFourier;
  radial.label = "E_XC@A=0";
  radial.effects = {{kinematics::Axis::kC, kinematics::Component::kTx, 1.0}};
  radial.condition.axis = kinematics::Axis::kA;  // A = 0 (condition value default)
  radial.argument = kinematics::Axis::kC;
  radial.orders = {2, 3};
  radial.is_sine = {false, true};
  radial.coefficients = {2e-3, 1e-3};  // mm
  ASSERT_TRUE(errors.AddTerm(setup->machine, radial).ok());
  testpieces::PieceConfig dense = setup->piece.config;
  dense.probing.points_per_circle = 72;
  auto piece = testpieces::MakeTestPiece(dense, setup->machine);
  ASSERT_TRUE(piece.ok()) << piece.status().ToString();
  testpieces::PieceSimOptions o;
  o.random_placement = true;
  o.seed = 4;
  auto sim = testpieces::SimulatePiece(*piece, setup->machine, errors, o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  auto stage = RunIdentifyStage(*piece, setup->machine, sim->points);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  auto motions = CAxisErrorMotions(*piece, *stage);
  ASSERT_TRUE(motions.ok()) << motions.status().ToString();
  ASSERT_EQ(motions->size(), 2u);
  const auto& a0 = (*motions)[0];
  EXPECT_EQ(a0.name, "C at A=0");
  // The table displaced +X toward the tool removes material: dr = -E_XC(C); the profile reports
  // the motion itself (harmonics >= 2 survive the circle fit).
  double max_err = 0.0, max_val = 0.0;
  for (std::size_t k = 0; k < a0.profile.c_deg.size(); ++k) {
    const double c = a0.profile.c_deg[k] * M_PI / 180.0;
    const double expected_um = 2.0 * std::cos(2 * c) + 1.0 * std::sin(3 * c);
    max_err = std::max(max_err, std::abs(a0.profile.radial_um[k] - expected_um));
    max_val = std::max(max_val, std::abs(expected_um));
    EXPECT_NEAR(a0.profile.tilt_urad[k], 0.0, 0.05) << "C " << a0.profile.c_deg[k];
  }
  EXPECT_LT(max_err, 0.02) << "largest profile error, um";
  EXPECT_GT(max_val, 2.0);
  EXPECT_NEAR(a0.profile.radial_pv_um, 2 * 2.0 + 0.0, 1.5);  // P-V of 2 cos 2C + sin 3C is 5.5 at most
  // A = -90: no error motion there.
  const auto& a90 = (*motions)[1];
  for (double r : a90.profile.radial_um) EXPECT_NEAR(r, 0.0, 0.02);
}

TEST(AxisProfiles, StraightnessOfXFromTheM1SideFaces) {
  auto setup = LoadPiece({.testpiece = "iso10791_m1_160"});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  kinematics::ErrorState errors(setup->machine);
  ASSERT_TRUE(errors.SetParameter(setup->machine, "E_C(0X)Y", 20e-6).ok());
  kinematics::ErrorTerm straight;
  straight.kind = kinematics::TermKind::kPolynomial;
  straight.label = "E_YX";
  straight.effects = {{kinematics::Axis::kX, kinematics::Component::kTy, 1.0}};
  straight.argument = kinematics::Axis::kX;
  straight.powers = {2};
  straight.coefficients = {1e-6};  // mm per mm^2: 6.4 um at 80 mm
  ASSERT_TRUE(errors.AddTerm(setup->machine, straight).ok());
  testpieces::PieceSimOptions o;
  o.random_placement = true;
  o.seed = 8;
  auto sim = testpieces::SimulatePiece(setup->piece, setup->machine, errors, o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  auto stage = RunIdentifyStage(setup->piece, setup->machine, sim->points);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  // Squareness identified (within 0.5 urad: the quadratic is orthogonal to a line only on a
  // symmetric range, so part of it can tilt the fit).
  for (const auto& p : stage->identification.parameters)
    if (p.name == "E_C(0X)Y") {
      EXPECT_TRUE(p.identifiable);
    }
  auto profiles = LinearAxisStraightness(setup->piece, *stage);
  ASSERT_TRUE(profiles.ok()) << profiles.status().ToString();
  int seen = 0;
  for (const auto& s : *profiles) {
    if (s.name != "E_YX") continue;
    ++seen;
    // Truth: 1e-6 x^2 mm with its LS line over the face's X positions removed, in um.
    const std::size_t n = s.position_mm.size();
    double mx = 0, my = 0;
    std::vector<double> y(n);
    for (std::size_t k = 0; k < n; ++k) {
      y[k] = 1e-3 * s.position_mm[k] * s.position_mm[k];
      mx += s.position_mm[k];
      my += y[k];
    }
    mx /= n;
    my /= n;
    double sxx = 0, sxy = 0;
    for (std::size_t k = 0; k < n; ++k) {
      sxx += (s.position_mm[k] - mx) * (s.position_mm[k] - mx);
      sxy += (s.position_mm[k] - mx) * (y[k] - my);
    }
    double lo = 1e9, hi = -1e9;
    for (std::size_t k = 0; k < n; ++k) {
      const double d = y[k] - my - sxy / sxx * (s.position_mm[k] - mx);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
      // The sign: ISO 230-1 E_YX is the Y error motion of the X carriage; on this machine the X
      // carriage carries the tool side, so the face follows +E_YX (deviation along +Y).
      EXPECT_NEAR(std::abs(s.deviation_um[k]), std::abs(d), 0.02) << s.feature << " at X " << s.position_mm[k];
    }
    EXPECT_NEAR(s.pv_ls_um, hi - lo, 0.03) << s.feature;
    EXPECT_LE(s.mz_um, s.pv_ls_um + 1e-9) << s.feature;
    EXPECT_GT(s.pv_ls_um, 0.5) << s.feature;
  }
  EXPECT_GE(seen, 2) << "the M1 faces along X";
}

}  // namespace
}  // namespace tpcal::pipeline
