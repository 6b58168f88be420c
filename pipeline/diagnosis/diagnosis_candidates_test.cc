#include "kinematics/slot_linearisation.h"

#include <gtest/gtest.h>

#include "kinematics/errors_yaml.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

// The slot chain rule against the direct autodiff Jacobian of every candidate coefficient.
// Zero errors: the basis is evaluated exactly where the solve lands, so the columns agree to
// rounding (1e-9 of the column scale). Table 2 errors (tens of um / urad): the basis is taken at
// the nominal sweep position, a relative change of order 1e-4; 1e-3 of the column norm allows it.
void CompareColumns(const std::string& yaml, double rel_tol) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  auto piece = testpieces::MakeTestPiece(testpieces::PieceConfig{}, *m);
  ASSERT_TRUE(piece.ok());
  auto plan = testpieces::MakeProbingPlan(*piece);
  ASSERT_TRUE(plan.ok());
  std::vector<kinematics::Observation> obs;
  for (const auto& pp : plan->points) obs.push_back({pp.cut, pp.point_part_mm, 0});
  auto errors = kinematics::ParseErrorState(
      yaml + "effects:\n"
             "  - thermal_drift: {parameter: E_Y0A, K_um: 0, tau_s: 1500}\n"
             "  - linear_error_motion: {symbol: E_ZX, coefficients_um_per_mm_pow: [0, 0, 0]}\n"
             "  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 2, cos_um: 0, sin_um: 0}]}\n"
             "  - rotary_error_motion: {symbol: E_CC, harmonics: [{order: 1, cos_urad: 0, sin_urad: 0}]}\n",
      "<test>", *m);
  ASSERT_TRUE(errors.ok()) << errors.status().message();
  const kinematics::ActiveSet all = kinematics::AllCoefficients(*errors);
  auto direct = kinematics::LineariseObservations(*m, *errors, all, obs);
  ASSERT_TRUE(direct.ok());
  auto slots = kinematics::LineariseBySlots(*m, *errors, all.coefficients, obs);
  ASSERT_TRUE(slots.ok()) << slots.status().message();
  ASSERT_EQ(slots->J_dev_params.cols(), direct->J_dev_params.cols());
  for (Eigen::Index j = 0; j < direct->J_dev_params.cols(); ++j) {
    const double scale = direct->J_dev_params.col(j).norm();
    EXPECT_LE((slots->J_dev_params.col(j) - direct->J_dev_params.col(j)).norm(), rel_tol * scale + 1e-12)
        << errors->coefficient_info(all.coefficients[static_cast<std::size_t>(j)]).name;
  }
  EXPECT_LE((slots->predicted_dev_um - direct->predicted_dev_um).norm(), 1e-9);
}

TEST(DiagnosisCandidates, SlotChainRuleEqualsDirectJacobianAtZeroErrors) { CompareColumns("", 1e-9); }

TEST(DiagnosisCandidates, SlotChainRuleCloseToDirectJacobianAtTable2Errors) {
  CompareColumns("dx_CR(0)_um: 12.4\ndy_CR(0)_um: -16.8\nalpha_CR(0)_urad: -8.7\ndy_AR(-90)_um: 36.5\n"
                 "dz_AR(-90)_um: 28.6\nalpha_CR(-90)_urad: 36.7\nalpha_ZY_urad: 19.2\n",
                 1e-3);
}

}  // namespace
}  // namespace tpcal::pipeline
