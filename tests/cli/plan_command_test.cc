// `tpcal plan`: the CSV is docs/formats/probing_plan.md exactly (tag, units, column names and
// order), reads back through pipeline::ReadPointFile bit for bit against the library's plan rows,
// is accepted as a point file by `tpcal fit`; density and --step work; bad input exits 2 with
// file:line and writes nothing.
#include <set>

#include "kinematics/machine_yaml.h"
#include "pipeline/io/point_io.h"
#include "testpieces/piece_config.h"
#include "testpieces/probing_plan.h"
#include "tests/cli/plan_simulate_run.h"

namespace tpcal::cli_test {
namespace {

using PlanCli = CliTest;

// Lines of a text file (without their '\n').
std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

TEST_F(PlanCli, TurningPlanIsContractSection2AndMatchesTheLibrary) {
  const RunResult r = Run("plan --testpiece turning -o plan.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = Lines(ReadText(Path("plan.csv")));
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(lines[0], "# tpcal plan v1");
  EXPECT_EQ(lines[1], "# units: mm");
  EXPECT_EQ(lines[2], "feature,x,y,z,i,j,k,op,t_s,A_deg,C_deg,X_mm,Y_mm,Z_mm");

  auto file = pipeline::ReadPointFile(Path("plan.csv"));
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_EQ(file->info.kind, pipeline::PointFileKind::kPlan);
  const PointSet& ps = file->points;
  ASSERT_TRUE(ps.has_normals());

  // The library's plan for the same piece (seed 002 defaults, nominal A/C table).
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  ASSERT_TRUE(machine.ok());
  auto piece = testpieces::MakeTestPiece(testpieces::PieceConfig{}, *machine);
  ASSERT_TRUE(piece.ok());
  auto plan = testpieces::MakeProbingPlan(*piece);
  ASSERT_TRUE(plan.ok());
  const std::vector<testpieces::PlanRow> rows = testpieces::PlanRows(*plan);
  ASSERT_EQ(ps.size(), rows.size());
  const PointAttribute* op = ps.Attribute("op");
  const PointAttribute* t = ps.Attribute("t_s");
  const PointAttribute* a = ps.Attribute("A_deg");
  const PointAttribute* c = ps.Attribute("C_deg");
  const PointAttribute* x = ps.Attribute("X_mm");
  const PointAttribute* y = ps.Attribute("Y_mm");
  const PointAttribute* z = ps.Attribute("Z_mm");
  for (const PointAttribute* attr : {op, t, a, c, x, y, z}) ASSERT_TRUE(attr != nullptr && attr->is_numeric());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const testpieces::PlanRow& row = rows[i];
    ASSERT_EQ(ps.feature_names[ps.feature[i]], row.feature) << i;
    // Shortest round-trip numbers: the file holds the library's doubles exactly (-0 written as 0).
    EXPECT_EQ(ps.xyz_mm[i], row.xyz_mm) << i;
    EXPECT_EQ(ps.normal[i], row.ijk) << i;
    EXPECT_EQ(op->values[i], row.op);
    EXPECT_EQ(t->values[i], row.t_s);
    EXPECT_EQ(a->values[i], row.a_deg);
    EXPECT_EQ(c->values[i], row.c_deg);
    EXPECT_EQ(x->values[i], row.x_mm);
    EXPECT_EQ(y->values[i], row.y_mm);
    EXPECT_EQ(z->values[i], row.z_mm);
    EXPECT_GE(op->values[i], 1.0);
    EXPECT_GT(t->values[i], 0.0);
  }
  // Contract section 3 feature names, all present.
  std::set<std::string> names(ps.feature_names.begin(), ps.feature_names.end());
  for (const char* f : {"S_R", "B_R", "H1", "H16", "S1", "S6", "B1", "B6"}) EXPECT_EQ(names.count(f), 1u) << f;
  // A/C table: A = -90 deg for S3/B3/S6/B6 (turned with the table swivelled), 0 elsewhere.
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const std::string& f = ps.feature_names[ps.feature[i]];
    const bool swivelled = f == "S3" || f == "B3" || f == "S6" || f == "B6";
    EXPECT_EQ(a->values[i], swivelled ? -90.0 : 0.0) << f;
  }

  // The plan is a point file every command accepts (docs/formats/probing_plan.md).
  const RunResult fit = Run("fit plan.csv --plan " + Source("samples/plans/turning.yaml"));
  EXPECT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("t5_concentricity_S4_SR"), std::string::npos);
}

TEST_F(PlanCli, RotaryColumnsFollowTheMachine) {
  // M2 on a B/C table: B_deg, C_deg; on the default 3-axis machine: no rotary column.
  RunResult r = Run("plan --testpiece iso10791_m2 --machine " + Source("samples/machines/bc_table.yaml") + " -o bc.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Lines(ReadText(Path("bc.csv")))[2], "feature,x,y,z,i,j,k,op,t_s,B_deg,C_deg,X_mm,Y_mm,Z_mm");
  r = Run("plan --testpiece iso10791_m1_160 -o m1.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Lines(ReadText(Path("m1.csv")))[2], "feature,x,y,z,i,j,k,op,t_s,X_mm,Y_mm,Z_mm");
  auto m1 = pipeline::ReadPointFile(Path("m1.csv"));
  ASSERT_TRUE(m1.ok()) << m1.status().ToString();
  EXPECT_TRUE(m1->points.FeatureIndex("BORE").has_value());
}

TEST_F(PlanCli, DensityConfigAndStep) {
  auto count = [&](const std::string& file, const std::string& feature) {
    auto f = pipeline::ReadPointFile(Path(file));
    EXPECT_TRUE(f.ok()) << f.status().ToString();
    return f.ok() ? f->points.IndicesOf(feature).size() : 0u;
  };
  ASSERT_EQ(Run("plan --testpiece turning -o paper.csv").exit_code, 0);
  EXPECT_EQ(count("paper.csv", "S4"), 16u);  // seed 002 section 4.2: 16 points per face
  EXPECT_EQ(count("paper.csv", "H7"), 8u);
  ASSERT_EQ(Run("plan --testpiece turning --density 32 --levels 3 -o n32.csv").exit_code, 0);
  EXPECT_EQ(count("n32.csv", "S4"), 96u);    // 32 per circle x 3 levels
  EXPECT_EQ(count("n32.csv", "H7"), 16u);    // N / 2 per hole, one level
  ASSERT_EQ(Run("plan --testpiece turning --density dense -o dense.csv").exit_code, 0);
  EXPECT_EQ(count("dense.csv", "S4"), 64u * 5u);
  EXPECT_EQ(count("dense.csv", "H7"), 16u * 3u);

  // --config: a sample configuration (enriched turning piece: inner groove wall S_RI).
  const RunResult r = Run("plan --testpiece turning --config " + Source("samples/testpieces/turning_enriched.yaml") +
                          " -o enriched.csv --step piece.step --write-config effective.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(count("enriched.csv", "S_RI"), 0u);
  const std::string step = ReadText(Path("piece.step"));
  EXPECT_EQ(step.rfind("ISO-10303-21;", 0), 0u);
  EXPECT_NE(step.find("MANIFOLD_SOLID_BREP"), std::string::npos);
  // The effective configuration reads back to the enriched piece.
  auto effective = testpieces::LoadPieceConfig(Path("effective.yaml"));
  ASSERT_TRUE(effective.ok()) << effective.status().ToString();
  EXPECT_TRUE(std::get<testpieces::TurningPieceParams>(effective->params).groove_inner_wall_pass);
  EXPECT_NE(r.err.find("wrote enriched.csv"), std::string::npos);  // progress on stderr
}

TEST_F(PlanCli, BadInputExits2WithFileLineAndWritesNothing) {
  WriteText(Path("bad.yaml"), "piece: turning\nturning:\n  groove: {bottom_z_mm: 405.702}\n  holez: {count: 16}\n");
  RunResult r = Run("plan --testpiece turning --config bad.yaml -o out.csv --step out.step");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:4:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("holez"), std::string::npos) << r.err;

  r = Run("plan --testpiece turning --config " + Source("samples/testpieces/iso10791_m2.yaml") + " -o out.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("iso10791_m2.yaml"), std::string::npos) << r.err;

  r = Run("plan --testpiece gear -o out.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown test piece 'gear'"), std::string::npos) << r.err;

  r = Run("plan --testpiece turning --density lots -o out.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--density"), std::string::npos) << r.err;

  // The turning piece cannot be cut on a 3-axis machine.
  r = Run("plan --testpiece turning --machine " + Source("samples/machines/xyz.yaml") + " -o out.csv");
  EXPECT_EQ(r.exit_code, 2);

  r = Run("plan --testpiece turning -o out.csv --step ./out.csv");  // one output over the other
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("-o and --step name the same file"), std::string::npos) << r.err;

  r = Run("plan -o out.csv");  // --testpiece missing: usage error
  EXPECT_EQ(r.exit_code, 2);

  EXPECT_FALSE(std::filesystem::exists(Path("out.csv")));
  EXPECT_FALSE(std::filesystem::exists(Path("out.step")));
}

TEST_F(PlanCli, HelpStatesColumnsAndUnits) {
  const RunResult r = Run("plan --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"tpcal plan v1", "x,y,z (mm)", "t_s", "A_deg", "B_deg", "X_mm", "--density", "--step"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

}  // namespace
}  // namespace tpcal::cli_test
