// `tpcal simulate`: zero errors give the nominal piece (to 1e-9 mm in the part frame, through the
// stated placement); a location error of C shows up through `tpcal fit` with the sign of seed 002
// eqs. 1, 10 and 16; noise, seed and probe-radius error do what the truth file says; a bad
// errors key exits 2 naming file:line and the key, writing nothing.
#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "core/units.h"
#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"
#include "pipeline/io/point_io.h"
#include "testpieces/probing_plan.h"
#include "tests/cli/plan_simulate_run.h"

namespace tpcal::cli_test {
namespace {

using SimulateCli = CliTest;

const std::string kMachine = Source("samples/machines/ac_table.yaml");
const std::string kTurningPlan = Source("samples/plans/turning.yaml");

Rigid3 RigidFromYaml(const YAML::Node& n) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = n["rotation"][i][j].as<double>();
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) t[i] = n["translation_mm"][i].as<double>();
  return MakeRigid(r, t);
}

// The nominal plan of the seed 002 piece on the sample machine (what the CLI builds).
testpieces::ProbingPlan NominalTurningPlan() {
  auto machine = kinematics::LoadMachineModel(kMachine);
  EXPECT_TRUE(machine.ok());
  auto piece = testpieces::MakeTestPiece(testpieces::PieceConfig{}, *machine);
  EXPECT_TRUE(piece.ok());
  auto plan = testpieces::MakeProbingPlan(*piece);
  EXPECT_TRUE(plan.ok());
  return *plan;
}

double Characteristic(const nlohmann::json& fit, const std::string& name, const std::string& value) {
  for (const auto& c : fit["characteristics"])
    if (c["name"] == name) return c["values"][value].get<double>();
  ADD_FAILURE() << "no characteristic " << name;
  return NAN;
}

TEST_F(SimulateCli, ZeroErrorsGiveTheNominalPieceInThePartFrame) {
  // Double precision through a rigid placement (|p| < 1 km): 1e-9 mm is ~1e3 ulps of margin.
  constexpr double kZero_mm = 1e-9;
  WriteText(Path("zero.yaml"), "schema: tpcal.errors/1\nmachine: ac_table\n");
  const testpieces::ProbingPlan plan = NominalTurningPlan();
  for (const char* placement : {"datum", "random"}) {
    SCOPED_TRACE(placement);
    const RunResult r = Run(std::string("simulate --testpiece turning --machine ") + kMachine +
                            " --errors zero.yaml --placement " + placement + " --seed 11 -o pts.csv --truth truth.yaml");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto file = pipeline::ReadPointFile(Path("pts.csv"));
    ASSERT_TRUE(file.ok()) << file.status().ToString();
    EXPECT_EQ(file->info.kind, pipeline::PointFileKind::kPoints);
    const PointSet& ps = file->points;
    ASSERT_EQ(ps.size(), plan.points.size());
    const YAML::Node truth = YAML::LoadFile(Path("truth.yaml"));
    const Rigid3 cmm_from_part = RigidFromYaml(truth["cmm_from_part"]);
    const Rigid3 part_from_cmm = cmm_from_part.inverse();
    double worst_mm = 0;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      ASSERT_EQ(ps.feature_names[ps.feature[i]], plan.points[i].feature);
      const Eigen::Vector3d p_part = part_from_cmm * ps.xyz_mm[i];
      worst_mm = std::max(worst_mm, (p_part - plan.points[i].point_part_mm).norm());
      EXPECT_LT((part_from_cmm.linear() * ps.normal[i] - plan.points[i].normal_part).norm(), 1e-12);
    }
    EXPECT_LT(worst_mm, kZero_mm);
    const bool random = std::string(placement) == "random";
    // Datum placement: the CMM frame is the datum frame (cmm_from_datum = identity).
    const Rigid3 cmm_from_datum = RigidFromYaml(truth["cmm_from_datum"]);
    EXPECT_EQ(cmm_from_datum.isApprox(Rigid3::Identity(), 1e-15), !random);
    EXPECT_EQ(truth["placement"].as<std::string>(), placement);
    EXPECT_EQ(truth["seed"].as<std::uint64_t>(), 11u);
    EXPECT_EQ(truth["noise_um"].as<double>(), 0.0);
    for (const char* f : {"S_R", "B_R", "H1", "S4", "B3"}) {
      EXPECT_LT(std::abs(truth["deviation_by_feature"][f]["min_um"].as<double>()), MmToUm(kZero_mm)) << f;
      EXPECT_LT(std::abs(truth["deviation_by_feature"][f]["max_um"].as<double>()), MmToUm(kZero_mm)) << f;
    }
  }
}

// ISO 230-1 E_X0C = +10 um (C axis line and table at +X): S4 is turned about the actual C line,
// S_R and the holes were milled / reamed with the machine's X, Y at C = 0 and indexed C, so in the
// datum frame (X toward H1 = table +X at C = 0) S4 and the hole pitch circle sit at +10 um in x
// from S_R: seed 002 eq. 1 (dx_CR(0) = E_X0C), eqs. 10 and 16 (dx = dx_CR(0), no height terms).
// First order: within 1 % of the effect; y within 1 % of it too (no y effect).
TEST_F(SimulateCli, LocationErrorOfCShowsUpInConcentricityWithItsSign) {
  constexpr double kEffect_um = 10.0, kTol_um = 0.01 * kEffect_um;
  for (const double sign : {1.0, -1.0}) {
    SCOPED_TRACE(sign);
    WriteText(Path("ex0c.yaml"), "E_X0C_um: " + std::to_string(sign * kEffect_um) + "\n");
    RunResult r = Run("simulate --testpiece turning --machine " + kMachine +
                      " --errors ex0c.yaml --placement random --seed 5 -o pts.csv");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = Run("-q fit pts.csv --plan " + kTurningPlan + " --json fit.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json fit = nlohmann::json::parse(ReadText(Path("fit.json")));
    EXPECT_NEAR(Characteristic(fit, "t5_concentricity_S4_SR", "dx_um"), sign * kEffect_um, kTol_um);
    EXPECT_NEAR(Characteristic(fit, "t5_concentricity_S4_SR", "dy_um"), 0.0, kTol_um);
    EXPECT_NEAR(Characteristic(fit, "t1_concentricity_Ch_SR", "dx_um"), sign * kEffect_um, kTol_um);
    EXPECT_NEAR(Characteristic(fit, "t1_concentricity_Ch_SR", "dy_um"), 0.0, kTol_um);
    // S4 and S1 are both turned about the same C line: concentric.
    EXPECT_NEAR(Characteristic(fit, "t6_concentricity_S4_S1", "dx_um"), 0.0, kTol_um);
  }
}

TEST_F(SimulateCli, NoiseSeedProbeRadiusAndTruth) {
  WriteText(Path("e.yaml"), "schema: tpcal.errors/1\nE_X0C_um: 10\nE_B0C_urad: -20\n");
  const std::string base = "simulate --testpiece turning --machine " + kMachine + " --errors e.yaml ";
  ASSERT_EQ(Run(base + "-o clean.csv").exit_code, 0);
  ASSERT_EQ(Run(base + "--noise-um 1 --seed 3 -o a.csv --truth a.yaml").exit_code, 0);
  ASSERT_EQ(Run(base + "--noise-um 1 --seed 3 -o b.csv").exit_code, 0);
  ASSERT_EQ(Run(base + "--noise-um 1 --seed 4 -o c.csv").exit_code, 0);
  EXPECT_EQ(ReadText(Path("a.csv")), ReadText(Path("b.csv")));  // same seed, same file
  EXPECT_NE(ReadText(Path("a.csv")), ReadText(Path("c.csv")));

  // Noise along the normal with the stated sigma: sample sd of n = 352 deviates is within
  // 4 / sqrt(2 n) = 15 % of sigma.
  auto clean = pipeline::ReadPointFile(Path("clean.csv"));
  auto noisy = pipeline::ReadPointFile(Path("a.csv"));
  ASSERT_TRUE(clean.ok() && noisy.ok());
  const std::size_t n = clean->points.size();
  ASSERT_EQ(noisy->points.size(), n);
  double sum = 0, sum2 = 0, off_normal_mm = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = noisy->points.xyz_mm[i] - clean->points.xyz_mm[i];
    const double along_um = MmToUm(d.dot(clean->points.normal[i]));
    sum += along_um;
    sum2 += along_um * along_um;
    off_normal_mm = std::max(off_normal_mm, (d - d.dot(clean->points.normal[i]) * clean->points.normal[i]).norm());
  }
  const double sd_um = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(sd_um, 1.0, 4.0 / std::sqrt(2.0 * n));
  EXPECT_LT(off_normal_mm, 1e-9);

  // The truth states seed, noise and the errors (which read back as an error file).
  const YAML::Node truth = YAML::LoadFile(Path("a.yaml"));
  EXPECT_EQ(truth["schema"].as<std::string>(), "tpcal.simulation_truth/1");
  EXPECT_EQ(truth["seed"].as<int>(), 3);
  EXPECT_EQ(truth["noise_um"].as<double>(), 1.0);
  EXPECT_EQ(truth["n_points"].as<std::size_t>(), n);
  YAML::Emitter em;
  em << truth["errors"];
  auto machine = kinematics::LoadMachineModel(kMachine);
  ASSERT_TRUE(machine.ok());
  auto errors = kinematics::ParseErrorState(em.c_str(), "truth errors", *machine);
  ASSERT_TRUE(errors.ok()) << errors.status().ToString();
  EXPECT_NEAR(*errors->Parameter(*machine, "E_X0C"), 10e-3, 1e-15);
  EXPECT_NEAR(*errors->Parameter(*machine, "E_B0C"), -20e-6, 1e-18);

  // Probe-radius error +2 um: outer diameters read larger, holes smaller (ISO 10360 sign).
  ASSERT_EQ(Run(base + "--probe-radius-error-um 2 -o probe.csv").exit_code, 0);
  ASSERT_EQ(Run("-q fit clean.csv --plan " + kTurningPlan + " --json clean.json").exit_code, 0);
  ASSERT_EQ(Run("-q fit probe.csv --plan " + kTurningPlan + " --json probe.json").exit_code, 0);
  const auto fc = nlohmann::json::parse(ReadText(Path("clean.json")));
  const auto fp = nlohmann::json::parse(ReadText(Path("probe.json")));
  EXPECT_NEAR(Characteristic(fp, "size_S1", "radius_error_um") - Characteristic(fc, "size_S1", "radius_error_um"),
              2.0, 1e-6);
  EXPECT_NEAR(Characteristic(fp, "hole_pattern_Ch", "radius_error_um") -
                  Characteristic(fc, "hole_pattern_Ch", "radius_error_um"),
              0.0, 1e-6);  // hole centres do not move
}

TEST_F(SimulateCli, UnknownErrorKeyExits2NamingFileLineAndKey) {
  WriteText(Path("bad.yaml"), "schema: tpcal.errors/1\nE_X0C_um: 10\nE_X0Q_um: 5\n");
  RunResult r = Run("simulate --testpiece turning --machine " + kMachine +
                    " --errors bad.yaml -o pts.csv --truth truth.yaml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:3:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("E_X0Q_um"), std::string::npos) << r.err;
  // A known parameter with a unit that does not fit it.
  WriteText(Path("unit.yaml"), "E_X0C_urad: 10\n");
  r = Run("simulate --testpiece turning --machine " + kMachine + " --errors unit.yaml -o pts.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unit.yaml:1:"), std::string::npos) << r.err;
  // An unknown key inside an effect, on its own line.
  WriteText(Path("nested.yaml"),
            "E_X0C_um: 10\neffects:\n  - thermal_drift:\n      parameter: E_X0C\n      K_um: 8\n      tau: 1200\n");
  r = Run("simulate --testpiece turning --machine " + kMachine + " --errors nested.yaml -o pts.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nested.yaml:6: unknown key 'tau'"), std::string::npos) << r.err;
  // Other bad input: negative noise, missing errors file, an errors file for another machine.
  r = Run("simulate --testpiece turning --machine " + kMachine + " --errors unit.yaml --noise-um -1 -o pts.csv");
  EXPECT_EQ(r.exit_code, 2);
  r = Run("simulate --testpiece turning --machine " + kMachine + " --errors missing.yaml -o pts.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.yaml"), std::string::npos) << r.err;
  r = Run("simulate --testpiece turning --machine " + kMachine + " --errors " +
          Source("samples/errors/seed001_table1a.yaml") + " -o pts.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("seed001_table1a.yaml"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(Path("pts.csv")));
  EXPECT_FALSE(std::filesystem::exists(Path("truth.yaml")));
}

// Every piece on a machine it can be cut on, with that machine's sample errors: a valid point
// file with the piece's features, which `tpcal fit` (ad hoc plan) accepts.
TEST_F(SimulateCli, EveryPieceOnItsMachine) {
  struct Case { const char* piece; const char* machine; const char* errors; const char* feature; };
  for (const Case& c : {Case{"iso10791_m1_160", "xyz", "seed004_y_straightness", "BORE"},
                        Case{"iso10791_m2", "bc_table", "seed001_table1a", "FACE_P1"},
                        Case{"iso10791_m2", "bhead_ctable", "seed003_bhead_ctable_means", "FACE_P2"},
                        Case{"cone_frustum", "ac_table", "ac_table_iso_example", "CONE_2"}}) {
    SCOPED_TRACE(std::string(c.piece) + " on " + c.machine);
    RunResult r = Run(std::string("simulate --testpiece ") + c.piece + " --machine " +
                      Source(std::string("samples/machines/") + c.machine + ".yaml") + " --errors " +
                      Source(std::string("samples/errors/") + c.errors + ".yaml") + " --noise-um 0.2 -o pts.csv");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto file = pipeline::ReadPointFile(Path("pts.csv"));
    ASSERT_TRUE(file.ok()) << file.status().ToString();
    EXPECT_GE(file->points.IndicesOf(c.feature).size(), 3u);
    r = Run("-q fit pts.csv");
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
}

// --process: the effects that are not machine geometry (tool deflection, servo reversal) go into
// the simulated piece from a tpcal.process/1 file, are stated in the truth, and `tpcal diagnose`,
// not told about them, names them. Truths: ISO location errors of C plus servo spikes of 5 / 4 um,
// or the default cutting-force compliances (about 3 um peak); noise 0.5 um, fixed seeds.
TEST_F(SimulateCli, ProcessEffectsFileIsWithheldFromTheDiagnosis) {
  WriteText(Path("iso.yaml"), "schema: tpcal.errors/1\nE_X0C_um: 6\nE_B0C_urad: -12\nE_C(0X)Y_urad: 15\n");
  WriteText(Path("servo.yaml"), "schema: tpcal.process/1\nservo_reversal: {spike_x_um: 5, spike_y_um: 4, decay_deg: 5}\n");
  WriteText(Path("deflection.yaml"), "schema: tpcal.process/1\ntool_deflection: {compliance_um_per_n: [0.02, 0.025, 0.01]}\n");
  WriteText(Path("none.yaml"), "schema: tpcal.process/1\n");
  struct Case { const char* file; const char* family; };
  for (const Case& c : {Case{"servo.yaml", "servo_reversal"}, Case{"deflection.yaml", "tool_deflection"},
                        Case{"none.yaml", "none"}}) {
    SCOPED_TRACE(c.file);
    RunResult r = Run("simulate --testpiece turning --machine " + kMachine + " --errors iso.yaml --process " + c.file +
                      " --noise-um 0.5 --seed 4 --placement random -o pts.csv --truth truth.yaml");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const YAML::Node truth = YAML::LoadFile(Path("truth.yaml"));
    EXPECT_EQ(truth["process_file"].as<std::string>(), c.file);
    EXPECT_EQ(truth["process"]["servo_reversal"].IsDefined(), std::string(c.file) == "servo.yaml");
    EXPECT_EQ(truth["process"]["tool_deflection"].IsDefined(), std::string(c.file) == "deflection.yaml");
    r = Run("-q diagnose pts.csv --testpiece turning --json d.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto d = nlohmann::json::parse(ReadText(Path("d.json")));
    EXPECT_EQ(d["verdict"]["family"], c.family) << r.out;
  }
  // A bad process file: exit 2 naming file:line and the key, nothing written.
  std::filesystem::remove(Path("pts.csv"));
  WriteText(Path("bad.yaml"), "servo_reversal:\n  spike_x_um: 5\n  spike_q_um: 1\n");
  const RunResult bad = Run("simulate --testpiece turning --machine " + kMachine +
                            " --errors iso.yaml --process bad.yaml -o pts.csv");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad.yaml:3:"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("spike_q_um"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(Path("pts.csv")));
}

// The enriched variants are names like the others (testpieces/named_pieces.h).
TEST_F(SimulateCli, EnrichedPiecesByName) {
  WriteText(Path("zero.yaml"), "schema: tpcal.errors/1\n");
  RunResult r = Run("simulate --testpiece cone_frustum_enriched --machine " + kMachine + " --errors zero.yaml -o cone.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto cone = pipeline::ReadPointFile(Path("cone.csv"));
  ASSERT_TRUE(cone.ok()) << cone.status().ToString();
  EXPECT_EQ(cone->points.IndicesOf("CONE2_1").size(), 48u);  // second cone, 48 points per section
  r = Run("simulate --testpiece turning_enriched --machine " + kMachine + " --errors zero.yaml -o turning.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto turning = pipeline::ReadPointFile(Path("turning.csv"));
  ASSERT_TRUE(turning.ok()) << turning.status().ToString();
  EXPECT_EQ(turning->points.IndicesOf("S_RI").size(), 32u * 3u);  // inner groove wall, 3 levels x 32
  r = Run("simulate --testpiece cone_frustum_enriched --config " + Source("samples/testpieces/iso10791_m2.yaml") +
          " --machine " + kMachine + " --errors zero.yaml -o x.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("but --testpiece is cone_frustum_enriched"), std::string::npos) << r.err;
}

TEST_F(SimulateCli, HelpStatesUnits) {
  const RunResult r = Run("simulate --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"tpcal points v1", "--noise-um", "um", "--seed", "--placement", "random",
                        "--probe-radius-error-um", "cmm_from_part", "--truth", "tpcal.errors/1", "--process",
                        "tpcal.process/1", "cone_frustum_enriched"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

}  // namespace
}  // namespace tpcal::cli_test
