// Noisy probing: Table 1 characteristics stay unbiased and scatter as the geometry predicts.
// Truth: gdt/testing/turning_piece.h with its default errors. Each trial adds independent
// Gaussian noise sigma = 0.5 um to every coordinate and places the piece anywhere on the CMM.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/units.h"
#include "gdt/inspection.h"
#include "gdt/plan_yaml.h"
#include "gdt/synthetic.h"
#include "gdt/testing/turning_piece.h"

namespace tpcal::gdt {
namespace {

constexpr double kSigma_mm = 0.0005;  // CMM probing noise, 0.5 um per coordinate
constexpr int kTrials = 300;

struct Stats {
  double mean = 0, sd = 0;
};
Stats Summarise(const std::vector<double>& v) {
  Stats s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.sd += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(s.sd / static_cast<double>(v.size() - 1));
  return s;
}

TEST(NoisyTurningPiece, Table1ValuesAreUnbiasedWithThePredictedScatter) {
  auto plan = LoadInspectionPlan(std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const testing::TurningTruth truth;
  const PointSet part = testing::MakeTurningPiece(truth);
  std::mt19937_64 rng(314159);
  std::normal_distribution<double> noise(0.0, kSigma_mm);
  std::vector<double> dx5, dy5, da2, err3;
  for (int trial = 0; trial < kTrials; ++trial) {
    PointSet noisy = part;
    for (auto& p : noisy.xyz_mm)
      for (int i = 0; i < 3; ++i) p(i) += noise(rng);
    auto r = EvaluatePlan(*plan, Transformed(noisy, RandomPlacement(rng, 1000.0)));
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const CharacteristicResult* c5 = r->Characteristic("t5_concentricity_S4_SR");
    dx5.push_back(*c5->Value("dx_um"));
    dy5.push_back(*c5->Value("dy_um"));
    da2.push_back(*r->Characteristic("t2_parallelism_B1_BR")->Value("da_urad"));
    err3.push_back(*r->Characteristic("t3_distance_B3_BR")->Value("error_um"));
  }
  // Predicted standard deviations (16 points evenly on each circle / ring):
  //  - LS circle centre, per axis: sigma sqrt(2/n); #5 differences two centres: sigma sqrt(4/n),
  //    plus the datum Z axis's tilt (B_R's LS normal, per axis sigma sqrt(2/(n R_BR^2))) acting
  //    on the 247.5 mm between S_R (z = +2.5) and S4 (z = -245): the projection into the datum
  //    XY plane moves S4's centre by 247.5 mm x tilt. That term (0.38 um) exceeds the fit term
  //    (0.25 um): the datum plane's orientation dominates this concentricity.
  //  - LS plane slope over a ring of radius R: sigma sqrt(2/(n R^2)); #2 differences B1 (R 163 mm)
  //    and B_R (R 114 mm), which defines Z.
  //  - #3: B3's height at its centroid and B_R's (their centroids are both on the Z axis):
  //    sigma sqrt(1/n + 1/n).
  const double n = 16;
  const double lever_mm = testing::kZSR - testing::kZ4;
  const double r_br = testing::kRBR, r_b1 = testing::kRB1;
  const double sd5_um = MmToUm(kSigma_mm * std::sqrt(4 / n + lever_mm * lever_mm * 2 / (n * r_br * r_br)));
  const double sd2_urad = RadToUrad(kSigma_mm * std::sqrt(2 / (n * r_b1 * r_b1) + 2 / (n * r_br * r_br)));
  const double sd3_um = MmToUm(kSigma_mm * std::sqrt(2 / n));
  const Eigen::Vector2d c5 = truth.InD(truth.s4_shift_mm) * kUmPerMm;
  const Eigen::Vector3d nb1 =
      RotZ(-truth.Phi()) * RotX(truth.b1_about_x_rad) * RotY(truth.b1_about_y_rad) * Eigen::Vector3d::UnitZ();
  const double da_true = RadToUrad(std::atan2(-nb1.y(), nb1.z()));
  // Mean within 4 standard errors; sample sd within 4 of its standard errors (sd / sqrt(2 N)).
  const double k_mean = 4 / std::sqrt(kTrials), k_sd = 4 / std::sqrt(2.0 * kTrials);
  const struct {
    const char* what;
    std::vector<double>* v;
    double truth, sd;
  } checks[] = {{"#5 dx", &dx5, c5.x(), sd5_um},
                {"#5 dy", &dy5, c5.y(), sd5_um},
                {"#2 da", &da2, da_true, sd2_urad},
                {"#3 error", &err3, 23.0, sd3_um}};
  for (const auto& c : checks) {
    const Stats s = Summarise(*c.v);
    EXPECT_NEAR(s.mean, c.truth, k_mean * c.sd) << c.what;
    EXPECT_NEAR(s.sd, c.sd, k_sd * c.sd) << c.what << " predicted sd " << c.sd;
  }
}

}  // namespace
}  // namespace tpcal::gdt
