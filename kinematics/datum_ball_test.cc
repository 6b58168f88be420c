// The datum-ball test (kinematics/datum_ball.h) on the nominal B/C table of seed 001 and on the
// A/C table. Truth: seed 001 Table 1(a)'s assumed errors (its 11 symbols mapped to ISO 230-1 names
// below), the ball 200 mm from the C axis and 100 mm above the table, readings at B = 0 and
// +-30 deg (A on the A/C table) with C every 30 deg (36 readings). Tolerances: noise-free, the
// Gauss-Newton solution reproduces the truth to 1e-3 um / urad (the Newton centring stops at
// 1e-9 mm = 1e-6 um); with 1 um noise (seed 11) every error lies within 4 u of its truth.
#include "kinematics/datum_ball.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics {
namespace {

// Seed 001 Table 1(a), assumed errors (um, urad) under ISO 230-1 names: alpha_YZ = E_A(0Y)Z,
// beta_XZ = E_B(0X)Z, gamma_XY = E_C(0X)Y, alpha_ZB = E_A0B, gamma_XB = E_C0B, delta_XB = E_X0B,
// delta_ZB = E_Z0B, alpha_YC = E_A0C, beta_XC = E_B0C, delta_XC = E_X0C, delta_YC = E_Y0C.
const std::map<std::string, double> kTable1a = {
    {"E_A(0Y)Z", -34.0}, {"E_B(0X)Z", 29.0}, {"E_C(0X)Y", 17.0}, {"E_A0B", -17.0}, {"E_C0B", 75.0}, {"E_X0B", -12.0},
    {"E_Z0B", 19.0},     {"E_A0C", -87.0},   {"E_B0C", 42.0},    {"E_X0C", 10.0},  {"E_Y0C", -15.0}};

MachineModel BallMachine(MachineType type) {
  auto m = MakeMachine(type);
  EXPECT_TRUE(m.ok());
  return *m;
}

ErrorState BallTruth(const MachineModel& m, const std::map<std::string, double>& display) {
  ErrorState e(m);
  for (const auto& [name, v] : display) {
    auto info = LookupParameter(m, name);
    EXPECT_TRUE(info.ok()) << name;
    const bool angle = info.ok() && info->quantity == Quantity::kAngle;
    EXPECT_TRUE(e.SetParameter(m, name, angle ? v * 1e-6 : UmToMm(v)).ok()) << name;
  }
  return e;
}

// Readings at tilt = 0, +-30 deg (B or A) and C every 30 deg, with noise sigma_um (seed).
std::vector<BallReading> BallReadings(const MachineModel& m, const ErrorState& truth, double sigma_um, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_um);
  const Eigen::Vector3d ball(200.0, 0.1, 100.0);
  std::vector<BallReading> out;
  for (double tilt : {0.0, 30.0, -30.0})
    for (int c = 0; c < 360; c += 30) {
      BallReading r;
      (m.HasAxis(Axis::kB) ? r.rotary.b_rad : r.rotary.a_rad) = DegToRad(tilt);
      r.rotary.c_rad = DegToRad(c);
      auto cmd = BallCentreCommand(m, truth, r.rotary, ball);
      EXPECT_TRUE(cmd.ok()) << cmd.status().ToString();
      r.command_mm = *cmd + UmToMm(1.0) * Eigen::Vector3d{noise(rng), noise(rng), noise(rng)};
      r.line = out.size() + 4;
      out.push_back(r);
    }
  return out;
}

TEST(DatumBall, CentringAtZeroErrorsIsTheNominalChain) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  AxisState rotary;
  rotary.b_rad = DegToRad(30), rotary.c_rad = DegToRad(120);
  const Eigen::Vector3d ball(200.0, 0.1, 100.0);
  auto cmd = BallCentreCommand(m, ErrorState(m), rotary, ball);
  ASSERT_TRUE(cmd.ok()) << cmd.status().ToString();
  AxisState at = rotary;
  at.x_mm = cmd->x(), at.y_mm = cmd->y(), at.z_mm = cmd->z();
  EXPECT_LT((NominalToolPointInPart(m, at, Eigen::Vector3d::Zero()) - ball).norm(), 1e-9);
}

TEST(DatumBall, Seed001Table1aIsRecoveredExactlyWithoutNoise) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  const auto readings = BallReadings(m, BallTruth(m, kTable1a), 0.0, 1);
  auto r = IdentifyDatumBall(m, readings);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_TRUE(r->identifiability.not_identifiable.empty());
  ASSERT_EQ(r->parameters.size(), kTable1a.size());
  for (const auto& p : r->parameters) {
    EXPECT_TRUE(p.identifiable) << p.name;
    EXPECT_NEAR(p.value, kTable1a.at(p.name), 1e-3) << p.name;
  }
  EXPECT_LT((r->ball_part_mm - Eigen::Vector3d(200.0, 0.1, 100.0)).norm(), 1e-6);
  EXPECT_LT(r->rms_after_um, 1e-4);
}

// Seed 001 Table 1(b): 1000 arbitrary error sets (here uniform +-100 um / urad each, seed 2026),
// noise-free readings, identified: the mean and standard deviation of estimated - assumed per
// error (printed; README "Datum ball" puts them beside the paper's). The paper's explicit
// equations leave 0.002 to 0.043 um / urad (its first-order model); the exact chain solved by
// Gauss-Newton leaves rounding: every difference below 1e-3.
TEST(DatumBall, Seed001Table1bThousandRandomSets) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> draw(-100.0, 100.0);
  std::map<std::string, std::vector<double>> diff;
  for (int trial = 0; trial < 1000; ++trial) {
    std::map<std::string, double> truth;
    for (const auto& [name, v] : kTable1a) truth[name] = draw(rng);
    auto r = IdentifyDatumBall(m, BallReadings(m, BallTruth(m, truth), 0.0, 1));
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    for (const auto& p : r->parameters) diff[p.name].push_back(p.value - truth.at(p.name));
  }
  for (const auto& [name, d] : diff) {
    double mean = 0.0, ss = 0.0, worst = 0.0;
    for (double x : d) mean += x / static_cast<double>(d.size()), worst = std::max(worst, std::abs(x));
    for (double x : d) ss += (x - mean) * (x - mean);
    std::printf("%-10s mean %+.2e std %.2e\n", name.c_str(), mean, std::sqrt(ss / static_cast<double>(d.size() - 1)));
    EXPECT_LT(worst, 1e-3) << name;
  }
}

TEST(DatumBall, NoisyReadingsGiveTheTruthWithinTheirUncertainty) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  auto r = IdentifyDatumBall(m, BallReadings(m, BallTruth(m, kTable1a), 1.0, 11));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_NEAR(r->sigma_um, 1.0, 0.3);  // 108 values less 14 unknowns
  for (const auto& p : r->parameters) {
    EXPECT_LT(std::abs(p.value - kTable1a.at(p.name)), 4.0 * p.u) << p.name << " " << p.value << " +- " << p.u;
    ASSERT_EQ(p.uncertainties.size(), 3u);  // analytic, jackknife_points, monte_carlo
    EXPECT_GT(p.uncertainties[1].u, 0.5 * p.u) << p.name;  // jackknife beside analytic
    EXPECT_LT(p.uncertainties[1].u, 2.0 * p.u) << p.name;
  }
}

const Uncertainty& MethodU(const ParameterEstimate& p, UncertaintyMethod m) {
  for (const auto& u : p.uncertainties)
    if (u.method == m) return u;
  ADD_FAILURE() << p.name << ": no " << UncertaintyMethodName(m);
  return p.uncertainties.front();
}

// Monte Carlo u against analytic u: both describe the same linearised map under the fitted sigma,
// so their ratio is 1 up to the sampling error of a standard deviation from n draws, relative sd
// 1 / sqrt(2 (n - 1)): 2000 runs, 4 sd = 0.063.
TEST(DatumBall, MonteCarloAgreesWithAnalyticWithinSamplingError) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  DatumBallOptions options;
  options.monte_carlo_runs = 2000;
  auto r = IdentifyDatumBall(m, BallReadings(m, BallTruth(m, kTable1a), 1.0, 11), options);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->monte_carlo_runs, 2000);
  const double tol = 4.0 / std::sqrt(2.0 * (2000 - 1));
  double lo = INFINITY, hi = 0.0;
  for (const auto& p : r->parameters) {
    const Uncertainty& mc = MethodU(p, UncertaintyMethod::kMonteCarlo);
    ASSERT_TRUE(mc.available) << p.name;
    lo = std::min(lo, mc.u / p.u), hi = std::max(hi, mc.u / p.u);
    EXPECT_NEAR(mc.u / p.u, 1.0, tol) << p.name << " mc " << mc.u << " analytic " << p.u;
    EXPECT_LT(mc.ci95_low, p.value);
    EXPECT_GT(mc.ci95_high, p.value);
  }
  std::printf("Monte Carlo / analytic u, 2000 runs: %.3f to %.3f (tolerance 1 +- %.3f)\n", lo, hi, tol);
}

// The Monte Carlo runs re-identify by the map linearised at the solution. Redone here in full
// (Gauss-Newton through the chain on each re-simulated reading set, the same draws:
// std::mt19937_64(seed), StandardNormal, run by run, reading by reading, x, y, z), the spread of
// the re-identified values is the same: the chain is linear in the errors over micrometre noise
// (second-order terms ~ 300 mm x 1e-4 rad x 1e-6 rad ~ 3e-5 um), so 1e-3 um / urad is a margin.
TEST(DatumBall, MonteCarloLinearisedMapIsTheFullReidentification) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  const auto readings = BallReadings(m, BallTruth(m, kTable1a), 1.0, 11);
  DatumBallOptions options;
  options.monte_carlo_runs = 20;
  options.monte_carlo_seed = 7;
  auto r = IdentifyDatumBall(m, readings, options);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::mt19937_64 rng(7);
  DatumBallOptions plain;
  plain.jackknife = false, plain.monte_carlo_runs = 0;
  std::vector<std::vector<double>> deviations(r->parameters.size());
  for (int run = 0; run < 20; ++run) {
    std::vector<BallReading> again = readings;
    for (std::size_t i = 0; i < again.size(); ++i)
      for (int c = 0; c < 3; ++c)
        again[i].command_mm(c) += UmToMm(-r->residuals_um[i](c) + r->sigma_um * StandardNormal(rng));
    auto ri = IdentifyDatumBall(m, again, plain);
    ASSERT_TRUE(ri.ok()) << ri.status().ToString();
    for (std::size_t k = 0; k < r->parameters.size(); ++k)
      deviations[k].push_back(ri->parameters[k].value - r->parameters[k].value);
  }
  double worst = 0.0;
  for (std::size_t k = 0; k < r->parameters.size(); ++k) {
    const ParameterEstimate& p = r->parameters[k];
    const Uncertainty full = MonteCarloUncertainty(p.value, deviations[k]);
    worst = std::max(worst, std::abs(full.u - MethodU(p, UncertaintyMethod::kMonteCarlo).u));
    EXPECT_NEAR(full.u, MethodU(p, UncertaintyMethod::kMonteCarlo).u, 1e-3) << p.name;
  }
  std::printf("Monte Carlo u, linearised map vs full re-identification: worst difference %.1e um / urad\n", worst);
}

// Weights: one reading (C = 90 deg at B = 0) 30 um off in each coordinate, the others with 0.5 um
// noise (seed 3). Given u_um = 30 there and 0.5 elsewhere, the weighted estimates lie within 4 u
// of the truth and closer to it (RMS over the errors) than the unweighted ones, which the 30 um
// reading pulls; the chi-like scale of correct u_um is 1 within 4 sd of sqrt(chi2_dof / dof)
// (sd ~ 1 / sqrt(2 dof) = 0.073, dof = 108 - 14).
TEST(DatumBall, WeightsFromReadingUncertaintiesDownweightANoisyPosition) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  auto readings = BallReadings(m, BallTruth(m, kTable1a), 0.5, 3);
  constexpr std::size_t kBad = 3;
  readings[kBad].command_mm += UmToMm(30.0) * Eigen::Vector3d(1.0, -1.0, 1.0);
  DatumBallOptions options;
  options.monte_carlo_runs = 0;
  auto unweighted = IdentifyDatumBall(m, readings, options);
  for (auto& r : readings) r.u_um = 0.5;
  readings[kBad].u_um = 30.0;
  auto weighted = IdentifyDatumBall(m, readings, options);
  ASSERT_TRUE(unweighted.ok() && weighted.ok());
  EXPECT_FALSE(unweighted->weighted);
  EXPECT_TRUE(weighted->weighted);
  EXPECT_NEAR(weighted->chi_scale, 1.0, 4.0 / std::sqrt(2.0 * 94));
  double ss_weighted = 0.0, ss_unweighted = 0.0;
  for (std::size_t k = 0; k < weighted->parameters.size(); ++k) {
    const auto& pw = weighted->parameters[k];
    const double truth = kTable1a.at(pw.name);
    EXPECT_LT(std::abs(pw.value - truth), 4.0 * pw.u) << pw.name << " " << pw.value << " +- " << pw.u;
    ss_weighted += std::pow(pw.value - truth, 2);
    ss_unweighted += std::pow(unweighted->parameters[k].value - truth, 2);
  }
  std::printf("RMS error over the errors: weighted %.3f, unweighted %.3f (um, urad)\n",
              std::sqrt(ss_weighted / 11), std::sqrt(ss_unweighted / 11));
  EXPECT_LT(ss_weighted, ss_unweighted);
}

TEST(DatumBall, ReadingUncertaintyForSomeReadingsOnlyIsAnError) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  auto readings = BallReadings(m, BallTruth(m, kTable1a), 0.0, 1);
  readings[5].u_um = 1.0;
  auto r = IdentifyDatumBall(m, readings);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().line(), readings[5].line);
  EXPECT_NE(r.status().message().find("for every reading (weights) or for none"), std::string::npos);
}

// One tilt only (B = 0): the tilt axis's errors cannot be told from the C axis's and the linear
// squareness; they are named, with the combinations the plan determines, not given numbers.
TEST(DatumBall, OneTiltNamesWhatItCannotSeparate) {
  const MachineModel m = BallMachine(MachineType::kBcTable);
  auto all = BallReadings(m, BallTruth(m, kTable1a), 0.0, 1);
  std::vector<BallReading> flat(all.begin(), all.begin() + 12);
  auto r = IdentifyDatumBall(m, flat);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_FALSE(r->identifiability.not_identifiable.empty());
  EXPECT_FALSE(r->identifiability.null_directions.empty());
  for (const auto& p : r->parameters) {
    if (!p.identifiable) {
      EXPECT_NE(p.name.find('0'), std::string::npos) << p.name;
    }
  }
}

TEST(DatumBall, AcTableIsIdentifiedTheSameWay) {
  const MachineModel m = BallMachine(MachineType::kAcTable);
  const std::map<std::string, double> truth = {{"E_Y0A", 12.0}, {"E_Z0A", -9.0},  {"E_B0A", 30.0},  {"E_C0A", -25.0},
                                               {"E_X0C", 8.0},  {"E_Y0C", -14.0}, {"E_A0A", 40.0},  {"E_B0C", -18.0},
                                               {"E_C(0X)Y", 11.0}, {"E_B(0X)Z", -16.0}, {"E_A(0Y)Z", 18.0}};
  auto r = IdentifyDatumBall(m, BallReadings(m, BallTruth(m, truth), 0.0, 1));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  for (const auto& p : r->parameters) {
    if (!p.identifiable) continue;
    const auto it = truth.find(p.name);
    EXPECT_NEAR(p.value, it == truth.end() ? 0.0 : it->second, 1e-3) << p.name;
  }
  // The ISO set of the A/C table holds the C zero offset E_C0C, which a ball fitted as a nuisance
  // cannot see apart from its own angular position about C: named, with no number.
  EXPECT_EQ(r->identifiability.not_identifiable, std::vector<std::string>{"E_C0C"});
}

}  // namespace
}  // namespace tpcal::kinematics
