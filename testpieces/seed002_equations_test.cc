// Seed 002 eqs. 10-27 through the whole chain: one Table 2 parameter at a time, the piece is
// machined virtually (kinematics::SimulateSurfacePoint at every plan point's cut state), measured
// without noise, and evaluated by the gdt turning plan. The expected values are the first-order
// formulas derived from our kinematics (testpieces/SEED002_EQUATIONS.md, which also lists the
// paper's printed forms and why they differ). Tolerance: 1 % of the effect, and 2 nm absolute for
// effects that vanish to first order (second-order terms are below 1e-4 um here).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/units.h"
#include "gdt/inspection.h"
#include "kinematics/errors_yaml.h"
#include "testpieces/simulate_piece.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {
namespace {

constexpr double kRelTol = 0.01;     // 1 % of the effect (the brief's first-order criterion)
constexpr double kAbsTol_um = 0.002; // zero-to-first-order effects: second order is < 1e-4 um

kinematics::MachineModel EquationsAcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

const TestPiece& EquationsPiece() {
  static const TestPiece piece = [] {
    auto p = MakeTestPiece(PieceConfig{}, EquationsAcTable());
    EXPECT_TRUE(p.ok()) << p.status().ToString();
    return *p;
  }();
  return piece;
}

// Heights of the default piece (mm from the A axis), read from the parameters.
struct Heights {
  double z_h, z_sr_cut, z1, z2, z3, z4, z5, z6, rho_b3, rho_b6;
};
Heights H() {
  const auto& p = std::get<TurningPieceParams>(EquationsPiece().config.params);
  Heights h;
  h.z_h = p.hole_probe_z_mm();
  h.z_sr_cut = p.groove_bottom_z_mm + p.groove_wall_lift_mm;  // Z command of the S_R wall pass
  h.z1 = p.steps[0].probe_z_mm;
  h.z2 = p.steps[1].probe_z_mm;
  h.z3 = p.steps[2].probe_z_mm;
  h.z4 = p.steps[3].probe_z_mm;
  h.z5 = p.steps[4].probe_z_mm;
  h.z6 = p.steps[5].probe_z_mm;
  h.rho_b3 = p.steps[2].radius_mm + p.bottom_probe_fraction * (p.BottomOuterRadius(2) - p.steps[2].radius_mm);
  h.rho_b6 = p.steps[5].radius_mm + p.bottom_probe_fraction * (p.BottomOuterRadius(5) - p.steps[5].radius_mm);
  return h;
}

gdt::InspectionResult EvaluateEquations(const kinematics::ErrorState& errors, bool random_placement = false) {
  PieceSimOptions o;
  o.random_placement = random_placement;
  o.seed = 7;
  auto sim = SimulatePiece(EquationsPiece(), EquationsAcTable(), errors, o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  auto result = gdt::EvaluatePlan(EquationsPiece().inspection, sim->points);
  EXPECT_TRUE(result.ok()) << result.status().ToString();
  return *result;
}

// Characteristic values checked for every parameter: expected 0 unless the case says otherwise.
const std::vector<std::pair<std::string, std::string>> kChecked = {
    {"t1_concentricity_Ch_SR", "dx_um"}, {"t1_concentricity_Ch_SR", "dy_um"},
    {"t2_parallelism_B1_BR", "da_urad"}, {"t2_parallelism_B1_BR", "db_urad"},
    {"t3_distance_B3_BR", "error_um"},   {"t4_size_S3", "radius_error_um"},
    {"t5_concentricity_S4_SR", "dx_um"}, {"t5_concentricity_S4_SR", "dy_um"},
    {"t6_concentricity_S4_S1", "dx_um"}, {"t6_concentricity_S4_S1", "dy_um"},
    {"t7_concentricity_S6_S3", "dx_um"}, {"t7_concentricity_S6_S3", "dy_um"},
    {"size_S1", "radius_error_um"},      {"size_S2", "radius_error_um"},
    {"size_S4", "radius_error_um"},      {"size_S5", "radius_error_um"},
    {"size_S6", "radius_error_um"},      {"concentricity_S3_SR", "dx_um"},
    {"concentricity_S3_SR", "dy_um"},    {"parallelism_B3_BR", "da_urad"},
    {"parallelism_B3_BR", "db_urad"},    {"distance_B6_BR", "error_um"},
    {"ta_circularity_S1", "circularity_um"}, {"tb_circularity_S3", "circularity_um"},
};

struct Case {
  std::string parameter;
  double value;  // um or urad
  std::map<std::string, double> expected;  // "characteristic/value" -> um or urad
};

std::vector<Case> Cases() {
  const Heights h = H();
  const double k = 1e-3;  // urad * mm -> um
  std::vector<Case> cases;
  {
    const double d = 20.0;
    cases.push_back({"dx_CR(0)", d,
                     {{"t1_concentricity_Ch_SR/dx_um", d}, {"t5_concentricity_S4_SR/dx_um", d},
                      // the C line's X position holds at A = -90 too (A turns about X)
                      {"concentricity_S3_SR/dx_um", d},
                      {"size_S1/radius_error_um", -d}, {"size_S4/radius_error_um", -d}}});
  }
  {
    const double d = -15.0;
    cases.push_back({"dy_CR(0)", d,
                     {{"t1_concentricity_Ch_SR/dy_um", d}, {"t5_concentricity_S4_SR/dy_um", d},
                      {"size_S2/radius_error_um", -d}, {"size_S5/radius_error_um", -d}}});
  }
  {
    const double a = 30.0;
    cases.push_back({"alpha_CR(0)", a,
                     {{"t1_concentricity_Ch_SR/dy_um", -a * h.z_h * k},
                      {"t5_concentricity_S4_SR/dy_um", -a * h.z4 * k},
                      {"t6_concentricity_S4_S1/dy_um", a * (h.z1 - h.z4) * k},
                      {"t2_parallelism_B1_BR/da_urad", a},
                      {"size_S2/radius_error_um", a * h.z2 * k},
                      {"size_S5/radius_error_um", a * h.z5 * k}}});
  }
  {
    const double b = -25.0;
    cases.push_back({"beta_CR(0)", b,
                     {{"t1_concentricity_Ch_SR/dx_um", b * h.z_h * k},
                      {"t5_concentricity_S4_SR/dx_um", b * h.z4 * k},
                      {"t6_concentricity_S4_S1/dx_um", b * (h.z4 - h.z1) * k},
                      {"t2_parallelism_B1_BR/db_urad", b},
                      {"size_S1/radius_error_um", -b * h.z1 * k},
                      {"size_S4/radius_error_um", -b * h.z4 * k}}});
  }
  {
    const double d = 40.0;
    cases.push_back({"dy_AR(-90)", d,
                     {{"t3_distance_B3_BR/error_um", d}, {"distance_B6_BR/error_um", d},
                      {"concentricity_S3_SR/dy_um", d}}});
  }
  {
    const double d = 30.0;
    cases.push_back({"dz_AR(-90)", d,
                     {{"t3_distance_B3_BR/error_um", d}, {"distance_B6_BR/error_um", d},
                      {"t4_size_S3/radius_error_um", -d}, {"size_S6/radius_error_um", -d}}});
  }
  {
    const double d = -25.0;
    cases.push_back({"dy_CA(-90)", d,
                     {{"t4_size_S3/radius_error_um", -d}, {"size_S6/radius_error_um", -d},
                      {"concentricity_S3_SR/dy_um", d}}});
  }
  {
    const double a = 35.0;
    cases.push_back({"alpha_CR(-90)", a,
                     {{"t4_size_S3/radius_error_um", a * h.z3 * k},
                      {"size_S6/radius_error_um", a * h.z6 * k},
                      {"t7_concentricity_S6_S3/dy_um", a * (h.z3 - h.z6) * k},
                      {"concentricity_S3_SR/dy_um", -a * h.z3 * k},
                      {"parallelism_B3_BR/da_urad", a},
                      // B3 and B6 are faced by a Z feed that is not normal to the tilted C line:
                      // shallow cones whose height at the probing radius drops by alpha rho.
                      {"t3_distance_B3_BR/error_um", -a * h.rho_b3 * k},
                      {"distance_B6_BR/error_um", -a * h.rho_b6 * k}}});
  }
  {
    const double g = 20.0;
    cases.push_back({"gamma_CR(-90)", g,
                     {{"t7_concentricity_S6_S3/dx_um", -g * (h.z3 - h.z6) * k},
                      {"concentricity_S3_SR/dx_um", g * h.z3 * k},
                      {"parallelism_B3_BR/db_urad", g}}});
  }
  {
    const double e = 15.0;
    cases.push_back({"beta_ZX", e,
                     {{"t1_concentricity_Ch_SR/dx_um", -e * h.z_sr_cut * k},
                      {"t5_concentricity_S4_SR/dx_um", -e * h.z_sr_cut * k},
                      {"concentricity_S3_SR/dx_um", -e * h.z_sr_cut * k},
                      {"size_S1/radius_error_um", e * h.z1 * k},
                      {"size_S4/radius_error_um", e * h.z4 * k}}});
  }
  {
    const double e = 20.0;
    cases.push_back({"alpha_ZY", e,
                     {{"t1_concentricity_Ch_SR/dy_um", e * h.z_sr_cut * k},
                      {"t5_concentricity_S4_SR/dy_um", e * h.z_sr_cut * k},
                      {"concentricity_S3_SR/dy_um", e * h.z_sr_cut * k},
                      {"size_S2/radius_error_um", -e * h.z2 * k},
                      {"size_S5/radius_error_um", -e * h.z5 * k},
                      {"t3_distance_B3_BR/error_um", e * h.rho_b3 * k},
                      {"distance_B6_BR/error_um", e * h.rho_b6 * k}}});
  }
  return cases;
}

double ItemValue(const gdt::InspectionResult& r, const std::string& characteristic, const std::string& value) {
  const gdt::CharacteristicResult* c = r.Characteristic(characteristic);
  EXPECT_NE(c, nullptr) << characteristic;
  if (!c) return NAN;
  auto v = c->Value(value);
  EXPECT_TRUE(v.has_value()) << characteristic << "/" << value;
  return v.value_or(NAN);
}

TEST(Seed002Equations, ZeroErrorsGiveZeroDeviations) {
  const kinematics::MachineModel m = EquationsAcTable();
  const kinematics::ErrorState none(m);
  for (const ProbingOptions& density : {ProbingOptions::Paper(), ProbingOptions::Dense()}) {
    PieceSimOptions o;
    o.density = density;
    auto sim = SimulatePiece(EquationsPiece(), m, none, o);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    for (double s : sim->truth.deviation_mm) EXPECT_LT(std::abs(s), 1e-9);
    const Rigid3 datum_from_part = EquationsPiece().part_from_datum.inverse();
    for (std::size_t i = 0; i < sim->points.size(); ++i) {
      EXPECT_LT((sim->points.xyz_mm[i] - datum_from_part * sim->truth.plan.points[i].point_part_mm).norm(), 1e-9);
    }
  }
  const gdt::InspectionResult r = EvaluateEquations(none);
  for (const auto& [name, value] : kChecked) EXPECT_NEAR(ItemValue(r, name, value), 0.0, 1e-6) << name << "/" << value;
}

TEST(Seed002Equations, EachTable2ParameterReproducesItsEquations) {
  const kinematics::MachineModel m = EquationsAcTable();
  for (const Case& c : Cases()) {
    SCOPED_TRACE(c.parameter);
    kinematics::ErrorState errors(m);
    auto info = kinematics::LookupParameter(m, c.parameter);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    const double internal = info->quantity == kinematics::Quantity::kLength ? c.value * 1e-3 : c.value * 1e-6;
    ASSERT_TRUE(errors.SetParameter(m, c.parameter, internal).ok());
    const gdt::InspectionResult r = EvaluateEquations(errors);
    for (const auto& [name, value] : kChecked) {
      const std::string key = name + "/" + value;
      const auto it = c.expected.find(key);
      const double expected = it == c.expected.end() ? 0.0 : it->second;
      const double got = ItemValue(r, name, value);
      EXPECT_NEAR(got, expected, std::max(kRelTol * std::abs(expected), kAbsTol_um))
          << c.parameter << " = " << c.value << ": " << key;
    }
  }
}

TEST(Seed002Equations, RandomCmmPlacementDoesNotChangeTheResult) {
  const kinematics::MachineModel m = EquationsAcTable();
  kinematics::ErrorState errors(m);
  ASSERT_TRUE(errors.SetParameter(m, "beta_CR(0)", -25e-6).ok());
  ASSERT_TRUE(errors.SetParameter(m, "dz_AR(-90)", 0.030).ok());
  const gdt::InspectionResult a = EvaluateEquations(errors, false);
  const gdt::InspectionResult b = EvaluateEquations(errors, true);
  for (const auto& [name, value] : kChecked) {
    // Placement changes only rounding: a 300 mm translation and a rotation cost ~1e-10 mm.
    EXPECT_NEAR(ItemValue(a, name, value), ItemValue(b, name, value), 1e-5) << name << "/" << value;
  }
}

// Eqs. 22-27: C-axis radial and tilt error motions (second harmonic) appear in the circularity
// profiles with the phase of the tool position: S1, S4 (tool at +X): theta = C; S2, S5 (tool at
// +Y) and S3, S6 (A = -90, tool above): theta = C + 90 deg.
struct ProfileCase {
  std::string yaml;                       // the error motion
  std::map<std::string, double> amp_um;   // feature -> expected dr = amp cos(2 theta)
};

TEST(Seed002Equations, ErrorMotionsAppearInTheCircularityProfiles) {
  const kinematics::MachineModel m = EquationsAcTable();
  const Heights h = H();
  const double c = 2.0, t = 10.0;  // um, urad
  const std::vector<ProfileCase> cases = {
      // eq. 22, 24: dr_S1(C) = -E_XC(C), dr_S4 = -E_XC(C); S2 sees it tangentially (0).
      {"  - rotary_error_motion: {symbol: E_XC, at: {A_deg: 0}, harmonics: [{order: 2, cos_um: 2}]}\n",
       {{"S1", -c}, {"S4", -c}, {"S2", 0.0}, {"S3", 0.0}}},
      // eq. 23, 25: dr_S2(C + 90) = -E_YC(C): -c cos(2 theta - 180) = +c cos(2 theta).
      {"  - rotary_error_motion: {symbol: E_YC, at: {A_deg: 0}, harmonics: [{order: 2, cos_um: 2}]}\n",
       {{"S2", c}, {"S5", c}, {"S1", 0.0}}},
      // eq. 22, 24 tilt: dr_S1(C) = -E_BC(C) z1.
      {"  - rotary_error_motion: {symbol: E_BC, at: {A_deg: 0}, harmonics: [{order: 2, cos_urad: 10}]}\n",
       {{"S1", -t * h.z1 * 1e-3}, {"S4", -t * h.z4 * 1e-3}, {"S2", 0.0}}},
      // eq. 23, 25 tilt: dr_S2(C + 90) = +E_AC(C) z2 -> -t z2 cos(2 theta).
      {"  - rotary_error_motion: {symbol: E_AC, at: {A_deg: 0}, harmonics: [{order: 2, cos_urad: 10}]}\n",
       {{"S2", -t * h.z2 * 1e-3}, {"S5", -t * h.z5 * 1e-3}, {"S1", 0.0}}},
      // eq. 26, 27 at A = -90: dr_S3(C + 90) = -E_YC(C) + E_AC(C) z3.
      {"  - rotary_error_motion: {symbol: E_YC, at: {A_deg: -90}, harmonics: [{order: 2, cos_um: 2}]}\n",
       {{"S3", c}, {"S6", c}, {"S1", 0.0}, {"S2", 0.0}}},
      {"  - rotary_error_motion: {symbol: E_AC, at: {A_deg: -90}, harmonics: [{order: 2, cos_urad: 10}]}\n",
       {{"S3", -t * h.z3 * 1e-3}, {"S6", -t * h.z6 * 1e-3}, {"S4", 0.0}}},
  };
  for (const ProfileCase& pc : cases) {
    SCOPED_TRACE(pc.yaml);
    auto errors = kinematics::ParseErrorState("effects:\n" + pc.yaml, "<test>", m);
    ASSERT_TRUE(errors.ok()) << errors.status().ToString();
    const gdt::InspectionResult r = EvaluateEquations(*errors);
    for (const auto& [feature, amp] : pc.amp_um) {
      std::string name;
      for (const auto& ch : EquationsPiece().inspection.characteristics) {
        if (ch.type == gdt::CharacteristicType::kCircularity && ch.feature == feature) name = ch.name;
      }
      const gdt::CharacteristicResult* res = r.Characteristic(name);
      ASSERT_NE(res, nullptr) << feature;
      ASSERT_EQ(res->profile.size(), 16u);
      for (const gdt::ProfileSample& s : res->profile) {
        const double expected = amp * std::cos(2.0 * s.theta_deg * kPi / 180.0);
        EXPECT_NEAR(s.dr_um, expected, std::max(kRelTol * std::abs(amp), kAbsTol_um))
            << feature << " theta " << s.theta_deg;
      }
    }
  }
}

}  // namespace
}  // namespace tpcal::testpieces
