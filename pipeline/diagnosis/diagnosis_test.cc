#include "pipeline/diagnosis/diagnosis.h"
#include "testpieces/iso10791_pieces.h"
#include "testpieces/named_pieces.h"

#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gdt/inspection.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/slot_linearisation.h"
#include "pipeline/report/diagnosis_json.h"
#include "pipeline/diagnosis/diagnosis_gap_summary.h"
#include "pipeline/diagnosis/diagnosis_reference_nuisance.h"
#include "pipeline/diagnosis/diagnosis_validate.h"
#include "testpieces/point_association.h"
#include "testpieces/probing_plan.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

struct Fixture {
  kinematics::MachineModel machine;
  testpieces::TestPiece piece;
};

Fixture Make() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  auto piece = testpieces::MakeTestPiece(testpieces::PieceConfig{}, *m);
  EXPECT_TRUE(piece.ok()) << piece.status().message();
  return {*m, *piece};
}

// The standard single cone frustum (NAS 979) on the nominal A/C table.
Fixture MakeCone() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  testpieces::PieceConfig config;
  config.params = testpieces::ConeFrustumParams{};
  auto piece = testpieces::MakeTestPiece(config, *m);
  EXPECT_TRUE(piece.ok()) << piece.status().message();
  return {*m, *piece};
}

// Seed 002 Table 2 (machining column) as the base errors of the simulated machine.
kinematics::ErrorState Table2(const kinematics::MachineModel& m, const std::string& effects = "") {
  auto e = kinematics::ParseErrorState(
      "dx_CR(0)_um: 12.4\ndy_CR(0)_um: -16.8\nalpha_CR(0)_urad: -8.7\nbeta_CR(0)_urad: -7.0\n"
      "dy_AR(-90)_um: 36.5\ndz_AR(-90)_um: 28.6\ndy_CA(-90)_um: -25.4\nalpha_CR(-90)_urad: 36.7\n"
      "gamma_CR(-90)_urad: 1.6\nbeta_ZX_urad: 3.5\nalpha_ZY_urad: 19.2\n" + effects,
      "<test>", m);
  EXPECT_TRUE(e.ok()) << e.status().message();
  return *e;
}

// CMM noise and its seed, the piece at a random placement.
testpieces::PieceSimOptions SimOptions(double noise_um, std::uint64_t seed) {
  testpieces::PieceSimOptions o;
  o.noise_um = noise_um;
  o.seed = seed;
  o.random_placement = true;
  return o;
}

Result<testpieces::SimulatedPiece> Simulate(const Fixture& f, const kinematics::ErrorState& e, double noise_um,
                                            std::uint64_t seed) {
  return testpieces::SimulatePiece(f.piece, f.machine, e, SimOptions(noise_um, seed));
}

// The piece simulated with `errors` (placement random, noise seeded), as observations in the
// nominal part frame through the datum of its inspection plan.
Result<testpieces::MeasuredObservations> SimulatedObservations(const Fixture& f, const kinematics::ErrorState& errors,
                                                   double noise_um, std::uint64_t seed) {
  auto sim = Simulate(f, errors, noise_um, seed);
  if (!sim.ok()) return sim.status();
  auto inspection = gdt::EvaluatePlan(f.piece.inspection, sim->points);
  if (!inspection.ok()) return inspection.status();
  return testpieces::AssociatePoints(f.piece, sim->points, inspection->datum_from_cmm);
}

// A circular profile of 16 points every 22.5 deg (radius 100 mm) with the hits at 0 and 180 deg
// left out (skipped, or outliers) and a gap of +3 um + 2 cos(2 phi) um at the 14 points left (a
// mean offset, a probe radius error, and an oval), sigma 1 um. Truth: order 2 is 2 um at 0 deg,
// every other order 0 to rounding; order 2's energy is the drop of the residual sum of squares when
// order 2 joins the others (Householder least squares here), and z its root over sigma. A DFT's
// sums over the 14 points leak the mean into the even orders (0.86 um).
TEST(Diagnosis, ProfileWithPointsLeftOutKeepsItsMeanOutOfTheHarmonics) {
  const Fixture f = Make();
  testpieces::MeasuredObservations mo;
  mo.feature_names = {"S1"};
  std::vector<double> phis;
  for (int j = 1; j < 16; ++j) {
    if (j == 8) continue;
    kinematics::Observation o;
    phis.push_back(j * M_PI / 8.0);
    o.cut.nominal_point_mm = Eigen::Vector3d(100.0 * std::cos(phis.back()), 100.0 * std::sin(phis.back()), 50.0);
    mo.observations.push_back(o);
  }
  const auto m = static_cast<Eigen::Index>(phis.size());
  Eigen::VectorXd gap(m);
  for (Eigen::Index i = 0; i < m; ++i) gap(i) = 3.0 + 2.0 * std::cos(2.0 * phis[static_cast<std::size_t>(i)]);
  DiagnosisResult out;
  diagnosis_internal::SummariseGap(f.machine, mo, gap, 1.0, DiagnosisOptions{}, &out);
  ASSERT_FALSE(out.harmonics.empty());
  const int kmax = static_cast<int>(out.harmonics.size());
  // Residual sums of squares of the fits on [1, cos k phi, sin k phi], k = 1..kmax, with and without order 2.
  auto rss = [&](bool with_order_2) {
    Eigen::MatrixXd X(m, 1 + 2 * kmax - (with_order_2 ? 0 : 2));
    for (Eigen::Index i = 0; i < m; ++i) {
      Eigen::Index c = 0;
      X(i, c++) = 1.0;
      for (int k = 1; k <= kmax; ++k)
        if (k != 2 || with_order_2) X(i, c++) = std::cos(k * phis[static_cast<std::size_t>(i)]), X(i, c++) = std::sin(k * phis[static_cast<std::size_t>(i)]);
    }
    return (gap - X * X.householderQr().solve(gap)).squaredNorm();
  };
  for (const auto& h : out.harmonics) {
    if (h.order == 2) {
      EXPECT_NEAR(h.amplitude_um, 2.0, 1e-9);
      EXPECT_NEAR(h.phase_deg, 0.0, 1e-6);
      EXPECT_NEAR(h.energy_um2, rss(false) - rss(true), 1e-9);
      EXPECT_NEAR(h.z, std::sqrt(h.energy_um2), 1e-12);
    } else {
      EXPECT_LT(h.amplitude_um, 1e-9) << "order " << h.order;
    }
  }
}

// Two adjacent hits (at 22.5 and 45 deg) missing from a 16-hit circle of radius 100 mm, gap
// 2 cos(2 phi) + 1 sin(3 phi) um. Truth: order 2 reads 2 um at 0 deg, order 3 1 um at 90 deg,
// the others 0 (to 1e-9). About the centroid of the 14 hits (14 mm off the centre) their radii
// spread by 28 % and the profile was skipped as not circular: no harmonic at all (measured).
TEST(Diagnosis, ProfileWithAdjacentHitsMissingIsTakenAboutItsCircle) {
  const Fixture f = Make();
  testpieces::MeasuredObservations mo;
  mo.feature_names = {"S1"};
  std::vector<double> phis;
  for (int j = 0; j < 16; ++j) {
    if (j == 1 || j == 2) continue;
    kinematics::Observation o;
    phis.push_back(j * M_PI / 8.0);
    o.cut.nominal_point_mm = Eigen::Vector3d(30.0 + 100.0 * std::cos(phis.back()), -20.0 + 100.0 * std::sin(phis.back()), 50.0);
    mo.observations.push_back(o);
  }
  Eigen::VectorXd gap(static_cast<Eigen::Index>(phis.size()));
  for (std::size_t i = 0; i < phis.size(); ++i)
    gap(static_cast<Eigen::Index>(i)) = 2.0 * std::cos(2.0 * phis[i]) + std::sin(3.0 * phis[i]);
  DiagnosisResult out;
  diagnosis_internal::SummariseGap(f.machine, mo, gap, 1.0, DiagnosisOptions{}, &out);
  ASSERT_GE(out.harmonics.size(), 3u);
  for (const auto& h : out.harmonics) {
    if (h.order == 2) {
      EXPECT_NEAR(h.amplitude_um, 2.0, 1e-9);
      EXPECT_NEAR(h.phase_deg, 0.0, 1e-6);
    } else if (h.order == 3) {
      EXPECT_NEAR(h.amplitude_um, 1.0, 1e-9);
      EXPECT_NEAR(h.phase_deg, 90.0, 1e-6);
    } else {
      EXPECT_LT(h.amplitude_um, 1e-9) << "order " << h.order;
    }
  }
}

// A hole probed at two levels, 8 hits each every 45 deg, the second level's azimuths 0.5 deg on
// (a tilted hole seen about Z), gap 1.5 cos(3 phi) um. Truth: 16 azimuths in close pairs hold
// orders 1 to 3 (8 directions apart), not 7: order 3 reads 1.5 um, orders 1 and 2 zero; a fit of
// 7 orders on them is near-singular and is not reported.
TEST(Diagnosis, HoleProbedAtTwoLevelsKeepsItsFirstOrders) {
  const Fixture f = Make();
  testpieces::MeasuredObservations mo;
  mo.feature_names = {"H1"};
  Eigen::VectorXd gap(16);
  for (int level = 0; level < 2; ++level)
    for (int j = 0; j < 8; ++j) {
      kinematics::Observation o;
      const double phi = j * M_PI / 4.0 + level * 0.5 * M_PI / 180.0;
      o.cut.nominal_point_mm = Eigen::Vector3d(8.0 * std::cos(phi), 8.0 * std::sin(phi), 40.0 - 5.0 * level);
      gap(static_cast<Eigen::Index>(mo.observations.size())) = 1.5 * std::cos(3.0 * phi);
      mo.observations.push_back(o);
    }
  DiagnosisResult out;
  diagnosis_internal::SummariseGap(f.machine, mo, gap, 0.5, DiagnosisOptions{}, &out);
  ASSERT_EQ(out.harmonics.size(), 3u);
  EXPECT_NEAR(out.harmonics[2].amplitude_um, 1.5, 1e-9);
  EXPECT_LT(out.harmonics[0].amplitude_um, 1e-9);
  EXPECT_LT(out.harmonics[1].amplitude_um, 1e-9);
}

// A 16-hit circle (radius 100 mm, every 22.5 deg, one minute apart) whose gap is 2 cos(3 phi) um,
// noise sigma 0.5 um, and a reference whose own uncertainty moves the gap along exactly that
// pattern with 1 sd (its leftover factor R: one column). Without R, the profile, its order 3
// and its groups stand out (order 3: z = sqrt(32 um^2) / 0.5 = 11.3; the profile's SSR is 128
// sigma^2 on 16 points). With R the same gap is what the reference's uncertainty explains at
// 1 sd: order 3's law is c chi2_d with mean 2 sigma^2 + 32 = 32.5 um^2 and d = 1.02, its
// Rayleigh-equivalent z 1.50, the group's z 0.33: nothing stands out. The drift's u holds
// R's slope in time, by its definition (least squares of R on [1, t / h]). Tolerances: 1e-9.
TEST(Diagnosis, WhereTheGapLiesWeighsTheReferencesOwnUncertainty) {
  const Fixture f = Make();
  testpieces::MeasuredObservations mo;
  mo.feature_names = {"S1"};
  Eigen::VectorXd gap(16);
  Eigen::MatrixXd T(16, 2);
  for (int j = 0; j < 16; ++j) {
    kinematics::Observation o;
    const double phi = j * M_PI / 8.0;
    o.cut.nominal_point_mm = Eigen::Vector3d(100.0 * std::cos(phi), 100.0 * std::sin(phi), 50.0);
    o.cut.axes.t_s = 60.0 * j;
    gap(j) = 2.0 * std::cos(3.0 * phi);
    T.row(j) << 1.0, o.cut.axes.t_s / 3600.0;
    mo.observations.push_back(o);
  }
  constexpr double kSigma_um = 0.5;
  DiagnosisResult plain, weighed;
  diagnosis_internal::SummariseGap(f.machine, mo, gap, kSigma_um, DiagnosisOptions{}, &plain);
  diagnosis_internal::SummariseGap(f.machine, mo, gap, kSigma_um, DiagnosisOptions{}, &weighed, gap);
  auto order3 = [](const DiagnosisResult& d) {
    for (const auto& h : d.harmonics)
      if (h.order == 3) return h;
    return HarmonicGap{};
  };
  EXPECT_NEAR(order3(plain).z, std::sqrt(32.0) / kSigma_um, 1e-9);
  EXPECT_TRUE(order3(plain).stands_out);
  EXPECT_TRUE(std::count(plain.standing_out.begin(), plain.standing_out.end(), "feature S1"));
  EXPECT_NEAR(order3(weighed).energy_um2, 32.0, 1e-9);
  EXPECT_GT(order3(weighed).z, 1.0);
  EXPECT_LT(order3(weighed).z, 2.0);
  EXPECT_TRUE(weighed.standing_out.empty()) << weighed.standing_out.front();
  ASSERT_FALSE(weighed.by_feature.empty());
  EXPECT_LT(std::abs(weighed.by_feature.front().z), 1.0);
  const Eigen::MatrixXd G = (T.transpose() * T).inverse() * T.transpose();
  const double u_noise = kSigma_um * std::sqrt((T.transpose() * T).inverse()(1, 1));
  EXPECT_NEAR(plain.drift_u_um_per_h, u_noise, 1e-9);
  EXPECT_NEAR(weighed.drift_u_um_per_h, std::hypot(u_noise, G.row(1).dot(gap)), 1e-9);
}

// "Where it lies": the C harmonics of each circular profile, the groups by operation and by A
// index, recomputed here from their definitions on the diagnosis's own gap (truth: the
// definitions, the profile's circle and harmonics by Householder least squares; tolerance 1e-9
// um: fits and sums of ~50 terms of ~10 um in another order).
TEST(Diagnosis, WhereTheGapLiesFollowsItsDefinitions) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine,
                             "effects:\n  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 3, cos_um: 3, sin_um: 1}]}\n");
  auto mo = SimulatedObservations(f, errors, 0.5, 21);
  ASSERT_TRUE(mo.ok()) << mo.status().message();
  auto d = DiagnoseObservations(f.piece, f.machine, *mo);
  ASSERT_TRUE(d.ok()) << d.status().message();
  const auto& obs = mo->observations;
  ASSERT_EQ(d->gap_um.size(), obs.size());
  std::map<std::string, std::vector<std::size_t>> by_feature, by_op, by_a;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    by_feature[mo->feature_names[static_cast<std::size_t>(obs[i].group)]].push_back(i);
    by_op[fmt::format("op {}", obs[i].cut.axes.op)].push_back(i);
    by_a[fmt::format("A={:g} deg", std::round(obs[i].cut.axes.a_rad * 180.0 / M_PI * 1000.0) / 1000.0 + 0.0)].push_back(i);
  }
  int checked = 0;
  for (const auto& h : d->harmonics) {
    const auto& idx = by_feature.at(h.feature);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (auto i : idx) c += obs[i].cut.nominal_point_mm;
    c /= static_cast<double>(idx.size());
    // The profile's centre: the algebraic circle x^2 + y^2 + D x + E y + F = 0 through its
    // nominal points (Householder QR here), kept when its azimuths leave no gap above 120 deg.
    {
      Eigen::MatrixXd A(static_cast<Eigen::Index>(idx.size()), 3);
      Eigen::VectorXd rhs(A.rows());
      for (std::size_t row = 0; row < idx.size(); ++row) {
        const Eigen::Vector3d v = obs[idx[row]].cut.nominal_point_mm - c;
        A.row(static_cast<Eigen::Index>(row)) << v.x(), v.y(), 1.0;
        rhs(static_cast<Eigen::Index>(row)) = -(v.x() * v.x() + v.y() * v.y());
      }
      const Eigen::Vector3d def = A.householderQr().solve(rhs);
      const Eigen::Vector3d circle = c + Eigen::Vector3d(-0.5 * def(0), -0.5 * def(1), 0.0);
      std::vector<double> az;
      for (auto i : idx) {
        const Eigen::Vector3d v = obs[i].cut.nominal_point_mm - circle;
        az.push_back(std::atan2(v.y(), v.x()));
      }
      std::sort(az.begin(), az.end());
      double widest = az.front() + 2.0 * M_PI - az.back();
      for (std::size_t k = 1; k < az.size(); ++k) widest = std::max(widest, az[k] - az[k - 1]);
      if (widest <= 2.0 * M_PI / 3.0) c = circle;
    }
    // Truth: least squares of the gap on [1, cos k phi, sin k phi], k = 1..kmax (the profile's
    // orders), by Householder QR; on equally spaced azimuths it is the DFT 2/m sum r e^{i k phi}.
    std::set<long long> azimuths;  // distinct to 1e-6 rad
    for (auto i : idx) {
      const Eigen::Vector3d v = obs[i].cut.nominal_point_mm - c;
      azimuths.insert(std::llround(std::atan2(v.y(), v.x()) * 1e6));
    }
    const int kmax = std::min<int>(DiagnosisOptions{}.max_harmonic, static_cast<int>(azimuths.size()) / 2 - 1);
    Eigen::MatrixXd X(static_cast<Eigen::Index>(idx.size()), 1 + 2 * kmax);
    Eigen::VectorXd y(X.rows());
    for (std::size_t row = 0; row < idx.size(); ++row) {
      const Eigen::Vector3d v = obs[idx[row]].cut.nominal_point_mm - c;
      const double phi = std::atan2(v.y(), v.x());
      const auto r = static_cast<Eigen::Index>(row);
      X(r, 0) = 1.0;
      for (int k = 1; k <= kmax; ++k) X(r, 2 * k - 1) = std::cos(k * phi), X(r, 2 * k) = std::sin(k * phi);
      y(r) = d->gap_um[idx[row]];
    }
    const Eigen::VectorXd coef = X.householderQr().solve(y);
    const double a = coef(2 * h.order - 1), b = coef(2 * h.order);
    EXPECT_NEAR(h.amplitude_um, std::hypot(a, b), 1e-9) << h.feature << " order " << h.order;
    if (std::hypot(a, b) > 1e-3) {
      EXPECT_NEAR(std::remainder(h.phase_deg - std::atan2(b, a) * 180.0 / M_PI, 360.0), 0.0, 1e-6) << h.feature;
    }
    ++checked;
  }
  EXPECT_GT(checked, 20);
  auto check_groups = [&](const std::vector<GroupGap>& groups, const std::map<std::string, std::vector<std::size_t>>& truth) {
    ASSERT_EQ(groups.size(), truth.size());
    for (const auto& g : groups) {
      const auto& idx = truth.at(g.group);
      double ss = 0;
      for (auto i : idx) ss += d->gap_um[i] * d->gap_um[i];
      EXPECT_EQ(g.n_points, static_cast<int>(idx.size())) << g.group;
      EXPECT_NEAR(g.rms_um, std::sqrt(ss / static_cast<double>(idx.size())), 1e-9) << g.group;
    }
  };
  check_groups(d->by_operation, by_op);
  check_groups(d->by_a_index, by_a);
  check_groups(d->by_feature, by_feature);
}

// Location errors only (what the base model holds) + noise: the gap is noise, verdict none.
TEST(Diagnosis, EffectFreePieceGivesNone) {
  const Fixture f = Make();
  constexpr double kNoise_um = 1.0;
  auto sim = Simulate(f, Table2(f.machine), kNoise_um, 11);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(d->verdict.family, "none");
  // Residual RMS of n points after q fitted directions: sigma sqrt((n - q) / n), within sampling
  // scatter (relative sd ~ 1 / sqrt(2 n) ~ 4 % for ~350 points; 20 % allows for > 4 sd).
  const double expected = kNoise_um * std::sqrt(1.0 - static_cast<double>(d->base_columns) / d->n_points);
  EXPECT_NEAR(d->rms_um, expected, 0.2 * expected);
  EXPECT_FALSE(d->candidates.empty());
  for (const auto& c : d->candidates) EXPECT_FALSE(c.significant) << c.name;
}

// A thermal drift of the table in Y (exponential, tau 40 min) withheld from the base model:
// the diagnosis names it, the gap shrinks, and the JSON follows the contract.
TEST(Diagnosis, WithheldThermalDriftIsNamedAndJsonFollowsTheContract) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 12, tau_s: 2400}\n");
  auto sim = Simulate(f, errors, 0.5, 12);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(d->verdict.family, "thermal_drift");
  EXPECT_GT(d->verdict.shrink_pct, 30.0);
  EXPECT_GT(d->candidates.front().cv_shrink_pct, 30.0);

  const auto j = nlohmann::json::parse(DiagnosisJson(*d));
  EXPECT_EQ(j["schema"], "tpcal.diagnosis/1");
  EXPECT_TRUE(j["base_model"].is_string());
  for (const char* k : {"rms_um", "max_abs_um", "n_points", "by_feature"}) EXPECT_TRUE(j["gap"].contains(k)) << k;
  ASSERT_FALSE(j["gap"]["by_feature"].empty());
  for (const char* k : {"feature", "rms_um", "max_abs_um"}) EXPECT_TRUE(j["gap"]["by_feature"][0].contains(k)) << k;
  ASSERT_FALSE(j["candidates"].empty());
  for (const auto& c : j["candidates"]) {
    for (const char* k : {"family", "name", "rms_after_um", "shrink_pct", "cv_rms_before_um", "cv_rms_after_um", "parameters"})
      EXPECT_TRUE(c.contains(k)) << k;
    for (const auto& [name, p] : c["parameters"].items()) {
      for (const char* k : {"value", "u", "unit"}) EXPECT_TRUE(p.contains(k)) << name << " " << k;
      // A number only where the data separate the parameter; null (and "identifiable": false) otherwise.
      const bool identifiable = !p.contains("identifiable") || p["identifiable"].get<bool>();
      EXPECT_EQ(p["value"].is_number(), identifiable) << name;
      EXPECT_EQ(p["u"].is_number(), identifiable) << name;
    }
  }
  for (const char* k : {"family", "name", "shrink_pct", "indistinguishable_from"}) EXPECT_TRUE(j["verdict"].contains(k)) << k;
  // shrink_pct = 100 (1 - rms_after / rms_before), candidates best first.
  const double rms0 = j["gap"]["rms_um"];
  for (const auto& c : j["candidates"])
    EXPECT_NEAR(c["shrink_pct"].get<double>(), 100.0 * (1.0 - c["rms_after_um"].get<double>() / rms0), 1e-9);
}

// A drift and servo glitches at once (turning piece, Table 2 base, noise 0.5 um, seed 1): the
// glitches are 3 um spikes on a few hits of S_R. To the drift alone two of those hits are isolated
// outliers; the screen's second pass has the pair the verdict names in its model, so they stay
// (with the drift alone in it, 2 hits were listed as outliers and left out).
TEST(Diagnosis, ServoGlitchesBesideADriftAreNotOutliers) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 6, tau_s: 2400}\n");
  testpieces::PieceSimOptions o = SimOptions(0.5, 1);
  testpieces::ServoReversalModel servo;
  servo.spike_x_um = 3.0;
  servo.spike_y_um = 2.4;
  o.process.servo = servo;
  auto sim = testpieces::SimulatePiece(f.piece, f.machine, errors, o);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(std::set<std::string>(d->verdict.families.begin(), d->verdict.families.end()),
            (std::set<std::string>{"thermal_drift", "servo_reversal"}))
      << DiagnosisText(*d);
  EXPECT_TRUE(d->outliers.empty()) << DiagnosisText(*d);
  EXPECT_TRUE(d->local_defects.empty()) << DiagnosisText(*d);
}

// Two withheld effects at once, of different families: a thermal drift of the table in Y and a
// CMM probe-radius error. The verdict names one of them; the runner-up (the other) still adds
// significantly beyond it, so the pair is fitted jointly and explains more than the verdict
// alone, in sample and cross-validated. Magnitudes: 12 um drift and 3 um probe radius against
// 0.5 um noise (each alone is named at 100 % in the validation matrix at >= 5x noise).
TEST(Diagnosis, TwoWithheldEffectsAreFittedAsAPair) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 12, tau_s: 2400}\n");
  testpieces::PieceSimOptions o = SimOptions(0.5, 21);
  o.probe_radius_error_um = 3.0;
  auto sim = testpieces::SimulatePiece(f.piece, f.machine, errors, o);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  const std::set<std::string> withheld = {"thermal_drift", "probe_radius"};
  EXPECT_TRUE(withheld.count(d->verdict.family)) << d->verdict.family;
  ASSERT_TRUE(d->pair.has_value()) << DiagnosisText(*d);
  const PairFit& p = *d->pair;
  ASSERT_EQ(p.families.size(), 2u);
  EXPECT_EQ(p.families[0], d->verdict.family);
  EXPECT_EQ(std::set<std::string>(p.families.begin(), p.families.end()), withheld) << DiagnosisText(*d);
  EXPECT_GT(p.shrink_pct, d->verdict.shrink_pct + 1.0);
  EXPECT_GT(p.cv_shrink_pct, d->verdict.cv_shrink_pct);
  // After both effects the residual is the CMM noise: sigma sqrt((n - q) / n) within sampling
  // scatter (20 %, > 4 sd for ~350 points).
  EXPECT_LT(p.rms_after_um, 1.2 * 0.5);
  // The probe-radius parameter comes out near its truth (3 um) within 4 u.
  bool found = false;
  for (const auto& e : p.parameters) {
    if (e.unit != "um" || e.name.find("probe") == std::string::npos) continue;
    found = true;
    EXPECT_LE(std::abs(std::abs(e.value) - 3.0), 4.0 * e.u) << e.name << " " << e.value << " +- " << e.u;
  }
  EXPECT_TRUE(found) << "no probe-radius parameter in the pair fit";
  const auto j = nlohmann::json::parse(DiagnosisJson(*d));
  ASSERT_TRUE(j.contains("pair"));
  EXPECT_EQ(j["pair"]["families"].size(), 2u);
  EXPECT_NEAR(j["pair"]["shrink_pct"].get<double>(), p.shrink_pct, 1e-12);
  // `also` carries what the data cannot tell it from (here nothing: the two are far apart).
  ASSERT_TRUE(d->verdict.also.has_value()) << DiagnosisText(*d);
  EXPECT_TRUE(d->verdict.also_indistinguishable_from.empty()) << DiagnosisText(*d);
  EXPECT_EQ(j["verdict"]["also_indistinguishable_from"], nlohmann::json::array());
}

// A pair whose sum looks like a third family (turning piece, Table 2 base, noise 0.5 um, seeds 1 to
// 6): a 6 um drift of the table in Y and a 20 um/m scale error of Y. Forward selection names the
// drift, then tool deflection, whose per-cut-class compliance takes up part of the scale, in 6 of
// 6 (measured); the joint search over two-family pairs finds drift and positioning, which explain
// and predict better, in 4 of 6. Truth: the drift leads every time; both named in at least 3.
TEST(Diagnosis, AJointSearchFindsThePairForwardSelectionMisses) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 6, tau_s: 2400}\n"
                                        "  - linear_error_motion: {symbol: E_YY, coefficients_um_per_mm_pow: [0, 0.02]}\n");
  int both = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    auto sim = testpieces::SimulatePiece(f.piece, f.machine, errors, SimOptions(0.5, seed));
    ASSERT_TRUE(sim.ok()) << sim.status().message();
    auto d = Diagnose(f.piece, f.machine, sim->points);
    ASSERT_TRUE(d.ok()) << d.status().message();
    EXPECT_EQ(d->verdict.family, "thermal_drift") << DiagnosisText(*d);
    const std::set<std::string> named(d->verdict.families.begin(), d->verdict.families.end());
    both += named == std::set<std::string>{"thermal_drift", "linear_positioning"};
  }
  EXPECT_GE(both, 3);
}

// An angular positioning error of A, the first rotary axis (turning piece, Table 2 base, noise 0.5
// um, seeds 1 to 3): E_AA from 35 urad at A -90 to 0 at A 0, as the maps tests' table. The piece cuts
// ops 7 and 8, its last, at A -90 and the rest at A 0, so the error is a step between them, which a
// drift of the table with machining time also fits. Truth: the catalogue's candidate for A's
// positioning explains it significantly, is its family's best (C's positioning does not take it)
// and is named, as the verdict or beside it as indistinguishable. verdict.indistinguishable_candidates
// names, by candidate, what indistinguishable_from names by family: each family listed there has at
// least one candidate listed by name, A's positioning itself when the verdict is a drift (and A's
// positioning is not the second effect, `also`, whose family is left out).
TEST(Diagnosis, ThePositioningOfTheFirstRotaryAxisIsACandidate) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - rotary_error_motion: {symbol: E_AA, positions_deg: [-90, -60, -30, 0],"
                                        " values_urad: [35, 22, 10, 0], interpolation: linear}\n");
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    auto sim = testpieces::SimulatePiece(f.piece, f.machine, errors, SimOptions(0.5, seed));
    ASSERT_TRUE(sim.ok()) << sim.status().message();
    auto d = Diagnose(f.piece, f.machine, sim->points);
    ASSERT_TRUE(d.ok()) << d.status().message();
    std::set<std::string> named(d->verdict.families.begin(), d->verdict.families.end());
    named.insert(d->verdict.indistinguishable_from.begin(), d->verdict.indistinguishable_from.end());
    EXPECT_TRUE(named.count("rotary_positioning")) << DiagnosisText(*d);
    const auto a = std::find_if(d->candidates.begin(), d->candidates.end(),
                                [](const auto& c) { return c.family == "rotary_positioning"; });
    ASSERT_NE(a, d->candidates.end());
    EXPECT_EQ(a->name, "angular positioning error of A, orders 1 to 4") << DiagnosisText(*d);
    EXPECT_TRUE(a->significant) << DiagnosisText(*d);
    const auto& by_name = d->verdict.indistinguishable_candidates;
    for (const std::string& family : d->verdict.indistinguishable_from) {
      const auto listed = std::count_if(d->candidates.begin(), d->candidates.end(), [&](const auto& c) {
        return c.family == family && std::count(by_name.begin(), by_name.end(), c.name) == 1;
      });
      EXPECT_GE(listed, 1) << family << "\n" << DiagnosisText(*d);
    }
    if (d->verdict.family != "rotary_positioning" && d->verdict.also.value_or("") != "rotary_positioning") {
      EXPECT_EQ(std::count(by_name.begin(), by_name.end(), a->name), 1) << DiagnosisText(*d);
    }
  }
}

// Reference mode (seed 002 section 4.4): the sim is the machine errors of Table 2's probing column,
// the real piece was cut with the machining column; the gap is a change of location errors and the
// `location_errors` candidate explains it entirely (noise-free data). Values: seed 002 Table 2
// (samples/errors/seed002_table2_*.yaml; the probing column has no squareness).
TEST(Diagnosis, ReferenceModeFindsTheLocationErrorChange) {
  const Fixture f = Make();
  auto probing = kinematics::ParseErrorState(
      "dx_CR(0)_um: -5.8\ndy_CR(0)_um: -26.1\nalpha_CR(0)_urad: -0.1\nbeta_CR(0)_urad: 5.2\n"
      "dy_AR(-90)_um: 46.5\ndz_AR(-90)_um: 18.7\ndy_CA(-90)_um: -31.6\nalpha_CR(-90)_urad: 47.1\n"
      "gamma_CR(-90)_urad: 2.4\n",
      "<test>", f.machine);
  ASSERT_TRUE(probing.ok()) << probing.status().message();
  auto sim = Simulate(f, Table2(f.machine), 0.0, 13);
  ASSERT_TRUE(sim.ok());
  DiagnosisOptions o;
  o.reference = *probing;
  o.noise_um = 0.5;
  auto d = Diagnose(f.piece, f.machine, sim->points, o);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_GT(d->rms_um, 1.0);
  const auto it = std::find_if(d->candidates.begin(), d->candidates.end(),
                               [](const CandidateResult& c) { return c.family == "location_errors"; });
  ASSERT_NE(it, d->candidates.end());
  EXPECT_GT(it->shrink_pct, 99.0);
  EXPECT_EQ(d->verdict.family, "location_errors");
  // The refitted set is the difference machining - probing (dx_CR(0): 12.4 - (-5.8) = 18.2 um);
  // exact data: linearisation error only (second order, < 1e-2 um here).
  for (const auto& p : it->parameters) {
    if (p.name == "dx_CR(0)") {
      EXPECT_NEAR(p.value, 18.2, 0.05);
    }
  }
}

// The reference's own uncertainty (DiagnosisOptions::reference_uncertainty). Truth: the piece is
// cut by Table 2's errors, the reference holds them with dx_CR(0) 4 um off (noise 0.5 um, seed 13).
// Known to 0.01 um the 4 um is the reference's error: refitting the location errors takes it
// (location_errors, no nuisance direction: its variance 1e-4 um^2 times its column's norm^2 off
// the re-alignment, 103 um^2/um^2 measured on this piece, is 0.01 um^2, below sigma^2 = 0.25 um^2).
// Known to 4 um (16 x 103 um^2, far above 0.25) the same 4 um lies within what the reference
// knows: one direction fitted, none.
TEST(Diagnosis, ReferenceUncertaintyIsFittedNotBlamed) {
  const Fixture f = Make();
  kinematics::ErrorState off = Table2(f.machine);
  const auto c = off.FindCoefficient("dx_CR(0)");
  ASSERT_TRUE(c.has_value());
  off.set_coefficient(*c, off.coefficient(*c) + 4.0 / off.coefficient_info(*c).display_per_internal);
  auto sim = Simulate(f, Table2(f.machine), 0.5, 13);
  ASSERT_TRUE(sim.ok());
  for (const double u_um : {0.01, 4.0}) {
    DiagnosisOptions o;
    o.reference = off;
    o.noise_um = 0.5;
    o.reference_uncertainty = ReferenceUncertainty{{"dx_CR(0)"}, Eigen::MatrixXd::Constant(1, 1, u_um * u_um), 0.5};
    auto d = Diagnose(f.piece, f.machine, sim->points, o);
    ASSERT_TRUE(d.ok()) << d.status().message();
    const bool loose = u_um > 1.0;
    EXPECT_EQ(d->verdict.family, loose ? "none" : "location_errors") << u_um;
    EXPECT_EQ(d->base_model.find("1 direction its own uncertainty") != std::string::npos, loose) << d->base_model;
  }
}

// ReferenceNuisanceColumns against K = P J S J^T P computed here (P off the re-alignment, J the
// turning piece's design in three location errors of C, S singular: dx and dy fully correlated,
// 2 um each, alpha 1 urad; rank 2). Truth: the fitted columns and the rest rebuild K, the columns
// are orthogonal to the re-alignment, each fitted one carries more than ratio sigma^2 = 0.25 um^2
// and each one left at most that, and at most rank S = 2 directions carry anything. Tolerance:
// double rounding, 1e-9 of K's largest entry.
TEST(Diagnosis, ReferenceNuisanceSplitsTheReferenceVarianceAtTheThreshold) {
  const Fixture f = Make();
  const kinematics::ErrorState table2 = Table2(f.machine);
  auto mo = SimulatedObservations(f, table2, 0.0, 13);
  ASSERT_TRUE(mo.ok()) << mo.status().message();
  const std::vector<std::string> names = {"dx_CR(0)", "dy_CR(0)", "alpha_CR(0)"};
  kinematics::ErrorState at = table2;
  auto active = kinematics::ActivateParameters(f.machine, &at, names);
  ASSERT_TRUE(active.ok());
  auto lin = kinematics::LineariseObservations(f.machine, at, *active, mo->observations);
  ASSERT_TRUE(lin.ok());
  Eigen::MatrixXd S(3, 3);
  S << 4, 4, 0, 4, 4, 0, 0, 0, 1;
  const Eigen::MatrixXd& A = lin->J_dev_alignment;
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ() * Eigen::MatrixXd::Identity(A.rows(), 6);
  const Eigen::MatrixXd PJ = lin->J_dev_params - Q * (Q.transpose() * lin->J_dev_params);
  const Eigen::MatrixXd K = PJ * S * PJ.transpose();
  auto split = diagnosis_internal::ReferenceNuisanceColumns(f.machine, table2, mo->observations, A,
                                                           ReferenceUncertainty{names, S, 0.5}, 1.0);
  ASSERT_TRUE(split.ok()) << split.status().message();
  const Eigen::MatrixXd& C = split->columns_um;
  const Eigen::MatrixXd& R = split->remaining_um;
  const double tol = 1e-9 * K.cwiseAbs().maxCoeff();
  EXPECT_LT((C * C.transpose() + R * R.transpose() - K).cwiseAbs().maxCoeff(), tol);
  EXPECT_LT((Q.transpose() * C).cwiseAbs().maxCoeff(), 1e-9 * C.cwiseAbs().maxCoeff());
  int carrying = 0;
  for (Eigen::Index j = 0; j < C.cols(); ++j) EXPECT_GT(C.col(j).squaredNorm(), 0.25);
  for (Eigen::Index j = 0; j < R.cols(); ++j) {
    EXPECT_LE(R.col(j).squaredNorm(), 0.25);
    carrying += R.col(j).squaredNorm() > tol;
  }
  EXPECT_LE(C.cols() + carrying, 2);
  EXPECT_GE(C.cols(), 1);  // 4 um^2 on a C location error moves hundreds of points
}

// Point reference: the "sim" is a point file simulated from the same machine errors (another
// placement and noise draw), the "real" the measured one. The gap is the difference of two
// noise draws: RMS sigma sqrt(2) sqrt((n - 6) / n) (re-alignment fitted), verdict none.
// Tolerance: the sampling scatter of an RMS of n ~ 350 values is 1 / sqrt(2 n) ~ 4 % relative;
// 20 % allows > 4 sd.
TEST(Diagnosis, PointReferenceFromTheSameErrorsGivesNoneAndNoiseGap) {
  const Fixture f = Make();
  constexpr double kNoise_um = 1.0;
  const auto errors = Table2(f.machine);
  auto measured = Simulate(f, errors, kNoise_um, 21);
  auto reference = Simulate(f, errors, kNoise_um, 22);
  ASSERT_TRUE(measured.ok() && reference.ok());
  auto d = DiagnoseAgainstPoints(f.piece, f.machine, measured->points, reference->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(d->verdict.family, "none");
  ASSERT_TRUE(d->reference_match.has_value());
  EXPECT_EQ(d->reference_match->unmatched, 0);
  EXPECT_EQ(d->reference_match->matched_by_order + d->reference_match->matched_by_nearest, d->n_points);
  EXPECT_LT(d->reference_match->max_offset_mm, 0.1);  // same plan: offsets are the errors' shifts (um)
  EXPECT_EQ(d->base_columns, 6);                       // only the re-alignment is fitted
  const double expected = kNoise_um * std::sqrt(2.0) * std::sqrt(1.0 - 6.0 / d->n_points);
  EXPECT_NEAR(d->rms_um, expected, 0.2 * expected);
  for (const auto& c : d->candidates) EXPECT_FALSE(c.significant) << c.name;
  // Reference errors equal to the measured piece's: location_errors explains nothing beyond noise.
  EXPECT_TRUE(std::any_of(d->candidates.begin(), d->candidates.end(),
                          [](const CandidateResult& c) { return c.family == "location_errors"; }));
}

// Reference files that differ in count: every 4th point of S1 dropped from the reference. S1 is
// then matched by nearest nominal position; the measured points whose partner is gone have no
// reference point within 1 mm (the plan spacing on S1 is far larger) and are skipped and listed.
TEST(Diagnosis, PointReferenceWithMissingPointsMatchesByNearestAndSkips) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine);
  auto measured = Simulate(f, errors, 1.0, 25);
  auto reference = Simulate(f, errors, 1.0, 26);
  ASSERT_TRUE(measured.ok() && reference.ok());
  PointSet thinned = reference->points;
  const auto s1 = thinned.IndicesOf("S1");
  ASSERT_GE(s1.size(), 8u);
  std::vector<bool> drop(thinned.size(), false);
  int dropped = 0;
  for (std::size_t k = 0; k < s1.size(); k += 4) drop[s1[k]] = true, ++dropped;
  PointSet kept = thinned;
  kept.xyz_mm.clear();
  kept.normal.clear();
  kept.feature.clear();
  kept.line.clear();
  kept.attributes.clear();
  for (std::size_t i = 0; i < thinned.size(); ++i) {
    if (drop[i]) continue;
    kept.xyz_mm.push_back(thinned.xyz_mm[i]);
    if (!thinned.normal.empty()) kept.normal.push_back(thinned.normal[i]);
    kept.feature.push_back(thinned.feature[i]);
    if (!thinned.line.empty()) kept.line.push_back(thinned.line[i]);
  }
  auto d = DiagnoseAgainstPoints(f.piece, f.machine, measured->points, kept);
  ASSERT_TRUE(d.ok()) << d.status().message();
  ASSERT_TRUE(d->reference_match.has_value());
  EXPECT_EQ(d->reference_match->unmatched, dropped);
  EXPECT_EQ(d->reference_match->matched_by_nearest, static_cast<int>(s1.size()) - dropped);
  EXPECT_LT(d->reference_match->max_offset_mm, 0.1);
  EXPECT_EQ(d->n_points, static_cast<int>(measured->points.size()) - dropped);
  EXPECT_GE(d->skipped_points.size(), static_cast<std::size_t>(dropped));
  EXPECT_EQ(d->verdict.family, "none");
}

// The same reference against a piece cut with a withheld drift: the gap is the drift.
TEST(Diagnosis, PointReferenceNamesAWithheldDrift) {
  const Fixture f = Make();
  auto measured = Simulate(f, Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_Y0A, K_um: 12, tau_s: 2400}\n"),
                           0.5, 23);
  auto reference = Simulate(f, Table2(f.machine), 0.5, 24);
  ASSERT_TRUE(measured.ok() && reference.ok());
  DiagnosisOptions o;
  o.reference_name = "simulated.csv";
  auto d = DiagnoseAgainstPoints(f.piece, f.machine, measured->points, reference->points, o);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(d->verdict.family, "thermal_drift");
  EXPECT_GT(d->candidates.front().cv_shrink_pct, 30.0);
  EXPECT_NE(d->base_model.find("simulated.csv"), std::string::npos);
  // Reference machine errors and a reference point file together are refused.
  o.reference = Table2(f.machine);
  EXPECT_FALSE(DiagnoseAgainstPoints(f.piece, f.machine, measured->points, reference->points, o).ok());
}

// Feature cross-validation in the diagnosis: cv_* are leave-one-feature-out over the features
// each candidate can hold out (the same set before and after), PRESS kept beside them.
TEST(Diagnosis, CrossValidationHoldsOutFeatures) {
  const Fixture f = Make();
  auto sim = Simulate(f, Table2(f.machine), 1.0, 31);
  ASSERT_TRUE(sim.ok());
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_EQ(d->n_features, 30);  // S_R, B_R, H1..H16, S1..S6, B1..B6
  EXPECT_EQ(d->cv_features + static_cast<int>(d->cv_not_held_out.size()), d->n_features);
  // S4 and S5 each alone carry a direction of the base model (the other features hold less than
  // holdout_tolerance = 5 % of its information): reported, not held out. Every other feature is.
  // (S4: with dx_CR(0) acting at A = -90 too, the holes, S1 and S3 see dx_CR(0) and the Z
  // squareness beta_ZX only as about dx_CR(0) - beta_ZX z_R; S4, 245 mm below S_R, separates them.)
  // S_R: the only feature milled by X-Y interpolation, so the only one that sees the X-Y
  // squareness E_C(0X)Y (its ellipse).
  EXPECT_EQ(d->cv_not_held_out, (std::vector<std::string>{"S_R", "S4", "S5"}));
  // The servo candidates act on the groove S_R only, which they make unholdable: no held-out
  // feature carries them, so they are judged by PRESS and say so.
  bool saw_servo = false;
  for (const auto& c : d->candidates) {
    if (c.family != "servo_reversal") continue;
    saw_servo = true;
    EXPECT_EQ(c.cv_method, "leave-one-point-out") << c.name;
    EXPECT_EQ(c.cv_rms_after_um, c.press_rms_after_um);
  }
  EXPECT_TRUE(saw_servo);
  for (const auto& c : d->candidates) {
    EXPECT_LE(c.cv_features, d->cv_features) << c.name;
    EXPECT_EQ(c.cv_features + static_cast<int>(c.cv_not_held_out.size()), d->n_features) << c.name;
    for (const auto& name : d->cv_not_held_out)  // the base's unholdable features stay unholdable
      EXPECT_NE(std::find(c.cv_not_held_out.begin(), c.cv_not_held_out.end(), name), c.cv_not_held_out.end()) << c.name;
    EXPECT_GT(c.press_rms_before_um, 0.0);
    // A prediction from fewer points is no better than the in-sample fit.
    if (c.cv_features > 0) {
      EXPECT_GE(c.cv_rms_after_um, 0.9 * c.rms_after_um) << c.name;
    }
  }
  const auto j = nlohmann::json::parse(DiagnosisJson(*d));
  EXPECT_EQ(j["cross_validation"]["method"], "leave-one-feature-out");
  EXPECT_TRUE(j["candidates"][0].contains("press_rms_after_um"));
  EXPECT_TRUE(j["candidates"][0].contains("cv_not_held_out"));
}

// A straightness error along Z (cubic table over the Z range the plan uses, linear trend removed):
// the straightness candidates' polynomial columns are fixed by the features at the ends of the Z
// range, which they make unholdable although the base model holds them out. Their feature-CV
// would then cover fewer features than the base's (leaving out those where they extrapolate
// worst), so they are judged by PRESS, say so, and are compared with every other candidate by
// PRESS; the verdict is still the straightness.
TEST(Diagnosis, CandidateThatMakesBaseFeaturesUnholdableIsJudgedByPress) {
  const Fixture f = Make();
  auto plan = testpieces::MakeProbingPlan(f.piece);
  ASSERT_TRUE(plan.ok());
  double lo = 1e300, hi = -1e300;
  for (const auto& pp : plan->points) lo = std::min(lo, pp.cut.axes.z_mm), hi = std::max(hi, pp.cut.axes.z_mm);
  ASSERT_GT(hi - lo, 10.0);
  const auto at = [&](double u) { return lo - 1.0 + (hi - lo + 2.0) * u; };
  // A bow with a small wave (its linear part is squareness, which the base model absorbs), +-60 um:
  // the base model absorbs most of it (S1 and S4 radii, S_R and hole centres), a +-20 um bow left
  // a visible signature of only 0.23 um RMS at 0.5 um noise.
  const std::string effect = fmt::format(
      "effects:\n  - linear_error_motion: {{symbol: E_XZ, positions_mm: [{}, {}, {}, {}, {}], "
      "values_um: [60, -15, -60, -30, 45], interpolation: cubic}}\n",
      at(0), at(0.25), at(0.5), at(0.75), at(1));
  auto sim = Simulate(f, Table2(f.machine, effect), 0.5, 41);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(f.piece, f.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  ASSERT_EQ(d->verdict.family, "linear_straightness") << DiagnosisText(*d);
  const auto& best = d->candidates.front();
  EXPECT_EQ(best.cv_method, "leave-one-point-out");
  EXPECT_FALSE(best.cv_method_reason.empty());
  EXPECT_LT(best.cv_features, d->cv_features);  // it loses features the base holds out
  EXPECT_EQ(best.cv_rms_before_um, best.press_rms_before_um);
  EXPECT_EQ(best.cv_rms_after_um, best.press_rms_after_um);
  EXPECT_GT(best.cv_shrink_pct, 30.0) << DiagnosisText(*d);
  for (const auto& c : d->candidates) {  // feature-tested candidates hold out exactly the base's features
    if (c.cv_method == "leave-one-feature-out") {
      EXPECT_EQ(c.cv_features, d->cv_features) << c.name;
    }
  }
  const auto j = nlohmann::json::parse(DiagnosisJson(*d));
  EXPECT_EQ(j["candidates"][0]["cv_method"], "leave-one-point-out");
  EXPECT_TRUE(j["candidates"][0].contains("cv_method_reason"));
}

// Straightness of X on the flank-milled cone: along each section X runs over +-32 mm as C turns,
// so a straightness table with more wiggles than a quartic can follow (5 nodes, cubic) is fitted
// better by the 2-to-5-lobe radial error motion of C than by the quartic straightness candidate
// (the verdict was rotary_error_motion before the sextic candidate). Truth: the straightness
// effect alone (no base errors, datum placement), noise 0.5 um against a signature of ~30 um;
// twenty noise seeds. The radial motion reproduces more than 90 % of the straightness signature on
// this piece, so each verdict must name the other family indistinguishable (never a second
// effect), and straightness must be the verdict in at least 15 of the 20 (measured: 18; the two
// families' cross-validated rms differ by less than the noise, so a few seeds go the other way).
TEST(Diagnosis, ConeStraightnessBeyondAQuarticIsStillStraightness) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(m.ok());
  testpieces::PieceConfig c;
  c.params = testpieces::ConeFrustumParams{};
  auto piece = testpieces::MakeTestPiece(c, *m);
  ASSERT_TRUE(piece.ok()) << piece.status().message();
  auto errors = kinematics::ParseErrorState(
      "effects:\n  - {linear_error_motion: {symbol: E_YX, positions_mm: [-32.2172, -16.1086, 0, 16.1086, 32.2172], "
      "values_um: [15.0, -38.0, 52.0, -50.0, 21.0], interpolation: cubic}}\n",
      "<test>", *m);
  ASSERT_TRUE(errors.ok()) << errors.status().message();
  int straightness = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    testpieces::PieceSimOptions o;
    o.noise_um = 0.5;
    o.seed = seed;
    auto sim = testpieces::SimulatePiece(*piece, *m, *errors, o);
    ASSERT_TRUE(sim.ok()) << sim.status().message();
    auto d = Diagnose(*piece, *m, sim->points);
    ASSERT_TRUE(d.ok()) << d.status().message();
    const std::string& family = d->verdict.family;
    ASSERT_TRUE(family == "linear_straightness" || family == "rotary_error_motion")
        << "seed " << seed << "\n" << DiagnosisText(*d);
    straightness += family == "linear_straightness";
    const std::string other = family == "linear_straightness" ? "rotary_error_motion" : "linear_straightness";
    const auto& ind = d->verdict.indistinguishable_from;
    EXPECT_NE(std::find(ind.begin(), ind.end(), other), ind.end()) << "seed " << seed << "\n" << DiagnosisText(*d);
    EXPECT_NE(d->verdict.also, other) << "seed " << seed;
  }
  std::printf("cone straightness: verdict linear_straightness for %d of 20 seeds\n", straightness);
  EXPECT_GE(straightness, 15);
}

// A caller's nominal slot design (tpcal run shares it with the identification) gives the
// diagnosis it would have made itself: the same slots at the same state, so the same numbers
// (tolerance 0); one that lacks slots is not used.
TEST(Diagnosis, SharedNominalSlotDesignGivesTheSameDiagnosis) {
  const Fixture f = Make();
  const auto errors = Table2(f.machine, "effects:\n  - thermal_drift: {parameter: E_X0C, rate_um_per_h: 6}\n");
  auto mo = SimulatedObservations(f, errors, 0.5, 5);
  ASSERT_TRUE(mo.ok()) << mo.status().message();
  auto own = DiagnoseObservations(f.piece, f.machine, *mo);
  ASSERT_TRUE(own.ok()) << own.status().message();
  ASSERT_EQ(own->verdict.family, "thermal_drift") << DiagnosisText(*own);
  auto slots = NominalDiagnosisSlots(f.piece, f.machine, DiagnosisOptions{});
  ASSERT_TRUE(slots.ok()) << slots.status().message();
  auto design = kinematics::LineariseSlots(f.machine, kinematics::ErrorState(f.machine), *slots, mo->observations);
  ASSERT_TRUE(design.ok()) << design.status().message();
  DiagnosisOptions o;
  o.nominal_slot_design = std::make_shared<const kinematics::SlotDesign>(std::move(*design));
  auto shared = DiagnoseObservations(f.piece, f.machine, *mo, o);
  ASSERT_TRUE(shared.ok()) << shared.status().message();
  EXPECT_EQ(shared->gap_um, own->gap_um);
  EXPECT_EQ(shared->verdict.family, own->verdict.family);
  ASSERT_EQ(shared->candidates.size(), own->candidates.size());
  for (std::size_t k = 0; k < own->candidates.size(); ++k) {
    EXPECT_EQ(shared->candidates[k].name, own->candidates[k].name);
    EXPECT_EQ(shared->candidates[k].rms_after_um, own->candidates[k].rms_after_um);
  }
  // Without the candidates' slots the design cannot serve: the diagnosis makes its own.
  auto partial = kinematics::LineariseSlots(f.machine, kinematics::ErrorState(f.machine),
                                            std::vector<kinematics::ErrorSlot>(slots->begin(), slots->begin() + 2),
                                            mo->observations);
  ASSERT_TRUE(partial.ok());
  o.nominal_slot_design = std::make_shared<const kinematics::SlotDesign>(std::move(*partial));
  auto fallback = DiagnoseObservations(f.piece, f.machine, *mo, o);
  ASSERT_TRUE(fallback.ok()) << fallback.status().message();
  EXPECT_EQ(fallback->gap_um, own->gap_um);
}

// Withheld `families` at 10x the noise (1 um), `trials` each (seed 11), on the cone piece with the
// extra cones at these offsets (0: none): the observable trials and those named right.
struct Named {
  int counted = 0, correct = 0;
  std::string markdown;
};
Result<Named> ValidateOnCones(double second_mm, double third_mm, std::vector<std::string> families, int trials) {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  if (!m.ok()) return m.status();
  testpieces::PieceConfig config;
  testpieces::ConeFrustumParams cone;
  cone.base_size_mm = 380;
  cone.second_cone_offset_mm = second_mm;
  cone.third_cone_offset_mm = third_mm;
  config.params = cone;
  auto piece = testpieces::MakeTestPiece(config, *m);
  if (!piece.ok()) return piece.status();
  ValidationOptions v;
  v.families = std::move(families);
  v.magnitudes = {10.0};
  v.noise_um = {1.0};
  v.trials = trials;
  v.seed = 11;
  auto s = RunValidation(*piece, *m, v);
  if (!s.ok()) return s.status();
  Named out;
  for (const auto& t : s->trials) {
    if (!t.observable) continue;
    ++out.counted;
    out.correct += t.verdict == t.true_family ? 1 : 0;
  }
  out.markdown = ValidationMarkdown(*s);
  return out;
}

// The validation harness on a small fixed-seed run: the targets where observable.
// The enriched cone piece (testpieces/iso10791_pieces.h: a second cone 130 mm along +X, its own
// flank pass): on one cone X, Y and C move together, so straightness of X and the radial motion of
// C alias; the second cone's X(C) separates them. Withheld at 10x the noise (1 um), 3 trials each
// on the default 16-point sections: every straightness and rotary-error-motion trial is named
// right (the 540-trial matrix in the README: 96 % and 100 % at >= 5x; on one cone 73 % and 36 %).
TEST(Diagnosis, SecondConeSeparatesStraightnessFromRotaryErrorMotion) {
  auto r = ValidateOnCones(130, 0, {"linear_straightness", "rotary_error_motion"}, 3);
  ASSERT_TRUE(r.ok()) << r.status().message();
  ASSERT_GE(r->counted, 3);
  EXPECT_EQ(r->correct, r->counted) << r->markdown;
}

// The third cone (130 mm along +Y): on two cones a first-harmonic angular positioning error of C
// leaves a field whose X^2 and Y^2 parts a quadratic straightness of X and Y also makes (README:
// 61 % top-1 over 540 trials; with this test's options 5 of 6 at seeds 11 and 12); on the cone a
// quarter turn away the two fall on the pass with other phases. Withheld at 10x the noise (1 um),
// 6 trials on 16-point sections: every trial is named rotary_positioning.
TEST(Diagnosis, ThirdConeSeparatesRotaryPositioningFromStraightness) {
  auto r = ValidateOnCones(130, 130, {"rotary_positioning"}, 6);
  ASSERT_TRUE(r.ok()) << r.status().message();
  ASSERT_EQ(r->counted, 6);
  EXPECT_EQ(r->correct, r->counted) << r->markdown;
}

// Observability in the validation is what the diagnosis can see: on the single cone a drift is
// 2-3 % visible by the linear projection at the nominal state, and scaled up to a 10x peak the base
// fit absorbs it (gap at noise level); such trials count unobservable, not as misses named none.
// On the turning piece the same family stays observable.
TEST(Diagnosis, ValidationCountsWhatTheBaseFitAbsorbsAsUnobservable) {
  const Fixture cone = MakeCone();
  ValidationOptions v;
  v.families = {"thermal_drift"};
  v.magnitudes = {10.0};
  v.noise_um = {1.0};
  v.trials = 6;
  v.seed = 11;
  auto s = RunValidation(cone.piece, cone.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  for (const auto& t : s->trials) {
    EXPECT_FALSE(t.observable) << t.true_detail << ": verdict " << t.verdict;
    EXPECT_LT(t.visible_fraction, 0.02) << t.true_detail;
  }
  const Fixture f = Make();
  auto turning = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(turning.ok()) << turning.status().message();
  for (const auto& t : turning->trials) EXPECT_TRUE(t.observable) << t.true_detail;
}

// Weak observability is said, not hidden: on the single cone's one flank pass a typical drift or
// scale signature keeps 8 % and 4 % outside the base model (the validation finds them unobservable
// in 59 and 60 of 60 trials), so the report names both with that share; the turning piece's least
// visible family keeps 26 % and nothing is named. Noise 0.5 um, no effect, seeds fixed.
TEST(Diagnosis, WeaklyObservableFamiliesAreNamed) {
  const Fixture c = MakeCone();
  auto sim = Simulate(c, kinematics::ErrorState(c.machine), 0.5, 3);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  auto d = Diagnose(c.piece, c.machine, sim->points);
  ASSERT_TRUE(d.ok()) << d.status().message();
  std::map<std::string, double> weak;
  for (const auto& w : d->weakly_observable) weak[w.family] = w.visible_share;
  ASSERT_EQ(weak.size(), 2u) << DiagnosisText(*d);
  EXPECT_GT(weak["thermal_drift"], 0.02);
  EXPECT_LT(weak["thermal_drift"], 0.10);
  EXPECT_GT(weak["linear_positioning"], 0.01);
  EXPECT_LT(weak["linear_positioning"], 0.10);
  EXPECT_NE(DiagnosisText(*d).find("weakly observable: thermal_drift"), std::string::npos);
  const auto j = nlohmann::json::parse(DiagnosisJson(*d));
  EXPECT_EQ(j["weakly_observable"].size(), 2u);
  EXPECT_TRUE(j["candidates"][0].contains("typical_visible_share_pct"));

  const Fixture f = Make();
  auto turning = Simulate(f, Table2(f.machine), 0.5, 3);
  ASSERT_TRUE(turning.ok());
  auto dt = Diagnose(f.piece, f.machine, turning->points);
  ASSERT_TRUE(dt.ok()) << dt.status().message();
  EXPECT_TRUE(dt->weakly_observable.empty()) << DiagnosisText(*dt);
}

// Servo glitches alone at 5x the 0.5 um noise (seed 3's ninth trial: X 0.80, Y 0.32 um per unit,
// decay 4.1 deg): the screen flagged the spikes at the reversals as outliers, left them out, and
// the piece read none. The diagnosis of every point names the glitches, whose model leaves no
// point to flag (FlagsAsEffect in diagnosis.cc). Truth: servo reversal in all nine trials, no
// point listed as an outlier in the ninth. (`--families servo_reversal --magnitudes 5,10 --noise
// 0.5 --trials 20`: 97 -> 98 % at seed 3, 98 -> 100 % at seed 4.)
TEST(Diagnosis, GlitchesFlaggedPointByPointAreNamedAsTheEffect) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"servo_reversal"};
  v.magnitudes = {5.0};
  v.noise_um = {0.5};
  v.trials = 9;
  v.seed = 3;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->trials.size(), 9u);
  for (const auto& t : s->trials) EXPECT_EQ(t.verdict, "servo_reversal") << t.true_detail;
  const ValidationTrial& ninth = s->trials.back();
  EXPECT_NE(ninth.true_detail.find("X 0.80, Y 0.32"), std::string::npos) << ninth.true_detail;
  EXPECT_EQ(ninth.false_flags, 0) << ninth.true_detail;
}

TEST(Diagnosis, SmallValidationMeetsTargets) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"thermal_drift",   "linear_straightness", "linear_positioning", "rotary_error_motion",
                "rotary_positioning", "tool_deflection",  "servo_reversal",     "probe_radius", "none"};
  v.magnitudes = {5.0, 10.0};
  v.noise_um = {1.0};
  v.trials = 2;
  v.seed = 2026;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  int correct = 0, counted = 0;
  for (const auto& t : s->trials) {
    if (t.true_family == "none" || !t.observable) continue;
    ++counted;
    if (t.verdict == t.true_family) ++correct;
  }
  ASSERT_GT(counted, 20);
  EXPECT_GE(static_cast<double>(correct) / counted, 0.9) << ValidationMarkdown(*s);
  EXPECT_LE(s->false_alarm_rate, 0.05);
  EXPECT_GE(s->median_cv_explained, 0.7);
}

// Real data (issue 18) on the turning piece: outliers, local defects, pairs and effects outside
// the catalogue (validation_injections.h), 5x and 10x noise, noise 0.5 and 1 um, 6 trials each,
// seed 2026. Measured at this seed: 36 of 36 outliers found at 10x, 0 clean points flagged;
// local_defect named in 20 of 24 (75 % at 5x, 92 % at 10x: a 2-hit burr tapering to 0.7 of its
// peak has its second hit at 3.5 sigma); fixture_bend, spindle_growth and lobes7 never none (72 of
// 72); pairs both named 20 of 23 observable (19 by forward selection alone, before the joint pair
// search); 1 false alarm in 24 effect-free pieces. Bounds: the measured rates less about two
// binomial standard deviations of 24 trials (sd 8 % at 85 %), the targets where the
// measurement meets them (outliers, false flags, out-of-catalogue); local_defect is below the
// issue's 90 % at 5x (README, "Real data") and guarded where it is.
TEST(Diagnosis, RealDataValidationMeetsTargets) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"outliers", "local_defect", "pairs", "fixture_bend", "spindle_growth", "lobes7", "none"};
  v.magnitudes = {5.0, 10.0};
  v.noise_um = {0.5, 1.0};
  v.trials = 6;
  v.seed = 2026;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  const std::string md = ValidationMarkdown(*s);
  EXPECT_GE(s->outliers_found_rate, 0.95) << md;
  EXPECT_LE(s->false_flag_rate, 0.01) << md;
  EXPECT_LE(s->false_alarm_rate, 0.1) << md;
  EXPECT_GE(s->top1_rate["local_defect"], 0.7) << md;
  for (const char* ooc : {"fixture_bend", "spindle_growth", "lobes7"}) EXPECT_GE(s->top1_rate[ooc], 0.9) << ooc << md;
  EXPECT_GE(s->top1_rate["pairs"], 0.7) << md;
}

// Local defects at 10x noise on the turning piece (noise 0.5, 1 and 2 um, 20 trials each, seed 6).
// A 4-hit chip or dent on a 16-point circle pulls the circle's fitted terms: the hits beside it can
// stand out beyond grow_z (the component is then too large to be a patch), and the far side can
// stand out as patches of the other sign, flagged in the same round when the worst-first order
// compared peaks (the feature then had too many groups and kept every point). Measured at this
// seed: local_defect top-1 55 of 60 before the screen's core rule and z order, 57 of 60 after
// (seeds 5 and 7: 51 / 54 and 56 / 58; the CLI's 240 trials at seed 5: 92 / 96 %). Bound: 56 of
// 60, which the old screen fails.
TEST(Diagnosis, ChipsOnCirclesAtTenTimesNoiseAreLocalDefects) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"local_defect"};
  v.magnitudes = {10.0};
  v.noise_um = {0.5, 1.0, 2.0};
  v.trials = 20;
  v.seed = 6;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_GE(s->top1_rate["local_defect"], 56.0 / 60.0 - 1e-9) << ValidationMarkdown(*s);
}

// A straightness whose visible part the base leaves on one feature (the axis range only that
// feature spans) is flagged as patches on both sides of the model; it read local_defect. When the
// diagnosis of every point names an effect whose model leaves no patch, that effect is the verdict
// (PatchAsEffect in diagnosis.cc). Truth: straightness withheld, seed 8, 40 trials at 5 and 10x,
// 0.5 and 1 um: one read local_defect before and 34 straightness; now none and 35 (the CLI's
// single-family matrix, README "Real data": straightness 86 / 88 %). Bound: no local_defect, and
// straightness top-1 at least 80 %.
TEST(Diagnosis, StraightnessLeftOnOneFeatureIsNotALocalDefect) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"linear_straightness"};
  v.magnitudes = {5.0, 10.0};
  v.noise_um = {0.5, 1.0};
  v.trials = 10;
  v.seed = 8;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  for (const ValidationTrial& t : s->trials) EXPECT_NE(t.verdict, "local_defect") << t.true_detail;
  EXPECT_GE(s->top1_rate["linear_straightness"], 0.8) << ValidationMarkdown(*s);
}

// The runner-up, the second effect tested beyond the verdict, is the candidate of another family
// that adds most beyond it, not the family's candidate that explains most alone. Truth: pairs
// withheld (validation_injections.h), seed 13, 40 trials at 5x, noise 1 um: both named in 25 with
// each family's best alone, 29 with every candidate. Bound: 28, which the former fails.
TEST(Diagnosis, TheRunnerUpIsTheCandidateThatAddsMost) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"pairs"};
  v.magnitudes = {5.0};
  v.noise_um = {1.0};
  v.trials = 40;
  v.seed = 13;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_GE(s->top1_rate["pairs"], 28.0 / 40.0 - 1e-9) << ValidationMarkdown(*s);
}

// Two ways a second effect went unnamed. Its part the verdict's model leaves on a few features was
// flagged as patches and left out: when the diagnosis of every point names a pair whose model
// leaves no patch, the pair is the verdict (PatchAsSecondEffect in diagnosis.cc). And a runner-up
// that adds overwhelmingly (p < alpha_each^2) was dropped for predicting held-out features less
// than 10 % better (PairCvMeanSquareRatio in diagnosis_verdict.cc). Truth: pairs withheld, seed 13,
// 40 trials at 5 and 10x, noise 0.5 and 1 um, 158 observable: one family beside local_defect /
// both named, with neither step 6 / 130, the patch step alone 4 / 132, the CV ratio alone 6 / 131,
// both 3 / 134. Bound: at most 4 and at least 133, which each step alone fails.
TEST(Diagnosis, ASecondEffectIsNamedBesideAStrongVerdict) {
  const Fixture f = Make();
  ValidationOptions v;
  v.families = {"pairs"};
  v.magnitudes = {5.0, 10.0};
  v.noise_um = {0.5, 1.0};
  v.trials = 40;
  v.seed = 13;
  auto s = RunValidation(f.piece, f.machine, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  int one_beside_patches = 0, observable = 0;
  for (const ValidationTrial& t : s->trials) {
    if (t.verdict_families.size() == 2 && t.verdict_families[1] == "local_defect") ++one_beside_patches;
    if (t.observable) ++observable;
  }
  EXPECT_LE(one_beside_patches, 4) << ValidationMarkdown(*s);
  ASSERT_EQ(observable, 158);
  EXPECT_GE(s->top1_rate["pairs"], 133.0 / 158.0 - 1e-9) << ValidationMarkdown(*s);
}

// On the enriched cone a second effect often aliases: a wrong `also` (probe_radius, or the other
// linear family) reproduces what the true second adds beyond the verdict. The verdict says so
// (also_indistinguishable_from), and the validation counts such a trial as "top-1 or alias".
// Truth: the two withheld families. Pairs at 5x, noise 0.5 um, 60 trials, seed 11 (measured: 8
// of 17 observable trials name both, 13 name or alias both, 5 of them through `also`'s list); the
// list never holds the verdict's own families, and at least 3 trials are named only through it.
TEST(Diagnosis, AnAliasedSecondEffectIsSaidIndistinguishable) {
  auto named = testpieces::NamedPieceConfig("cone_frustum_enriched");
  ASSERT_TRUE(named.ok()) << named.status().message();
  auto m = kinematics::MakeMachine(named->usual_machine);
  ASSERT_TRUE(m.ok());
  auto piece = testpieces::MakeTestPiece(named->config, *m);
  ASSERT_TRUE(piece.ok()) << piece.status().message();
  ValidationOptions v;
  v.families = {"pairs"};
  v.magnitudes = {5.0};
  v.noise_um = {0.5};
  v.trials = 60;
  v.seed = 11;
  auto s = RunValidation(*piece, *m, v);
  ASSERT_TRUE(s.ok()) << s.status().message();
  int through_also = 0, with_list = 0;
  for (const ValidationTrial& t : s->trials) {
    if (!t.observable || t.also_indistinguishable_from.empty()) continue;
    ++with_list;
    for (const auto& f : t.also_indistinguishable_from)
      EXPECT_EQ(std::count(t.verdict_families.begin(), t.verdict_families.end(), f), 0) << f;
    const auto missing = std::count_if(t.pair_families.begin(), t.pair_families.end(), [&](const std::string& f) {
      return std::count(t.verdict_families.begin(), t.verdict_families.end(), f) == 0 &&
             std::count(t.indistinguishable_from.begin(), t.indistinguishable_from.end(), f) == 0;
    });
    const auto via_also = std::count_if(t.pair_families.begin(), t.pair_families.end(), [&](const std::string& f) {
      return std::count(t.also_indistinguishable_from.begin(), t.also_indistinguishable_from.end(), f) > 0;
    });
    if (missing > 0 && via_also == missing) ++through_also;
  }
  EXPECT_GE(through_also, 3) << with_list << " trials with a list\n" << ValidationMarkdown(*s);
  EXPECT_GT(s->top1_or_alias_rate["pairs"], s->top1_rate["pairs"]) << ValidationMarkdown(*s);
}

}  // namespace
}  // namespace tpcal::pipeline
