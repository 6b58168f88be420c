// Machine and error YAML files: the samples load, round-trip, and bad input fails with the
// file, the line and the key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "kinematics/errors_yaml.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::kinematics {
namespace {

using ::testing::HasSubstr;

std::string Sample(const std::string& rel) { return std::string(TPCAL_SOURCE_DIR) + "/samples/" + rel; }

MachineModel Load(const std::string& name) {
  Result<MachineModel> m = LoadMachineModel(Sample("machines/" + name));
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  return m.ok() ? *m : MachineModel{};
}

TEST(MachineYaml, SamplesLoadWithTheirTypesAndChains) {
  const MachineModel ac = Load("ac_table.yaml");
  EXPECT_EQ(ac.type, MachineType::kAcTable);
  EXPECT_EQ(ac.num_workpiece_links, 2);
  EXPECT_EQ(ac.links[0].axis, Axis::kA);
  EXPECT_NEAR(ac.links[0].min_position, -120.0 * 3.14159265358979 / 180.0, 1e-12);
  EXPECT_TRUE(ac.links[1].continuous);
  const MachineModel bh = Load("bhead_ctable.yaml");
  EXPECT_EQ(bh.type, MachineType::kBheadCtable);
  EXPECT_EQ(bh.links.back().axis, Axis::kB);
  EXPECT_DOUBLE_EQ(bh.links.back().pivot_mm.z(), 300.0);
  EXPECT_EQ(Load("bc_table.yaml").type, MachineType::kBcTable);
  const MachineModel xyz = Load("xyz.yaml");
  EXPECT_EQ(xyz.num_workpiece_links, 2);  // table X on saddle Y
}

TEST(MachineYaml, FormatRoundTrips) {
  for (const char* f : {"ac_table.yaml", "bc_table.yaml", "bhead_ctable.yaml", "xyz.yaml"}) {
    const MachineModel m = Load(f);
    Result<MachineModel> back = ParseMachineModel(FormatMachineModel(m), "<formatted>");
    ASSERT_TRUE(back.ok()) << back.status().ToString();
    ASSERT_EQ(back->num_links(), m.num_links());
    for (int i = 0; i < m.num_links(); ++i) {
      EXPECT_EQ(back->links[i].axis, m.links[i].axis);
      EXPECT_EQ(back->links[i].continuous, m.links[i].continuous);
      EXPECT_NEAR(back->links[i].min_position, m.links[i].min_position, 1e-12);
      EXPECT_EQ(back->links[i].pivot_mm, m.links[i].pivot_mm);
    }
  }
}

TEST(MachineYaml, BadInputNamesLineAndKey) {
  const std::string text =
      "type: ac_table\n"
      "axes:\n"
      "  X: {min_mm: -1, max_mm: 1}\n"
      "  Y: {min_mm: -1, max_mm: 1, stroke_mm: 3}\n";
  Result<MachineModel> m = ParseMachineModel(text, "m.yaml");
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().line(), 4u);
  EXPECT_THAT(m.status().ToString(), HasSubstr("m.yaml:4:"));
  EXPECT_THAT(m.status().message(), HasSubstr("stroke_mm"));

  Result<MachineModel> missing = ParseMachineModel("type: ac_table\naxes:\n  X: {}\n", "m.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_THAT(missing.status().message(), HasSubstr("missing axis"));

  Result<MachineModel> type = ParseMachineModel("type: ab_table\naxes: {}\n", "m.yaml");
  ASSERT_FALSE(type.ok());
  EXPECT_EQ(type.status().line(), 1u);

  Result<MachineModel> top = ParseMachineModel("type: xyz\nspindle: 1\naxes: {}\n", "m.yaml");
  ASSERT_FALSE(top.ok());
  EXPECT_EQ(top.status().line(), 2u);
  EXPECT_THAT(top.status().message(), HasSubstr("'spindle'"));

  Result<MachineModel> syntax = ParseMachineModel("type: xyz\naxes: [\n", "m.yaml");
  ASSERT_FALSE(syntax.ok());
  EXPECT_EQ(syntax.status().code(), StatusCode::kParseError);

  Result<MachineModel> nofile = LoadMachineModel("/nonexistent/machine.yaml");
  ASSERT_FALSE(nofile.ok());
  EXPECT_EQ(nofile.status().code(), StatusCode::kIoError);
}

TEST(ErrorsYaml, AllSamplesLoadAgainstTheirMachines) {
  const MachineModel ac = Load("ac_table.yaml");
  const struct { const char* file; const MachineModel machine; int coefficients; } cases[] = {
      {"seed002_table2_machining.yaml", ac, 11},
      {"seed002_table2_probing.yaml", ac, 9},
      {"ac_table_iso_example.yaml", ac, 11 + 3 + 4 + 3 + 6 + 1 + 1 + 1},
      {"seed000_error_map_example.yaml", ac, 24 + 4},
      {"seed001_table1a.yaml", Load("bc_table.yaml"), 11},
      {"seed003_bhead_ctable_means.yaml", Load("bhead_ctable.yaml"), 12},
      {"seed004_y_straightness.yaml", Load("xyz.yaml"), 17},
  };
  for (const auto& c : cases) {
    Result<ErrorState> e = LoadErrorState(Sample(std::string("errors/") + c.file), c.machine);
    ASSERT_TRUE(e.ok()) << e.status().ToString();
    EXPECT_EQ(e->num_coefficients(), c.coefficients) << c.file;
  }
}

TEST(ErrorsYaml, UnitsConvertToMmAndRad) {
  const MachineModel ac = Load("ac_table.yaml");
  Result<ErrorState> e = LoadErrorState(Sample("errors/seed002_table2_machining.yaml"), ac);
  ASSERT_TRUE(e.ok());
  EXPECT_DOUBLE_EQ(*e->Parameter(ac, "dx_CR(0)"), 12.4e-3);
  EXPECT_DOUBLE_EQ(*e->Parameter(ac, "gamma_CR(-90)"), 1.6e-6);
  EXPECT_DOUBLE_EQ(*e->Parameter(ac, "E_B(0X)Z"), 3.5e-6);  // beta_ZX is its alias
  Result<ErrorState> mm = ParseErrorState("E_X0C_mm: 0.01\nE_B0C_deg: 1\n", "<s>", ac);
  ASSERT_TRUE(mm.ok()) << mm.status().ToString();
  EXPECT_DOUBLE_EQ(*mm->Parameter(ac, "E_X0C"), 0.01);
  EXPECT_NEAR(*mm->Parameter(ac, "E_B0C"), 3.14159265358979 / 180.0, 1e-15);
  const std::optional<int> drift = LoadErrorState(Sample("errors/ac_table_iso_example.yaml"), ac)
                                       ->FindCoefficient("E_B0C.drift_rate");
  ASSERT_TRUE(drift);
}

TEST(ErrorsYaml, FormatRoundTripsEveryTermKind) {
  const MachineModel ac = Load("ac_table.yaml");
  for (const char* f : {"ac_table_iso_example.yaml", "seed000_error_map_example.yaml",
                        "seed002_table2_machining.yaml"}) {
    Result<ErrorState> e = LoadErrorState(Sample(std::string("errors/") + f), ac);
    ASSERT_TRUE(e.ok());
    const std::string text = FormatErrorState(*e, ac);
    Result<ErrorState> back = ParseErrorState(text, "<formatted>", ac);
    ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << text;
    ASSERT_EQ(back->num_coefficients(), e->num_coefficients());
    for (int i = 0; i < e->num_coefficients(); ++i) {
      EXPECT_EQ(back->coefficient_info(i).name, e->coefficient_info(i).name);
      EXPECT_NEAR(back->coefficient(i), e->coefficient(i), 1e-15 * (1 + std::abs(e->coefficient(i))));
    }
  }
}

struct BadCase {
  const char* text;
  std::size_t line;
  const char* substring;
};

TEST(ErrorsYaml, BadInputNamesLineAndKey) {
  const MachineModel ac = Load("ac_table.yaml");
  const BadCase cases[] = {
      {"E_X0C_um: 1\nE_X0Q_um: 2\n", 2, "E_X0Q_um"},
      {"E_X0C_urad: 1\n", 1, "a length"},
      {"E_B0C_um: 1\n", 1, "an angle"},
      {"E_X0C_um: ten\n", 1, "expected a number"},
      {"E_Y0C_um: 1\nE_Y(0A)C_um: 2\n", 2, "given twice"},
      {"beta_ZX_urad: 1\nE_B(0X)Z_urad: 2\n", 2, "given twice"},
      {"machine: bc_table\n", 1, "bc_table"},
      {"schema: tpcal.errors/2\n", 1, "schema"},
      {"effects:\n  - linear_error_motion:\n      symbol: E_YX\n      coefficents_um_per_mm_pow: [1]\n", 3,
       "give"},
      {"effects:\n  - linear_error_motion:\n      symbol: E_YX\n      coefficients_um_per_mm_pow: [1]\n"
       "      order: 2\n", 5, "'order'"},
      {"effects:\n  - rotary_error_motion: {symbol: E_XC, harmonics: [{order: 2, cos_urad: 1}]}\n", 2,
       "cos_urad"},
      {"effects:\n  - rotary_error_motion: {symbol: E_XC, at: {B_deg: 0}, harmonics: [{order: 2, cos_um: 1}]}\n",
       2, "B_deg"},
      {"effects:\n  - rotary_error_motion: {symbol: E_XQ, harmonics: []}\n", 2, "E_XQ"},
      {"effects:\n  - thermal_drift: {parameter: E_X0C, K_um: 8}\n", 2, "tau_s"},
      {"effects:\n  - thermal_drift: {parameter: E_X0C, K_um: 8, tau_s: 10}\n"
       "  - thermal_drift: {parameter: E_X0C, K_um: 3, tau_s: 20}\n", 3, "duplicate"},
      {"effects:\n  - thermal_drift: {parameter: E_Q0C, K_um: 8, tau_s: 1}\n", 2, "E_Q0C"},
      {"effects:\n  - operation_offset: {parameter: E_Z0A, op: 0, value_um: 1}\n", 2, "op"},
      {"effects:\n  - spindle_growth: {K_um: 1}\n", 2, "spindle_growth"},
      {"effects:\n  - rotary_error_motion: {symbol: E_CC, positions_deg: [0, 90, 45], values_urad: [1, 2, 3]}\n",
       2, "increasing"},
      {"effects:\n  - rotary_error_motion: {symbol: E_CC, positions_deg: [0, 90], values_urad: [1]}\n", 2,
       "one value per"},
  };
  for (const BadCase& c : cases) {
    Result<ErrorState> e = ParseErrorState(c.text, "e.yaml", ac);
    ASSERT_FALSE(e.ok()) << c.text;
    EXPECT_EQ(e.status().file(), "e.yaml");
    EXPECT_EQ(e.status().line(), c.line) << c.text << "\n" << e.status().ToString();
    EXPECT_THAT(e.status().message(), HasSubstr(c.substring)) << c.text;
  }
}

TEST(ErrorsYaml, EmptyFileIsNoErrors) {
  const MachineModel ac = Load("ac_table.yaml");
  Result<ErrorState> e = ParseErrorState("", "e.yaml", ac);
  ASSERT_TRUE(e.ok());
  EXPECT_TRUE(e->empty());
}

}  // namespace
}  // namespace tpcal::kinematics
