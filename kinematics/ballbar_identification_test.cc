// Ball-bar identification (kinematics/ballbar_identification.h) on the seed 003 machine
// (samples/machines/bhead_ctable.yaml) with seed003_setups.yaml's seven C installations.
// Truths and tolerances:
//   kBbiTZeroTol = 1e-9 (um, urad): zero errors, dl is rounding only (~1e-11 um);
//   random truths: a noisy fit is judged by its own u (within 4 u always, beyond 3 u rarely);
//   the truth compared is its part the data can see: t - B B^T t, B the not-separable basis
//   (the parts along B are absorbed by the offsets and the centring, by the convention stated).
#include "kinematics/ballbar_identification.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/portable_random.h"
#include "core/units.h"
#include "kinematics/ballbar_setup.h"
#include "kinematics/error_parameters.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::kinematics {
namespace {

constexpr double kBbiTZeroTol = 1e-9;
constexpr double kBbiTNoise_um = 0.5;
// Second-order remainder of the axial bar: the lateral motion of the tool ball, |delta| + |eps|
// * 200 mm <~ 14 um, gives |lateral|^2 / (2 * 150 mm) <~ 7e-4 um.
constexpr double kBbiTSecondOrder_um = 1e-3;
constexpr double kBbiTAmplitude_um = 5.0, kBbiTAmplitude_urad = 10.0;
constexpr char kBbiTDirections[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};

MachineModel BbiTMachine() {
  auto m = LoadMachineModel(std::string(TPCAL_SOURCE_DIR) + "/samples/machines/bhead_ctable.yaml");
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  return *m;
}

// The installations of seed003_setups.yaml that turn `axis`, in file order.
std::vector<BallbarGeometry> BbiTInstallations(const MachineModel& m, Axis axis) {
  auto setup = LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
  EXPECT_TRUE(setup.ok()) << setup.status().ToString();
  std::vector<BallbarGeometry> out;
  for (const BallbarInstallation& i : setup->installations) {
    if (i.kind == BallbarKind::kCircle || i.axis != axis) continue;
    auto g = MakeBallbarGeometry(m, i);
    EXPECT_TRUE(g.ok()) << g.status().ToString();
    out.push_back(*g);
  }
  return out;
}

// The seven C installations.
std::vector<BallbarGeometry> BbiTCInstallations(const MachineModel& m) {
  auto out = BbiTInstallations(m, Axis::kC);
  EXPECT_EQ(out.size(), 7u);
  return out;
}

// A truth: the six C error motions as Fourier series of orders 2 and 3 (cos and sin), amplitudes
// ~5 um / 10 urad. `coef[d]` holds cos2, sin2, cos3, sin3 (display units).
struct BbiTTruth {
  ErrorState errors;
  std::vector<std::vector<double>> coef;
  double At(int d, double angle_deg) const {
    const double q = DegToRad(angle_deg);
    return coef[d][0] * std::cos(2 * q) + coef[d][1] * std::sin(2 * q) + coef[d][2] * std::cos(3 * q) +
           coef[d][3] * std::sin(3 * q);
  }
};

BbiTTruth BbiTRandomTruth(const MachineModel& m, std::mt19937_64& rng, Axis axis = Axis::kC) {
  BbiTTruth t{ErrorState(m), {}};
  for (int d = 0; d < 6; ++d) {
    ErrorTerm term;
    term.kind = TermKind::kFourier;
    term.label = std::string("E_") + kBbiTDirections[d] + AxisLetter(axis);
    term.quantity = d < 3 ? Quantity::kLength : Quantity::kAngle;
    term.effects = {SlotEffect{axis, static_cast<Component>(d), 1.0}};
    term.argument = axis;
    term.orders = {2, 2, 3, 3};
    term.is_sine = {false, true, false, true};
    std::vector<double> c;
    for (int k = 0; k < 4; ++k) c.push_back((d < 3 ? kBbiTAmplitude_um : kBbiTAmplitude_urad) * StandardNormal(rng) / 2.0);
    for (double v : c) term.coefficients.push_back(d < 3 ? UmToMm(v) : v * 1e-6);
    t.coef.push_back(c);
    EXPECT_TRUE(t.errors.AddTerm(m, term).ok());
  }
  return t;
}

// Readings at `angles_deg` (default: the C table's 0 to 340 deg every 20 deg).
std::vector<BallbarReading> BbiTSimulate(const MachineModel& m, const ErrorState& e,
                                         const std::vector<BallbarGeometry>& gs, std::mt19937_64* rng,
                                         double noise_um, std::vector<double> angles_deg = {}) {
  if (angles_deg.empty())
    for (double a = 0.0; a <= 340.0; a += 20.0) angles_deg.push_back(a);
  std::vector<BallbarReading> out;
  Workspace ws;
  for (int j = 0; j < static_cast<int>(gs.size()); ++j)
    for (double a : angles_deg) {
      auto dl = SimulateBallbarDlUm(m, e, gs[j], a, 0.0, &ws);
      EXPECT_TRUE(dl.ok());
      out.push_back({j, a, *dl + (noise_um > 0.0 ? noise_um * StandardNormal(*rng) : 0.0), 0.0, 0});
    }
  return out;
}

// The truth at the entries, minus its part along the not-separable basis.
Eigen::VectorXd BbiTVisibleTruth(const BallbarIdentification& r, const BbiTTruth& t) {
  Eigen::VectorXd v(static_cast<int>(r.entries.size()));
  for (int e = 0; e < v.size(); ++e) {
    const std::string& s = r.entries[e].symbol;
    int d = 0;
    while (kBbiTDirections[d] != s[2]) ++d;
    v(e) = t.At(d, r.entries[e].angle_deg);
  }
  const Eigen::MatrixXd& b = r.not_separable_basis;
  return b.cols() > 0 ? Eigen::VectorXd(v - b * (b.transpose() * v)) : v;
}

TEST(BallbarIdentification, ZeroErrorsGiveZeroMaps) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTCInstallations(m);
  const auto readings = BbiTSimulate(m, ErrorState(m), gs, nullptr, 0.0);
  auto r = IdentifyBallbar(m, gs, readings);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->angle_deg.size(), 18u);
  EXPECT_TRUE(r->periodic);
  for (const BallbarErrorEntry& e : r->entries) EXPECT_NEAR(e.value, 0.0, kBbiTZeroTol) << e.coefficient;
  for (const BallbarSetupTerm& s : r->setup_terms) EXPECT_NEAR(s.value_um, 0.0, kBbiTZeroTol) << s.name;
}

// The linear axes' squareness is not in the ball bar's model: on seed 003's seven C
// installations (bhead_ctable) 15, -12 and 10 urad of E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z alone leave C
// maps of several um. BallbarMapResponse (one column per display unit of each) times those values
// must be the maps IdentifyBallbar gives: the identification is linear, and the chain's second
// order is about (15 urad x 500 mm)^2 / 150 mm = 4e-4 um (tolerance 1e-3 in the entries' display
// units, um or urad; measured 1.7e-4 at most).
TEST(BallbarIdentification, MapResponseIsWhatTheSquarenessLeavesInTheMaps) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTCInstallations(m);
  const std::vector<std::string> names = LinearSquarenessSet();
  const Eigen::Vector3d values_urad(15.0, -12.0, 10.0);
  ErrorState e(m);
  auto active = ActivateParameters(m, &e, names);
  ASSERT_TRUE(active.ok()) << active.status().ToString();
  for (int k = 0; k < 3; ++k) e.set_coefficient(active->coefficients[k], values_urad(k) * 1e-6);
  const auto readings = BbiTSimulate(m, e, gs, nullptr, 0.0);
  auto r = IdentifyBallbar(m, gs, readings);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto response = BallbarMapResponse(m, gs, readings, names);
  ASSERT_TRUE(response.ok()) << response.status().ToString();
  ASSERT_EQ(response->rows(), static_cast<Eigen::Index>(r->entries.size()));
  const Eigen::VectorXd predicted = *response * values_urad;
  double largest = 0.0;
  for (std::size_t i = 0; i < r->entries.size(); ++i) {
    EXPECT_NEAR(predicted(static_cast<Eigen::Index>(i)), r->entries[i].value, 1e-3) << r->entries[i].coefficient;
    largest = std::max(largest, std::abs(r->entries[i].value));
  }
  EXPECT_GT(largest, 1.0) << "the squareness leaves nothing in the maps";
  EXPECT_FALSE(BallbarMapResponse(m, gs, readings, {"E_Q(0X)Y"}).ok());
  EXPECT_FALSE(BallbarMapResponse(m, gs, readings, {"E_C(0X)Y", "E_C(0X)Y"}).ok());
}

TEST(BallbarIdentification, RandomTruthWithinItsUncertainty) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTCInstallations(m);
  std::mt19937_64 rng(3003);
  const BbiTTruth truth = BbiTRandomTruth(m, rng);
  const auto readings = BbiTSimulate(m, truth.errors, gs, &rng, kBbiTNoise_um);
  auto r = IdentifyBallbar(m, gs, readings);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::printf("rows %d unknowns %d rank %d dof %d sigma %.3f um (noise %.1f)\n", r->rows, r->unknowns, r->rank,
              r->dof, r->sigma_um, kBbiTNoise_um);
  for (const std::string& s : r->not_separable) std::printf("  not separable: %s\n", s.c_str());
  // What the seven installations cannot separate, with offsets and centring fitted: for each of
  // the six measured combinations (radial / tangential / axial translation and tilt) its mean
  // (length offsets) and its first harmonic (centring): 18 families, no other direction.
  EXPECT_EQ(r->rank, r->unknowns - 18);
  ASSERT_EQ(r->not_separable.size(), 18u);
  for (const std::string& s : r->not_separable) EXPECT_EQ(s.find("further"), std::string::npos) << s;
  int n_offsets = 0, n_centring = 0;
  for (const std::string& s : r->not_separable) {
    n_offsets += s.find("mean over C: confounded with the length offsets") != std::string::npos;
    n_centring += s.find("component: confounded with the centring") != std::string::npos;
  }
  EXPECT_EQ(n_offsets, 6);
  EXPECT_EQ(n_centring, 12);
  // Every entry gets a number relative to the convention, none from the data alone.
  EXPECT_TRUE(r->not_identifiable.empty());
  EXPECT_EQ(r->convention_dependent, 108);
  ASSERT_TRUE(r->sigma_known);
  const Eigen::VectorXd visible = BbiTVisibleTruth(*r, truth);
  // Orders >= 2 are free of the centring for E_ZC and E_CC only: order 2 of E_XC, E_YC, E_AC,
  // E_BC puts a first harmonic into the radial / tangential combinations (printed, not asserted).
  Eigen::VectorXd full(visible.size());
  for (int e = 0; e < full.size(); ++e) {
    int d = 0;
    while (kBbiTDirections[d] != r->entries[e].symbol[2]) ++d;
    full(e) = truth.At(d, r->entries[e].angle_deg);
  }
  std::printf("truth norm %.3f, its part along the not-separable families %.3f\n", full.norm(),
              (full - visible).norm());
  int beyond3 = 0;
  for (int e = 0; e < visible.size(); ++e) {
    const BallbarErrorEntry& x = r->entries[e];
    ASSERT_TRUE(x.identifiable) << x.coefficient;
    ASSERT_GT(x.u, 0.0) << x.coefficient;
    EXPECT_LE(std::abs(x.value - visible(e)), 4.0 * x.u) << x.coefficient;
    beyond3 += std::abs(x.value - visible(e)) > 3.0 * x.u;
  }
  std::printf("entries beyond 3 u: %d of %d\n", beyond3, static_cast<int>(visible.size()));
  EXPECT_LE(beyond3, 3);
}

TEST(BallbarIdentification, Coverage95Over200Tests) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTCInstallations(m);
  std::mt19937_64 rng(3030);
  long covered = 0, total = 0;
  for (int run = 0; run < 200; ++run) {
    const BbiTTruth truth = BbiTRandomTruth(m, rng);
    const auto readings = BbiTSimulate(m, truth.errors, gs, &rng, kBbiTNoise_um);
    auto r = IdentifyBallbar(m, gs, readings);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const Eigen::VectorXd visible = BbiTVisibleTruth(*r, truth);
    for (int e = 0; e < visible.size(); ++e) {
      const BallbarErrorEntry& x = r->entries[e];
      if (!x.identifiable) continue;
      ++total;
      covered += x.ci95_low <= visible(e) && visible(e) <= x.ci95_high;
    }
  }
  const double coverage = static_cast<double>(covered) / static_cast<double>(total);
  std::printf("95 %% intervals: coverage %.2f %% over %ld entries in 200 tests\n", 100.0 * coverage, total);
  EXPECT_GE(coverage, 0.93);
  EXPECT_LE(coverage, 0.97);
}

// The B head: seed003_setups.yaml's six B installations at Table 2's angles (B 0 to -100 deg
// every 5 deg), the same random Fourier truths on the six B error motions. Truth: the visible
// part of the truth; entries the installations leave without a number (no B installation sees
// the tilt about the bar's own direction at B -90 and B 0) are not counted. Expected, as for the
// C table: 95 % intervals cover 93-97 % of the entries (a binomial 95 % with thousands of
// entries varies by well under 1 %; the interval leaves room for the t quantile of each fit).
TEST(BallbarIdentification, BHeadCoverage95Over200Tests) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTInstallations(m, Axis::kB);
  ASSERT_EQ(gs.size(), 6u);
  std::vector<double> angles_deg;
  for (double a = 0.0; a >= -100.0; a -= 5.0) angles_deg.push_back(a);
  std::mt19937_64 rng(3031);
  long covered = 0, total = 0, beyond3 = 0, skipped = 0;
  for (int run = 0; run < 200; ++run) {
    const BbiTTruth truth = BbiTRandomTruth(m, rng, Axis::kB);
    const auto readings = BbiTSimulate(m, truth.errors, gs, &rng, kBbiTNoise_um, angles_deg);
    BallbarIdentificationOptions o;
    o.axis = Axis::kB;
    auto r = IdentifyBallbar(m, gs, readings, o);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    ASSERT_TRUE(r->sigma_known);
    const Eigen::VectorXd visible = BbiTVisibleTruth(*r, truth);
    for (int e = 0; e < visible.size(); ++e) {
      const BallbarErrorEntry& x = r->entries[e];
      if (!x.identifiable) {
        ++skipped;
        continue;
      }
      ++total;
      covered += x.ci95_low <= visible(e) && visible(e) <= x.ci95_high;
      beyond3 += std::abs(x.value - visible(e)) > 3.0 * x.u;
    }
  }
  const double coverage = static_cast<double>(covered) / static_cast<double>(total);
  std::printf("B head, 95 %% intervals: coverage %.2f %% over %ld entries in 200 tests (%ld beyond 3 u, %ld "
              "without a number)\n",
              100.0 * coverage, total, beyond3, skipped);
  EXPECT_EQ(skipped, 200 * 2);
  EXPECT_GE(coverage, 0.93);
  EXPECT_LE(coverage, 0.97);
}

// One axial installation without set-up terms: 18 readings for the 18 E_ZC nodes (dof 0, so
// sigma is unknown and no u is given); the other five motions do not reach the bar to first
// order and are named.
TEST(BallbarIdentification, AxialAloneDeterminesOnlyTheAxialTranslation) {
  const MachineModel m = BbiTMachine();
  const auto all = BbiTCInstallations(m);
  const std::vector<BallbarGeometry> gs = {all[2]};
  ASSERT_EQ(gs[0].installation.kind, BallbarKind::kAxial);
  std::mt19937_64 rng(3033);
  const BbiTTruth truth = BbiTRandomTruth(m, rng);
  const auto readings = BbiTSimulate(m, truth.errors, gs, &rng, 0.0);
  BallbarIdentificationOptions o;
  o.fit_length_offsets = false;
  o.fit_centring = false;
  auto r = IdentifyBallbar(m, gs, readings, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->rank, 18);
  EXPECT_EQ(r->dof, 0);
  EXPECT_FALSE(r->sigma_known);
  ASSERT_EQ(r->not_identifiable.size(), 90u);
  EXPECT_EQ(r->not_identifiable[0], "E_XC(C 0)");
  EXPECT_EQ(r->not_identifiable[19], "E_YC(C 20)");
  for (const BallbarErrorEntry& e : r->entries) {
    EXPECT_EQ(e.identifiable, e.symbol == "E_ZC") << e.coefficient;
    EXPECT_EQ(e.u, 0.0) << e.coefficient;
    if (e.identifiable) {  // the other motions reach the axial bar at second order only
      EXPECT_NEAR(e.value, truth.At(2, e.angle_deg), kBbiTSecondOrder_um) << e.coefficient;
    }
  }
}

TEST(BallbarIdentification, RejectsAnInstallationOfAnotherAxis) {
  const MachineModel m = BbiTMachine();
  auto gs = BbiTCInstallations(m);
  BallbarInstallation b = gs[0].installation;
  b.name = "B_radial";
  b.axis = Axis::kB;
  b.workpiece_ball_in_part_mm = Eigen::Vector3d(0, 0, 0);
  b.sense = -1;
  auto g = MakeBallbarGeometry(m, b);
  ASSERT_TRUE(g.ok()) << g.status().ToString();
  gs.push_back(*g);
  auto r = IdentifyBallbar(m, gs, {{0, 0.0, 0.0, 0.0, 0}, {0, 20.0, 0.0, 0.0, 0}});
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
}

// Seed 003 Table 3 (Ni et al., "The maximum, minimum, and average values of each axis for the C
// turntable"): displacement X, Y, axial in 1e-3 mm (um); angular X, Y, Z in 1e-5 rad, here
// converted to urad (x 10). Columns in the order E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC.
constexpr double kSeed003Table3Max[6] = {7.71, 11.1, 14.4, 2.05, 0.31, 53.7};
constexpr double kSeed003Table3Min[6] = {-7.5, 0.018, 13.6, 0.02, 0.2, 0.47};
constexpr double kSeed003Table3Avg[6] = {0.061, 5.386, 14.079, 1.0, 0.26, 25.95};

// samples/ballbar/seed003_table1_c_axis.csv: `setup,angle_deg,dl_um`, '#' comments.
std::vector<BallbarReading> BbiTReadSeed003(const std::vector<BallbarGeometry>& gs) {
  std::ifstream in(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_table1_c_axis.csv");
  EXPECT_TRUE(in.good());
  std::vector<BallbarReading> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#' || line.rfind("setup,", 0) == 0) continue;
    std::stringstream ss(line);
    std::string name, angle, dl;
    std::getline(ss, name, ',');
    std::getline(ss, angle, ',');
    std::getline(ss, dl, ',');
    int j = 0;
    while (j < static_cast<int>(gs.size()) && gs[j].installation.name != name) ++j;
    EXPECT_LT(j, static_cast<int>(gs.size())) << "line " << n << ": " << name;
    out.push_back({j, std::stod(angle), std::stod(dl), 0.0, n});
  }
  return out;
}

void BbiTPrintTable(const char* title, const BallbarIdentification& r) {
  std::printf("%s: rows %d unknowns %d rank %d dof %d sigma %.2f um\n", title, r.rows, r.unknowns, r.rank, r.dof,
              r.sigma_um);
  std::printf("  %-5s %-4s | %9s %9s %9s | %9s %9s %9s | %7s\n", "error", "unit", "max", "min", "mean", "paper max",
              "paper min", "paper avg", "max u");
  const int nn = static_cast<int>(r.angle_deg.size());
  for (int d = 0; d < 6; ++d) {
    double mx = -1e300, mn = 1e300, sum = 0.0, umax = 0.0;
    for (int i = 0; i < nn; ++i) {
      const BallbarErrorEntry& e = r.entries[d * nn + i];
      mx = std::max(mx, e.value), mn = std::min(mn, e.value), sum += e.value, umax = std::max(umax, e.u);
    }
    std::printf("  %-5s %-4s | %9.3f %9.3f %9.3f | %9.3f %9.3f %9.3f | %7.3f\n", r.entries[d * nn].symbol.c_str(),
                r.entries[d * nn].unit.c_str(), mx, mn, sum / nn, kSeed003Table3Max[d], kSeed003Table3Min[d],
                kSeed003Table3Avg[d], umax);
  }
}

TEST(BallbarIdentification, Seed003Table1AgainstTable3) {
  const MachineModel m = BbiTMachine();
  const auto gs = BbiTCInstallations(m);
  const auto readings = BbiTReadSeed003(gs);
  ASSERT_EQ(readings.size(), 7u * 19u);
  auto fitted = IdentifyBallbar(m, gs, readings);
  ASSERT_TRUE(fitted.ok()) << fitted.status().ToString();
  BbiTPrintTable("seed 003 Table 1, offsets and centring fitted (maps relative to the convention)", *fitted);
  for (const BallbarSetupTerm& s : fitted->setup_terms)
    std::printf("  %-32s %9.3f +- %.3f um\n", s.name.c_str(), s.value_um, s.u_um);
  BallbarIdentificationOptions raw;
  raw.fit_length_offsets = false;
  raw.fit_centring = false;
  auto plain = IdentifyBallbar(m, gs, readings, raw);
  ASSERT_TRUE(plain.ok()) << plain.status().ToString();
  BbiTPrintTable("seed 003 Table 1, no set-up terms (every node value from the data alone)", *plain);
  std::printf("  not identifiable without set-up terms: %zu entries\n", plain->not_identifiable.size());
  EXPECT_EQ(fitted->entries.size(), 108u);
}

}  // namespace
}  // namespace tpcal::kinematics
