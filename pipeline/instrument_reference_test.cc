// A turning piece diagnosed against a datum-ball test of the same A/C table (issue 22). Truth: the
// machine's cold geometry, ISO 230-1 location errors and squareness of a few to 20 um / urad
// (kColdErrors); the datum-ball test of it (A at 0, -30, -60, -90 deg, C every 30 deg, ball at
// (200, 0.1, 300) mm) with readings of noise sigma 0.5 um (tight) or 20 um (loose) per axis; the
// piece cut by the same machine cold, or with a table-motor drift of E_X0C (8 um, tau 20 min)
// withheld from the instrument, measured with 0.5 um noise at a random placement. Fixed seeds.
// Expected: cold piece and tight instrument agree on every compared parameter (family-wise
// false-alarm probability <= alpha = 0.01 by construction) and the verdict is none; the loose
// instrument raises no alarm either (its u lets the piece decide); the drift is named.
#include "pipeline/instrument_reference.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <cstdio>
#include <random>
#include <set>

#include "kinematics/datum_ball.h"
#include "kinematics/error_parameters.h"
#include "kinematics/errors_yaml.h"
#include "pipeline/datum_ball_stage.h"
#include "pipeline/report/datum_ball_json.h"
#include "pipeline/report/diagnosis_json.h"
#include "pipeline/testing/turning_fixture.h"
#include "testpieces/datum_ball_plan.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

const char* const kColdErrors =
    "schema: tpcal.errors/1\nmachine: ac_table\nE_Y0A_um: 15\nE_Z0A_um: -8\nE_B0A_urad: 6\nE_C0A_urad: -4\n"
    "E_A0A_urad: 12\nE_X0C_um: 10\nE_Y(0A)C_um: -6\nE_B0C_urad: -20\nE_C(0X)Y_urad: 7\nE_B(0X)Z_urad: 5\n"
    "E_A(0Y)Z_urad: -3\n";
const char* const kDrift = "effects:\n  - thermal_drift:\n      parameter: E_X0C\n      K_um: 8\n      tau_s: 1200\n";

std::filesystem::path InstrumentTestDir() {
  auto dir = std::filesystem::temp_directory_path() / ("tpcal_instrument_reference_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

kinematics::ErrorState InstrumentTestErrors(const std::string& yaml) {
  auto e = kinematics::ParseErrorState(yaml, "errors.yaml", test_support::AcTable());
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return *e;
}

// The datum-ball file of the cold machine, readings with N(0, sigma_um) per axis.
std::string WriteBallpos(double sigma_um, std::uint64_t seed, const std::string& cold_yaml = kColdErrors) {
  const auto m = test_support::AcTable();
  const kinematics::ErrorState cold = InstrumentTestErrors(cold_yaml);
  auto plan = testpieces::MakeDatumBallPlan(m, {.tilt_deg = {0.0, -30.0, -60.0, -90.0}});
  EXPECT_TRUE(plan.ok()) << plan.status().ToString();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_um * 1e-3);
  std::string text = "# tpcal ballpos v1\n# units: mm\nA_deg,C_deg,x,y,z\n";
  for (const auto& pos : plan->positions) {
    auto cmd = kinematics::BallCentreCommand(m, cold, pos, plan->ball_part_mm);
    EXPECT_TRUE(cmd.ok()) << cmd.status().ToString();
    // Drawn z, y, x in sequence: the order GCC gave the call's arguments (C++ leaves it unspecified).
    const double noise_z = noise(rng), noise_y = noise(rng), noise_x = noise(rng);
    text += fmt::format("{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", pos.a_rad * 180.0 / M_PI, pos.c_rad * 180.0 / M_PI,
                        cmd->x() + noise_x, cmd->y() + noise_y, cmd->z() + noise_z);
  }
  const auto path = InstrumentTestDir() / fmt::format("ball_{}_{}.csv", sigma_um, seed);
  std::ofstream(path) << text;
  return path.string();
}

PointSet CutPiece(const std::string& errors_yaml, std::uint64_t seed) {
  testpieces::PieceSimOptions o;
  o.noise_um = 0.5, o.seed = seed, o.random_placement = true;
  auto sim = testpieces::SimulatePiece(test_support::Turning(), test_support::AcTable(), InstrumentTestErrors(errors_yaml), o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  return sim->points;
}

Result<DiagnosisResult> AgainstBall(const PointSet& piece, const std::string& ballpos) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  DiagnosisOptions options;
  return DiagnoseAgainstInstrument(setup, piece, {.path = ballpos, .instrument = "datum_ball", .setup_path = "", .machine_path = ""}, options);
}

TEST(InstrumentReference, ColdPieceAgreesWithATightDatumBallTest) {
  auto d = AgainstBall(CutPiece(kColdErrors, 7), WriteBallpos(0.5, 11));
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  ASSERT_TRUE(d->reference_agreement.has_value());
  const ReferenceAgreement& a = *d->reference_agreement;
  EXPECT_GE(a.compared, 6);
  EXPECT_EQ(a.disagreeing, 0);
  for (const AgreementRow& r : a.rows) EXPECT_TRUE(r.agree) << r.name << " z " << r.z;
  EXPECT_EQ(d->verdict.family, "none");
}

TEST(InstrumentReference, ALooseInstrumentRaisesNoAlarm) {
  auto d = AgainstBall(CutPiece(kColdErrors, 8), WriteBallpos(20.0, 12));
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  EXPECT_EQ(d->reference_agreement->disagreeing, 0);
  EXPECT_EQ(d->verdict.family, "none") << DiagnosisText(*d);
}

TEST(InstrumentReference, DriftWithheldFromTheInstrumentIsNamed) {
  auto d = AgainstBall(CutPiece(std::string(kColdErrors) + kDrift, 9), WriteBallpos(0.5, 13));
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  EXPECT_EQ(d->verdict.family, "thermal_drift") << DiagnosisText(*d);
}

// A drift of the C line's tilt (E_B0C, 20 urad, tau 1500 s) withheld from the instrument: its mean
// over the machining time makes parameters disagree. They are refitted on top of the instrument
// (named in the base model, the gap with everything held kept beside), and the tilt drift
// candidate names what is left. Held, this piece read linear_straightness (README).
// Truth: a tilt drift of the C line (E_B0C, 40 urad, tau 1500 s) on the piece, none in the cold
// ball test. Over 20 noise realisations (pieces 1000+k, balls 2000+k) it was named 20 times, its
// parameter refitted each time, and the cold piece stayed clean 19 times; at 20 urad it was named
// 5 times of 20 (below what the turning piece resolves), so the test runs five realisations of
// the larger drift and asks every one to name it, and four of five cold pieces to stay clean.
TEST(InstrumentReference, TiltDriftIsNamedBeyondTheDisagreeingParameters) {
  const std::string tilt = "effects:\n  - thermal_drift:\n      parameter: E_B0C\n      K_urad: 40\n      tau_s: 1500\n";
  int cold_clean = 0;
  for (int k = 0; k < 5; ++k) {
    SCOPED_TRACE(k);
    auto d = AgainstBall(CutPiece(std::string(kColdErrors) + tilt, 1000 + k), WriteBallpos(0.5, 2000 + k));
    ASSERT_TRUE(d.ok()) << d.status().ToString();
    ASSERT_GT(d->reference_agreement->disagreeing, 0);
    std::set<std::string> disagreeing;
    for (const AgreementRow& r : d->reference_agreement->rows)
      if (!r.agree) disagreeing.insert(r.members.begin(), r.members.end());
    ASSERT_FALSE(d->base_parameters.empty());
    EXPECT_NE(d->base_model.find("refitted"), std::string::npos) << d->base_model;
    for (const auto& p : d->base_parameters) {
      EXPECT_TRUE(disagreeing.count(p.name)) << p.name;
      EXPECT_NE(d->base_model.find(p.name), std::string::npos) << d->base_model;
    }
    ASSERT_TRUE(d->reference_held_rms_um.has_value());
    EXPECT_GT(*d->reference_held_rms_um, d->rms_um);
    EXPECT_EQ(d->verdict.family, "thermal_drift") << DiagnosisText(*d);
    auto cold = AgainstBall(CutPiece(kColdErrors, 3000 + k), WriteBallpos(0.5, 4000 + k));
    ASSERT_TRUE(cold.ok()) << cold.status().ToString();
    cold_clean += !cold->reference_held_rms_um.has_value() && cold->base_parameters.empty();  // nothing refitted
  }
  EXPECT_GE(cold_clean, 4);
}

TEST(InstrumentReference, UnknownInstrumentAndOtherMachineTypeAreNamed) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto bad = DiagnoseAgainstInstrument(setup, PointSet{}, {.path = "x.csv", .instrument = "laser", .setup_path = "", .machine_path = ""}, {});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("expected datum_ball"), std::string::npos);
  const auto bc = InstrumentTestDir() / "bc.csv";
  std::ofstream(bc) << "# tpcal ballpos v1\nB_deg,C_deg,x,y,z\n";
  for (int b : {0, 30, -30})
    for (int c : {0, 90, 180, 270}) std::ofstream(bc, std::ios::app) << b << "," << c << ",200,0,300\n";
  auto other = DiagnoseAgainstInstrument(setup, PointSet{}, {.path = bc.string(), .instrument = "datum_ball", .setup_path = "", .machine_path = ""}, {});
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.status().ToString().find("machine is ac_table"), std::string::npos) << other.status().ToString();
}

// The identification JSON `tpcal identify --instrument datum_ball --json` writes serves as the
// reference as the raw file does: the same table and the same gap, since values, u and the
// covariance round-trip through nlohmann's shortest form exactly (1e-9 um allowed for the sums'
// order). A JSON without its covariance (an older file) keeps u alone, not the correlations the
// update weighs: its gap agrees to 0.05 um, a tenth of the piece's 0.5 um noise.
TEST(InstrumentReference, IdentificationJsonGivesTheSameComparisonAsTheRawFile) {
  const std::string ballpos = WriteBallpos(0.5, 11);
  auto report = RunDatumBallStage({.path = ballpos, .machine_path = "", .parameters = {}, .ball_part_mm = {}});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const auto json_path = InstrumentTestDir() / "ball.json";
  std::ofstream(json_path) << DatumBallJson(*report);
  const PointSet piece = CutPiece(kColdErrors, 7);
  auto raw = AgainstBall(piece, ballpos), js = AgainstBall(piece, json_path.string());
  ASSERT_TRUE(raw.ok() && js.ok()) << js.status().ToString();
  ASSERT_EQ(raw->reference_agreement->rows.size(), js->reference_agreement->rows.size());
  for (std::size_t k = 0; k < raw->reference_agreement->rows.size(); ++k) {
    EXPECT_EQ(raw->reference_agreement->rows[k].z, js->reference_agreement->rows[k].z) << k;
    EXPECT_EQ(raw->reference_agreement->rows[k].instrument_value, js->reference_agreement->rows[k].instrument_value);
  }
  EXPECT_EQ(js->reference_agreement->instrument, "datum_ball");
  EXPECT_NEAR(raw->rms_um, js->rms_um, 1e-9) << "raw " << raw->rms_um << ", json " << js->rms_um;
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(DatumBallJson(*report));
  ASSERT_EQ(doc.erase("parameter_covariance"), 1u);
  std::ofstream(InstrumentTestDir() / "ball_u.json") << doc.dump(2);
  auto u_alone = AgainstBall(piece, (InstrumentTestDir() / "ball_u.json").string());
  ASSERT_TRUE(u_alone.ok()) << u_alone.status().ToString();
  EXPECT_NEAR(raw->rms_um, u_alone->rms_um, 0.05) << "raw " << raw->rms_um << ", u alone " << u_alone->rms_um;
  std::ofstream(InstrumentTestDir() / "bad.json") << "{\"schema\": \"tpcal.identification/1\",\n \"parameters\": [{\"name\": \"E_X0C\", \"unit\": \"um\", \"identifiable\": true, \"u\": 1}]}";
  auto bad = AgainstBall(piece, (InstrumentTestDir() / "bad.json").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().ToString().find("bad.json: parameters[0] (E_X0C): expected a number \"value\""), std::string::npos)
      << bad.status().ToString();
  std::ofstream(InstrumentTestDir() / "broken.json") << "{\n\"schema\": \n,";
  auto broken = AgainstBall(piece, (InstrumentTestDir() / "broken.json").string());
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.status().ToString().find("broken.json:3: expected JSON"), std::string::npos) << broken.status().ToString();
}

// A small study (fixed seed 2026): 30 machines with random cold errors (the 11 parameters
// uniform in +-20 um / urad), each measured by a tight datum-ball test (0.5 um) and a loose one
// (20 um), cutting one cold piece and one with a withheld table drift of E_X0C (K uniform in 4 to
// 12 um, tau in 600 to 2400 s; the piece takes about 40 min, so the drift's visible part peaks at
// several times the 0.5 um noise). Targets of issue 22: the drift named (top-1) in >= 90 % of the
// trials, false alarms (verdict not none, or a parameter disagreeing, on a cold piece) <= 5 %.
// With 30 trials a true 5 % rate gives more than 3 alarms with probability 6 %: the test allows 3.
// Measured: false alarms 0/30 (tight) and 1/30 (loose: unexplained); the drift named 30/30 (the
// parameters the piece disagrees on refitted on top of the instrument; held, 26/30: the mean of
// a short-tau drift stayed in the gap and linear_straightness's quartic fitted it better). The
// test asks for the 90 % target, 27 of 30.
TEST(InstrumentReference, StudyOfFalseAlarmsAndAWithheldDrift) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> base(-20.0, 20.0), k_um(4.0, 12.0), tau_s(600.0, 2400.0);
  const std::vector<std::string> names = kinematics::IsoLocationSet(test_support::AcTable());
  int tight_alarms = 0, loose_alarms = 0, drift_named = 0;
  const int trials = 30;
  for (int t = 0; t < trials; ++t) {
    std::string cold = "schema: tpcal.errors/1\nmachine: ac_table\n";
    for (const auto& name : names) {
      auto info = kinematics::LookupParameter(test_support::AcTable(), name);
      ASSERT_TRUE(info.ok());
      if (name == "E_C0C") continue;  // the C zero: the turning piece and the ball both leave it free
      cold += fmt::format("{}_{}: {:.3f}\n", name, info->quantity == kinematics::Quantity::kAngle ? "urad" : "um", base(rng));
    }
    const double drift_k_um = k_um(rng), drift_tau_s = tau_s(rng);  // drawn in this order under every compiler
    const std::string hot = cold + fmt::format("effects:\n  - thermal_drift:\n      parameter: E_X0C\n      K_um: {:.3f}\n"
                                               "      tau_s: {:.1f}\n", drift_k_um, drift_tau_s);
    const std::string tight = WriteBallpos(0.5, 100 + t, cold), loose = WriteBallpos(20.0, 200 + t, cold);
    const PointSet cold_piece = CutPiece(cold, 300 + t), hot_piece = CutPiece(hot, 400 + t);
    auto a = AgainstBall(cold_piece, tight), b = AgainstBall(cold_piece, loose), c = AgainstBall(hot_piece, tight);
    ASSERT_TRUE(a.ok() && b.ok() && c.ok()) << t;
    tight_alarms += (a->verdict.family != "none" || a->reference_agreement->disagreeing > 0) ? 1 : 0;
    loose_alarms += (b->verdict.family != "none" || b->reference_agreement->disagreeing > 0) ? 1 : 0;
    drift_named += c->verdict.family == "thermal_drift" ? 1 : 0;
  }
  std::printf("instrument study: drift named %d/%d, false alarms tight %d/%d, loose %d/%d\n", drift_named, trials,
              tight_alarms, trials, loose_alarms, trials);
  EXPECT_GE(drift_named, 27);
  EXPECT_LE(tight_alarms, 3);
  EXPECT_LE(loose_alarms, 3);
}

}  // namespace
}  // namespace tpcal::pipeline
