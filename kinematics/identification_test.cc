// Identify (kinematics/identification.h) on its own, without test pieces: a box of 200 x 150 mm
// milled on a nominal 3-axis `xyz` machine (four side faces cut by the side of a 10 mm end mill,
// the top face by its end), measured as the exact actual surface points of SimulateSurfacePoint
// under known errors. Shows the noise-free round trip, noisy data within their uncertainty,
// a non-identifiable pair reported with its estimable combination, and failures as statuses.
// Truths: the squareness errors of ISO 230-1 (E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z) and an X offset
// (E_XX.c0) of a few um / urad; random draws from std::mt19937_64 with fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/frames.h"
#include "core/status.h"
#include "core/units.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/identification.h"
#include "kinematics/inverse_kinematics.h"
#include "kinematics/machine_model.h"
#include "kinematics/prior_update.h"
#include "kinematics/simulate.h"

namespace tpcal::kinematics {
namespace {

// The box (part frame = machine frame on an xyz machine): faces x = +-100, y = +-75, top z = 0.
constexpr double kIdentifyTestHalfX_mm = 100.0;
constexpr double kIdentifyTestHalfY_mm = 75.0;
constexpr double kIdentifyTestToolRadius_mm = 5.0;
// Heights of the side-face points: four levels (the lever arms of E_B(0X)Z and E_A(0Y)Z).
const std::vector<double> kIdentifyTestHeights_mm = {-80.0, -60.0, -40.0, -20.0};
// The one level of the design that cannot separate an X offset from E_B(0X)Z.
constexpr double kIdentifyTestSingleHeight_mm = -40.0;
// Squareness truth (urad), in IsoLocationSet order for xyz: E_C(0X)Y, E_B(0X)Z, E_A(0Y)Z.
const std::vector<double> kIdentifyTestSquareness_urad = {14.0, -9.0, 6.0};

MachineModel IdentifyTestMachine() {
  Result<MachineModel> m = MakeMachine(MachineType::kXyz);
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  return *m;
}

double IdentifyTestLinspace(double a, double b, int n, int k) { return a + (b - a) * k / (n - 1); }

// One cut point: the tool point `contact` (tool frame) at part point p with outward normal n,
// swept by the axis increments du, dv (the tool frame never turns on an xyz machine).
Observation IdentifyTestCut(const MachineModel& m, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                            const Eigen::Vector3d& contact, const AxisDelta& du, const AxisDelta& dv, int group) {
  Observation o;
  o.group = group;
  o.cut.contact_in_tool_mm = contact;
  o.cut.nominal_point_mm = p;
  o.cut.nominal_normal = n;
  o.cut.du.axes = du;
  o.cut.dv.axes = dv;
  Result<AxisState> axes = NominalAxesForToolPoint(m, p, AxisState{}, contact);
  EXPECT_TRUE(axes.ok()) << axes.status().ToString();
  if (axes.ok()) o.cut.axes = *axes;
  EXPECT_LT(CutPointMismatch(m, o.cut), 1e-9);
  o.measured_mm = p;  // nominal until measured (IdentifyTestMeasure)
  return o;
}

// The box's cut points, one group per face: +X, -X, +Y, -Y (9 points along the face at each of
// `heights`, cut by the side of the end mill: path along the face, Z feed across), then the top
// (5 x 5 points, cut by the end: X and Y sweeps). Order fixed: the noise draws follow it.
std::vector<Observation> IdentifyTestBoxCuts(const MachineModel& m, const std::vector<double>& heights) {
  std::vector<Observation> out;
  const double r = kIdentifyTestToolRadius_mm;
  const AxisDelta along_x{1, 0, 0, 0, 0, 0}, along_y{0, 1, 0, 0, 0, 0}, along_z{0, 0, 1, 0, 0, 0};
  int group = 0;
  for (double sx : {1.0, -1.0}) {
    const Eigen::Vector3d n(sx, 0, 0);
    for (int k = 0; k < 9; ++k) {
      const double y = IdentifyTestLinspace(-60.0, 60.0, 9, k);
      for (double z : heights)
        out.push_back(IdentifyTestCut(m, Eigen::Vector3d(sx * kIdentifyTestHalfX_mm, y, z), n, -r * n, along_y,
                                      along_z, group));
    }
    ++group;
  }
  for (double sy : {1.0, -1.0}) {
    const Eigen::Vector3d n(0, sy, 0);
    for (int k = 0; k < 9; ++k) {
      const double x = IdentifyTestLinspace(-80.0, 80.0, 9, k);
      for (double z : heights)
        out.push_back(IdentifyTestCut(m, Eigen::Vector3d(x, sy * kIdentifyTestHalfY_mm, z), n, -r * n, along_x,
                                      along_z, group));
    }
    ++group;
  }
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      const Eigen::Vector3d p(IdentifyTestLinspace(-80.0, 80.0, 5, i), IdentifyTestLinspace(-60.0, 60.0, 5, j), 0.0);
      out.push_back(IdentifyTestCut(m, p, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), along_x, along_y, group));
    }
  }
  return out;
}

// Standard normal deviate by Box-Muller from two 53-bit uniforms taken straight from the
// generator's bits (std::normal_distribution differs between standard libraries).
double IdentifyTestGaussian(std::mt19937_64& rng) {
  constexpr double kIdentifyTestTwoToMinus53 = 1.0 / 9007199254740992.0;
  const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * kIdentifyTestTwoToMinus53;  // (0, 1]
  const double u2 = static_cast<double>(rng() >> 11) * kIdentifyTestTwoToMinus53;          // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// Measures the observations on the part cut under `truth`: the exact actual surface point
// (SimulateSurfacePoint), plus noise_um x N(0, 1) along the nominal normal (one draw per point,
// in order; rng unused when noise_um = 0), then placed on the CMM: measured = placement * point.
void IdentifyTestMeasure(const MachineModel& m, const ErrorState& truth, double noise_um, std::mt19937_64* rng,
                         const Rigid3& placement, std::vector<Observation>* observations) {
  Workspace ws;
  for (Observation& o : *observations) {
    Result<SurfacePoint> sp = SimulateSurfacePoint(m, truth, o.cut, &ws);
    ASSERT_TRUE(sp.ok()) << sp.status().ToString();
    Eigen::Vector3d point = sp->point_mm;
    if (noise_um > 0.0) point += UmToMm(noise_um * IdentifyTestGaussian(*rng)) * o.cut.nominal_normal;
    o.measured_mm = placement * point;
  }
}

// Zero base errors with `names` activated (ActivateParameters), and the truth: the same state
// with the active coefficients at `display_values` (um, urad: CoefficientInfo::unit), in order.
void IdentifyTestErrors(const MachineModel& m, const std::vector<std::string>& names,
                        const std::vector<double>& display_values, ErrorState* base, ErrorState* truth,
                        ActiveSet* active) {
  ASSERT_EQ(names.size(), display_values.size());
  Result<ActiveSet> a = ActivateParameters(m, base, names);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  *active = *a;
  *truth = *base;
  for (int k = 0; k < active->size(); ++k) {
    const int c = active->coefficients[static_cast<std::size_t>(k)];
    const double value = display_values[static_cast<std::size_t>(k)];
    truth->set_coefficient(c, value / truth->coefficient_info(c).display_per_internal);
  }
}

const Uncertainty* IdentifyTestFindUncertainty(const ParameterEstimate& p, UncertaintyMethod method) {
  for (const Uncertainty& u : p.uncertainties)
    if (u.method == method) return &u;
  return nullptr;
}

// Noise-free round trip. Truth: 14, -9, 6 urad of squareness; the measured points are also
// misplaced on the CMM (20-40 urad, 5-12 um), which the re-alignment nuisance must undo.
// Tolerance 1e-3 urad: Identify solves the exact non-linear model, so only the solver limits it
// (Ceres stops at relative steps < 1e-9, SimulateSurfacePoint at 1e-10 mm = 1e-7 um, i.e.
// ~1e-6 urad at these 20-100 mm lever arms); even a single linearised step would be off by
// second-order terms only, (15e-6)^2 x 100 mm = 2e-5 um = 2e-4 urad at 100 mm. Residual RMS: the
// same rounding, far below 1e-4 um.
TEST(Identification, NoiseFreeSquarenessRoundTrip) {
  const MachineModel m = IdentifyTestMachine();
  const std::vector<std::string> names = IsoLocationSet(m);
  ASSERT_EQ(names.size(), 3u);  // xyz: squareness only
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, kIdentifyTestSquareness_urad, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  const Rigid3 placement =
      RigidFromTwist(Eigen::Vector3d(30e-6, -20e-6, 40e-6), Eigen::Vector3d(0.012, -0.008, 0.005));
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, placement, &obs));

  const Result<IdentificationResult> id = Identify(m, base, active, obs);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  EXPECT_EQ(id->num_observations, obs.size());
  EXPECT_EQ(id->num_groups, 5);
  EXPECT_EQ(id->identifiability.num_parameters, 3);
  EXPECT_EQ(id->identifiability.rank, 3);
  EXPECT_TRUE(id->identifiability.not_identifiable.empty());
  EXPECT_TRUE(id->identifiability.estimable.empty());
  ASSERT_EQ(id->parameters.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    const ParameterEstimate& p = id->parameters[k];
    EXPECT_EQ(p.name, names[k]);
    EXPECT_EQ(p.unit, "urad");
    EXPECT_TRUE(p.identifiable) << p.name;
    EXPECT_NEAR(p.value, kIdentifyTestSquareness_urad[k], 1e-3) << p.name;
    const int c = active.coefficients[k];
    EXPECT_NEAR(id->fitted.coefficient(c) * id->fitted.coefficient_info(c).display_per_internal,
                kIdentifyTestSquareness_urad[k], 1e-3)
        << p.name;
  }
  EXPECT_GT(id->rms_before_um, 1.0);  // the placement alone moves the points by ~10 um
  EXPECT_LT(id->rms_after_um, 1e-4);
  EXPECT_LT(id->sigma_um, 1e-4);
  // The re-alignment undoes the placement: 1e-8 rad (1e-3 um at 100 mm) and 1e-6 mm.
  const Rigid3 left = id->alignment * placement;
  EXPECT_LT((left.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-8);
  EXPECT_LT(left.translation().norm(), 1e-6);
}

// Noisy data. Truth as above, N(0, 0.25 um) along the normal (seed 20240611, Box-Muller), 169
// points, 3 coefficients + 6 alignment terms. Each estimate within 4 u (analytic, k = 1) of the
// truth: 4 u has a two-sided probability of 6e-5 per coefficient. sigma_um within 25 % of 0.25:
// its relative standard deviation is 1 / sqrt(2 (n - 9)) = 0.056, so 25 % is 4.5 of them. The
// analytic u and the delete-one-point jackknife u estimate the same spread (homoscedastic
// noise, leverage <= 0.2 here): their ratio within 0.5-2.
TEST(Identification, NoisySquarenessWithinFourU) {
  const MachineModel m = IdentifyTestMachine();
  const std::vector<std::string> names = IsoLocationSet(m);
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, kIdentifyTestSquareness_urad, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  const double noise_um = 0.25;
  std::mt19937_64 rng(20240611);
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, noise_um, &rng, Rigid3::Identity(), &obs));

  const Result<IdentificationResult> id = Identify(m, base, active, obs);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  EXPECT_EQ(id->identifiability.rank, 3);
  EXPECT_NEAR(id->sigma_um, noise_um, 0.25 * noise_um);
  ASSERT_EQ(id->parameters.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    const ParameterEstimate& p = id->parameters[k];
    ASSERT_TRUE(p.identifiable) << p.name;
    const Uncertainty* analytic = IdentifyTestFindUncertainty(p, UncertaintyMethod::kAnalytic);
    const Uncertainty* jackknife = IdentifyTestFindUncertainty(p, UncertaintyMethod::kJackknifePoints);
    ASSERT_NE(analytic, nullptr) << p.name;
    ASSERT_NE(jackknife, nullptr) << p.name;
    ASSERT_TRUE(analytic->available && jackknife->available) << p.name;
    ASSERT_GT(analytic->u, 0.0) << p.name;
    ASSERT_GT(jackknife->u, 0.0) << p.name;
    EXPECT_LT(std::abs(p.value - kIdentifyTestSquareness_urad[k]), 4.0 * analytic->u)
        << p.name << " = " << p.value << " +- " << analytic->u;
    const double ratio = analytic->u / jackknife->u;
    EXPECT_GT(ratio, 0.5) << p.name;
    EXPECT_LT(ratio, 2.0) << p.name;
    EXPECT_EQ(p.u, jackknife->u) << p.name;  // the default primary method
  }
}

// Weighted least squares (Observation::noise_scale). Truth: an observation of scale 1 / sqrt(2)
// weighs in the normal equations exactly as the same observation twice at scale 1, so the box
// (0.25 um noise, misplaced as in the round trip) with its side faces at scale 1 / sqrt(2) gives
// the estimates of the box with the side faces listed twice (to the solver's 1e-6 urad: tolerance
// 1e-4 urad), the same weighted SSR, hence analytic u in the ratio sqrt((n2 - m) / (n1 - m)) of
// the degrees of freedom (1e-6 relative), and unweighted residuals (1e-9 um). Every scale 1 / 2
// instead: the ordinary estimates and u (scaling every row changes neither), sigma twice theirs
// (one hit's, from observations of half its noise).
TEST(Identification, WeightedRowsWeighAsRepeatedObservations) {
  const MachineModel m = IdentifyTestMachine();
  const std::vector<std::string> names = IsoLocationSet(m);
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, kIdentifyTestSquareness_urad, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  std::mt19937_64 rng(20261203);
  const Rigid3 placement =
      RigidFromTwist(Eigen::Vector3d(30e-6, -20e-6, 40e-6), Eigen::Vector3d(0.012, -0.008, 0.005));
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.25, &rng, placement, &obs));
  std::vector<Observation> weighted = obs, repeated = obs;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (obs[i].group < 4) {
      weighted[i].noise_scale = 1.0 / std::sqrt(2.0);
      repeated.push_back(obs[i]);
    }
  const auto a = Identify(m, base, active, weighted);
  const auto b = Identify(m, base, active, repeated);
  const auto ols = Identify(m, base, active, obs);
  std::vector<Observation> halves = obs;
  for (auto& o : halves) o.noise_scale = 0.5;
  const auto half = Identify(m, base, active, halves);
  ASSERT_TRUE(a.ok() && b.ok() && ols.ok() && half.ok());
  const double m_fit = 3 + 6;  // coefficients and the re-alignment
  const double dof_ratio = std::sqrt((static_cast<double>(repeated.size()) - m_fit) / (static_cast<double>(obs.size()) - m_fit));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto* ua = IdentifyTestFindUncertainty(a->parameters[k], UncertaintyMethod::kAnalytic);
    const auto* ub = IdentifyTestFindUncertainty(b->parameters[k], UncertaintyMethod::kAnalytic);
    const auto* uo = IdentifyTestFindUncertainty(ols->parameters[k], UncertaintyMethod::kAnalytic);
    const auto* uh = IdentifyTestFindUncertainty(half->parameters[k], UncertaintyMethod::kAnalytic);
    ASSERT_TRUE(ua && ub && uo && uh);
    EXPECT_NEAR(a->parameters[k].value, b->parameters[k].value, 1e-4) << names[k];
    EXPECT_NEAR(ua->u / ub->u, dof_ratio, 1e-6) << names[k];
    EXPECT_NEAR(half->parameters[k].value, ols->parameters[k].value, 1e-4) << names[k];
    EXPECT_NEAR(uh->u / uo->u, 1.0, 1e-6) << names[k];
  }
  for (std::size_t i = 0; i < obs.size(); ++i) EXPECT_NEAR(a->residuals_um[i], b->residuals_um[i], 1e-9) << i;
  EXPECT_NEAR(half->sigma_um, 2.0 * ols->sigma_um, 1e-9);
  EXPECT_NEAR(half->rms_after_um, ols->rms_after_um, 1e-9);
}

// Identifiability is reported, never hidden. All side-face points at one height z0 = -40 mm and
// no re-alignment fitted (with it, the translation would absorb any X offset by itself): an X
// offset of the X axis (E_XX.c0, um) and the squareness E_B(0X)Z (urad, an X shift of z0 x 1e-3 um
// per urad at that height) then have proportional columns. Truth: 14, -9, 6 urad, 3 um.
// Expected: rank 3 of 4; E_B(0X)Z and E_XX.c0 not identifiable, without value or u; one estimable
// combination, E_XX.c0 + z0 1e-3 E_B(0X)Z = 3 + 0.36 um, to 1e-3 um (the exact model, as in the
// round trip); its coefficient from the geometry to 1e-9 (the columns are proportional to rounding
// at zero errors); E_C(0X)Y and E_A(0Y)Z still identified to 1e-3 urad.
TEST(Identification, OffsetAndSquarenessAtOneHeightGiveACombination) {
  const MachineModel m = IdentifyTestMachine();
  const std::vector<std::string> names = {"E_C(0X)Y", "E_B(0X)Z", "E_A(0Y)Z", "E_XX.c0"};
  const std::vector<double> values = {14.0, -9.0, 6.0, 3.0};
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, values, &base, &truth, &active));
  std::map<std::string, double> truth_of;
  for (std::size_t k = 0; k < names.size(); ++k) truth_of[names[k]] = values[k];
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, {kIdentifyTestSingleHeight_mm});
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));

  IdentifyOptions options;
  options.fit_alignment = false;
  const Result<IdentificationResult> id = Identify(m, base, active, obs, options);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  const Identifiability& idf = id->identifiability;
  EXPECT_EQ(idf.num_parameters, 4);
  EXPECT_EQ(idf.rank, 3);
  ASSERT_EQ(idf.singular_values.size(), 4u);
  EXPECT_LT(idf.singular_values[3], 1e-9 * idf.singular_values[0]);  // rounding, not a weak direction
  EXPECT_EQ(idf.not_identifiable, (std::vector<std::string>{"E_B(0X)Z", "E_XX.c0"}));
  ASSERT_EQ(id->parameters.size(), names.size());
  for (const ParameterEstimate& p : id->parameters) {
    if (p.name == "E_B(0X)Z" || p.name == "E_XX.c0") {
      EXPECT_FALSE(p.identifiable) << p.name;
      EXPECT_EQ(p.value, 0.0) << p.name;
      EXPECT_EQ(p.u, 0.0) << p.name;
      EXPECT_TRUE(p.uncertainties.empty()) << p.name;
    } else {
      EXPECT_TRUE(p.identifiable) << p.name;
      EXPECT_NEAR(p.value, truth_of.at(p.name), 1e-3) << p.name;
    }
  }
  // The estimable combination: coefficients normalised so the largest is +1 (E_XX.c0).
  const double lever_um_per_urad = kIdentifyTestSingleHeight_mm * 1e-3;  // -0.04
  ASSERT_EQ(idf.estimable.size(), 1u);
  const Combination& comb = idf.estimable[0];
  ASSERT_EQ(comb.names, idf.not_identifiable);
  ASSERT_EQ(comb.coefficients.size(), 2u);
  EXPECT_NEAR(comb.coefficients[0], lever_um_per_urad, 1e-9);  // E_B(0X)Z
  EXPECT_NEAR(comb.coefficients[1], 1.0, 1e-9);                // E_XX.c0
  EXPECT_EQ(comb.text, "-0.04 E_B(0X)Z + E_XX.c0");
  double comb_truth = 0.0;
  for (std::size_t k = 0; k < comb.names.size(); ++k) comb_truth += comb.coefficients[k] * truth_of.at(comb.names[k]);
  EXPECT_NEAR(comb_truth, 3.0 + lever_um_per_urad * -9.0, 1e-8);  // 3.36 um
  EXPECT_NEAR(comb.value, comb_truth, 1e-3);
  // What the data cannot see: +1 urad of squareness with -z0 1e-3 = +0.04 um of offset.
  ASSERT_EQ(idf.null_directions.size(), 1u);
  ASSERT_EQ(idf.null_directions[0].coefficients.size(), 2u);
  EXPECT_NEAR(idf.null_directions[0].coefficients[0], 1.0, 1e-9);
  EXPECT_NEAR(idf.null_directions[0].coefficients[1], -lever_um_per_urad, 1e-9);
  // The identified part explains the data completely.
  EXPECT_LT(id->rms_after_um, 1e-4);
}

// An X offset of the X axis (E_XX.c0, 3 um) moves every point of the box by the same vector, which
// the re-alignment's X translation absorbs whole: once the nuisance is projected out, its column is
// rounding (about 1e-13 of its norm). Alone it must be reported as not identifiable
// (kNotIdentifiable), not as a rank-1 fit of that rounding; beside the squareness errors it is the
// one coefficient without a value while the three squareness errors keep theirs (to 1e-3 urad, as
// in the round trip).
TEST(Identification, OffsetAbsorbedByTheAlignmentIsNotIdentifiable) {
  const MachineModel m = IdentifyTestMachine();
  {
    ErrorState base(m), truth(m);
    ActiveSet active;
    ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, {"E_XX.c0"}, {3.0}, &base, &truth, &active));
    std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
    ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));
    const Result<IdentificationResult> alone = Identify(m, base, active, obs);
    ASSERT_FALSE(alone.ok());
    EXPECT_EQ(alone.status().code(), StatusCode::kNotIdentifiable) << alone.status().ToString();
  }
  const std::vector<std::string> names = {"E_C(0X)Y", "E_B(0X)Z", "E_A(0Y)Z", "E_XX.c0"};
  const std::vector<double> values = {14.0, -9.0, 6.0, 3.0};
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, values, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));
  const Result<IdentificationResult> id = Identify(m, base, active, obs);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  EXPECT_EQ(id->identifiability.rank, 3);
  ASSERT_EQ(id->parameters.size(), 4u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(id->parameters[k].identifiable) << names[k];
    EXPECT_NEAR(id->parameters[k].value, values[k], 1e-3) << names[k];
  }
  EXPECT_FALSE(id->parameters[3].identifiable);
}

// n must exceed q + 6 (coefficients and alignment terms); no observations at all is the extreme
// case. Identify returns kTooFewPoints (identification.cc, before any linearisation).
TEST(Identification, TooFewObservationsAreAnError) {
  const MachineModel m = IdentifyTestMachine();
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(
      IdentifyTestErrors(m, IsoLocationSet(m), kIdentifyTestSquareness_urad, &base, &truth, &active));
  const std::vector<Observation> none;
  const Result<IdentificationResult> empty = Identify(m, base, active, none);
  ASSERT_FALSE(empty.ok());
  EXPECT_EQ(empty.status().code(), StatusCode::kTooFewPoints) << empty.status().ToString();

  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));
  const std::vector<Observation> nine(obs.begin(), obs.begin() + 9);  // q + 6
  const Result<IdentificationResult> few = Identify(m, base, active, nine);
  ASSERT_FALSE(few.ok());
  EXPECT_EQ(few.status().code(), StatusCode::kTooFewPoints) << few.status().ToString();
  IdentifyOptions no_alignment;  // then n must exceed q only
  no_alignment.fit_alignment = false;
  const std::vector<Observation> three(obs.begin(), obs.begin() + 3);
  const Result<IdentificationResult> few2 = Identify(m, base, active, three, no_alignment);
  ASSERT_FALSE(few2.ok());
  EXPECT_EQ(few2.status().code(), StatusCode::kTooFewPoints) << few2.status().ToString();
}

// IdentifyOptions::initial_design of other observations (one row fewer) or of other
// coefficients (two columns for three) is kInvalidArgument, not a silent misfit or an
// out-of-range read; the matching design is accepted.
TEST(Identification, MismatchedInitialDesignIsAnError) {
  const MachineModel m = IdentifyTestMachine();
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(
      IdentifyTestErrors(m, IsoLocationSet(m), kIdentifyTestSquareness_urad, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));

  const std::vector<Observation> fewer(obs.begin(), obs.end() - 1);
  Result<LinearDesign> fewer_rows = LineariseObservations(m, base, active, fewer);
  ASSERT_TRUE(fewer_rows.ok()) << fewer_rows.status().ToString();
  IdentifyOptions wrong_rows;
  wrong_rows.initial_design = std::make_shared<LinearDesign>(*fewer_rows);
  const Result<IdentificationResult> bad_rows = Identify(m, base, active, obs, wrong_rows);
  ASSERT_FALSE(bad_rows.ok());
  EXPECT_EQ(bad_rows.status().code(), StatusCode::kInvalidArgument) << bad_rows.status().ToString();
  EXPECT_NE(bad_rows.status().message().find("initial design"), std::string::npos) << bad_rows.status().ToString();

  Result<ActiveSet> two = SelectCoefficients(base, {"E_C(0X)Y", "E_B(0X)Z"});
  ASSERT_TRUE(two.ok()) << two.status().ToString();
  Result<LinearDesign> fewer_cols = LineariseObservations(m, base, *two, obs);
  ASSERT_TRUE(fewer_cols.ok()) << fewer_cols.status().ToString();
  IdentifyOptions wrong_cols;
  wrong_cols.initial_design = std::make_shared<LinearDesign>(*fewer_cols);
  const Result<IdentificationResult> bad_cols = Identify(m, base, active, obs, wrong_cols);
  ASSERT_FALSE(bad_cols.ok());
  EXPECT_EQ(bad_cols.status().code(), StatusCode::kInvalidArgument) << bad_cols.status().ToString();

  Result<LinearDesign> matching = LineariseObservations(m, base, active, obs);
  ASSERT_TRUE(matching.ok()) << matching.status().ToString();
  IdentifyOptions given;
  given.initial_design = std::make_shared<LinearDesign>(*matching);
  const Result<IdentificationResult> good = Identify(m, base, active, obs, given);
  ASSERT_TRUE(good.ok()) << good.status().ToString();
}

// The other documented errors, each a status with its code: an empty active set and invalid
// options (kInvalidArgument), a cut point whose simulation fails (its status, naming the
// observation), and coefficients no point depends on (kNotIdentifiable: an operation offset for
// an operation none of the points was cut in has an exactly zero column).
TEST(Identification, BadInputsAreStatuses) {
  const MachineModel m = IdentifyTestMachine();
  ErrorState base(m), truth(m);
  ActiveSet active;
  ASSERT_NO_FATAL_FAILURE(
      IdentifyTestErrors(m, IsoLocationSet(m), kIdentifyTestSquareness_urad, &base, &truth, &active));
  std::vector<Observation> obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
  ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));

  const Result<IdentificationResult> no_active = Identify(m, base, ActiveSet{}, obs);
  ASSERT_FALSE(no_active.ok());
  EXPECT_EQ(no_active.status().code(), StatusCode::kInvalidArgument) << no_active.status().ToString();

  IdentifyOptions bad_tolerance;
  bad_tolerance.rank_tolerance = 0.0;
  const Result<IdentificationResult> bad_options = Identify(m, base, active, obs, bad_tolerance);
  ASSERT_FALSE(bad_options.ok());
  EXPECT_EQ(bad_options.status().code(), StatusCode::kInvalidArgument) << bad_options.status().ToString();

  for (const double scale : {0.0, -1.0, std::nan("")}) {
    std::vector<Observation> weighed = obs;
    weighed[7].noise_scale = scale;
    const Result<IdentificationResult> bad_scale = Identify(m, base, active, weighed);
    ASSERT_FALSE(bad_scale.ok()) << scale;
    EXPECT_EQ(bad_scale.status().code(), StatusCode::kInvalidArgument) << bad_scale.status().ToString();
    EXPECT_NE(bad_scale.status().message().find("observation 7"), std::string::npos) << bad_scale.status().ToString();
  }

  std::vector<Observation> bent = obs;
  bent[5].cut.nominal_normal *= 1.01;  // not a unit vector: SimulateSurfacePoint refuses it
  const Result<IdentificationResult> bad_cut = Identify(m, base, active, bent);
  ASSERT_FALSE(bad_cut.ok());
  EXPECT_EQ(bad_cut.status().code(), StatusCode::kInvalidArgument) << bad_cut.status().ToString();
  EXPECT_NE(bad_cut.status().message().find("observation 5"), std::string::npos) << bad_cut.status().ToString();

  ErrorState idle(m);
  ErrorTerm offset;
  offset.kind = TermKind::kOperationOffset;
  offset.label = "E_XX";
  offset.effects = {{Axis::kX, Component::kTx, 1.0}};
  offset.op = 3;  // every point has op = 0
  offset.coefficients = {0.0};
  ASSERT_TRUE(idle.AddTerm(m, offset).ok());
  Result<ActiveSet> unseen = SelectCoefficients(idle, {"E_XX.op3"});
  ASSERT_TRUE(unseen.ok()) << unseen.status().ToString();
  const Result<IdentificationResult> blind = Identify(m, idle, *unseen, obs);
  ASSERT_FALSE(blind.ok());
  EXPECT_EQ(blind.status().code(), StatusCode::kNotIdentifiable) << blind.status().ToString();
}

// The noise-free box of the PriorUpdate tests: the squareness set as truth, measured at sigma 1
// um, and a prior shifted from the truth by `shift_urad` per coefficient (display units).
class PriorUpdateBox : public ::testing::Test {
 protected:
  void SetUp() override {
    names = IsoLocationSet(m);
    ErrorState base(m);
    ASSERT_NO_FATAL_FAILURE(IdentifyTestErrors(m, names, kIdentifyTestSquareness_urad, &base, &truth, &active));
    ASSERT_EQ(names.size(), 3u);
    obs = IdentifyTestBoxCuts(m, kIdentifyTestHeights_mm);
    ASSERT_NO_FATAL_FAILURE(IdentifyTestMeasure(m, truth, 0.0, nullptr, Rigid3::Identity(), &obs));
  }
  ErrorState Shifted(const std::array<double, 3>& shift_urad) const {
    ErrorState prior = truth;
    for (std::size_t k = 0; k < 3; ++k) {
      const int c = active.coefficients[k];
      prior.set_coefficient(c, truth.coefficient(c) + shift_urad[k] / truth.coefficient_info(c).display_per_internal);
    }
    return prior;
  }
  double Value(const ErrorState& e, std::size_t k) const {
    const int c = active.coefficients[k];
    return e.coefficient(c) * e.coefficient_info(c).display_per_internal;
  }
  const MachineModel m = IdentifyTestMachine();
  std::vector<std::string> names;
  ErrorState truth{m};
  ActiveSet active;
  std::vector<Observation> obs;
};

// UpdateWithinPrior (kinematics/prior_update.h) on the noise-free box. Truth: the squareness set
// above; the prior: the truth + 20 urad on each. A prior of u = 1e-3 urad is kept (the piece's
// information, ~1 / (0.1 urad)^2 at sigma 1 um, moves it by about (1e-3 / 0.1)^2 x 20 = 2e-3
// urad); one of u = 1e6 urad gives the piece's own fit, the truth, to the linearisation's
// second order (20e-6^2 x 100 mm = 4e-5 um: below 1e-3 urad); a coefficient without prior
// (u = 0) likewise. A prior u equal to the piece's marginal u (the others free) halves the 20 urad.
TEST_F(PriorUpdateBox, TightPriorIsKeptLoosePriorGivesThePieceAndEqualWeightsMeetHalfway) {
  const ErrorState prior = Shifted({20.0, 20.0, 20.0});
  auto tight = UpdateWithinPrior(m, prior, active, std::vector<double>{1e-3, 1e-3, 1e-3}, obs, 1.0);
  ASSERT_TRUE(tight.ok()) << tight.status().ToString();
  auto loose = UpdateWithinPrior(m, prior, active, std::vector<double>{1e6, 0.0, 1e6}, obs, 1.0);
  ASSERT_TRUE(loose.ok()) << loose.status().ToString();
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_NEAR(Value(tight->posterior, k), kIdentifyTestSquareness_urad[k] + 20.0, 0.01) << names[k];
    EXPECT_NEAR(Value(loose->posterior, k), kIdentifyTestSquareness_urad[k], 1e-3) << names[k];
    EXPECT_LT(tight->posterior_u[k], 1e-3) << names[k];
  }
  // Equal weights: the piece's u of each coefficient (sigma 1 um) as the prior's u.
  std::vector<double> piece_u(loose->posterior_u.begin(), loose->posterior_u.end());
  ASSERT_GT(piece_u[1], 0.0);
  auto half = UpdateWithinPrior(m, prior, active, std::vector<double>{1e6, piece_u[1], 1e6}, obs, 1.0);
  ASSERT_TRUE(half.ok()) << half.status().ToString();
  EXPECT_NEAR(Value(half->posterior, 1), kIdentifyTestSquareness_urad[1] + 10.0, 0.01);
  EXPECT_FALSE(UpdateWithinPrior(m, prior, active, std::vector<double>{1.0}, obs, 1.0).ok());
  EXPECT_FALSE(UpdateWithinPrior(m, prior, active, piece_u, obs, 0.0).ok());
}

// A prior far tighter on one coefficient than the piece on any: u = 1e-5 urad on the first
// (information 1e10 / urad^2, 1e8 times the piece's ~100) at its true value, none on the other two,
// which start 20 urad off. What the piece sees is judged against the piece's own information, not
// the prior's: the other two come from the piece (the truth to 1e-3 urad, as above) with a u > 0,
// the first stays at the truth.
TEST_F(PriorUpdateBox, APriorTightOnOneCoefficientDoesNotHideWhatThePieceSees) {
  const ErrorState prior = Shifted({0.0, 20.0, -20.0});
  auto up = UpdateWithinPrior(m, prior, active, std::vector<double>{1e-5, 0.0, 0.0}, obs, 1.0);
  ASSERT_TRUE(up.ok()) << up.status().ToString();
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(Value(up->posterior, k), kIdentifyTestSquareness_urad[k], 1e-3) << names[k];
  EXPECT_GT(up->posterior_u[1], 0.0);
  EXPECT_GT(up->posterior_u[2], 0.0);
}

// UpdateWithinPriorCovariance on the same box. Truth: the squareness set; the prior: the truth +20,
// +20 and -20 urad, whose covariance knows only the sum of the first and third (variance 0.01
// urad^2 along (1, 0, 1) / sqrt 2, nothing else: information 100 / urad^2, the piece's order).
// The sum, right in the prior, is kept; their difference and the second come from the piece: the
// truth, to the linearisation's second order (1e-3 urad, as above). With the same covariance's
// diagonal as u (correlations dropped) the prior pulls the first toward its wrong value (measured
// more than 5 urad off). A covariance of the wrong size, or not symmetric, is an error.
TEST_F(PriorUpdateBox, ACovarianceKnowsOnlyTheCombinationsItSpans) {
  const ErrorState prior = Shifted({20.0, 20.0, -20.0});
  const Eigen::Vector3d sum = Eigen::Vector3d(1.0, 0.0, 1.0) / std::sqrt(2.0);
  const Eigen::MatrixXd cov = 0.01 * sum * sum.transpose();
  auto up = UpdateWithinPriorCovariance(m, prior, active, cov, obs, 1.0);
  ASSERT_TRUE(up.ok()) << up.status().ToString();
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(Value(up->posterior, k), kIdentifyTestSquareness_urad[k], 1e-3) << names[k];
  const std::vector<double> diag_u = {std::sqrt(cov(0, 0)), 0.0, std::sqrt(cov(2, 2))};
  auto per_parameter = UpdateWithinPrior(m, prior, active, diag_u, obs, 1.0);
  ASSERT_TRUE(per_parameter.ok()) << per_parameter.status().ToString();
  EXPECT_GT(std::abs(Value(per_parameter->posterior, 0) - kIdentifyTestSquareness_urad[0]), 5.0);
  EXPECT_FALSE(UpdateWithinPriorCovariance(m, prior, active, Eigen::MatrixXd::Identity(2, 2), obs, 1.0).ok());
  Eigen::MatrixXd skew = Eigen::MatrixXd::Identity(3, 3);
  skew(0, 1) = 0.5;
  EXPECT_FALSE(UpdateWithinPriorCovariance(m, prior, active, skew, obs, 1.0).ok());
}

}  // namespace
}  // namespace tpcal::kinematics
