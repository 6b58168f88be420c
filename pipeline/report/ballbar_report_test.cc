// The ball-bar report (pipeline/report/ballbar_report.h): JSON and text of an identification of
// seed 003's seven C installations (kinematics/ballbar_identification.h; zero errors, 0.5 um
// Gaussian noise, seed 21) and of a circular test given field by field. Truth: the report writes
// the result's own numbers, so the JSON compares exactly; the text holds one row per angle.
#include "pipeline/report/ballbar_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "core/portable_random.h"
#include "kinematics/ballbar.h"
#include "kinematics/machine_yaml.h"

namespace tpcal::pipeline {
namespace {

const BallbarReport& BbrReport() {
  static const BallbarReport report = [] {
    auto m = kinematics::MakeMachine(kinematics::MachineType::kBheadCtable);
    EXPECT_TRUE(m.ok());
    auto setup = kinematics::LoadBallbarSetup(std::string(TPCAL_SOURCE_DIR) + "/samples/ballbar/seed003_setups.yaml");
    EXPECT_TRUE(setup.ok()) << setup.status().ToString();
    std::vector<kinematics::BallbarGeometry> gs;
    std::vector<std::string> names;
    for (const auto& i : setup->installations) {
      if (i.kind == kinematics::BallbarKind::kCircle || i.axis != kinematics::Axis::kC) continue;
      gs.push_back(*kinematics::MakeBallbarGeometry(*m, i));
      names.push_back(i.name);
    }
    std::mt19937_64 rng(21);
    std::vector<kinematics::BallbarReading> readings;
    std::vector<std::size_t> lines;
    for (int j = 0; j < static_cast<int>(gs.size()); ++j)
      for (double a = 0.0; a <= 340.0; a += 20.0) {
        readings.push_back({j, a, 0.5 * StandardNormal(rng), 0.0, static_cast<int>(lines.size()) + 4});
        lines.push_back(lines.size() + 4);
      }
    auto r = kinematics::IdentifyBallbar(*m, gs, readings);
    EXPECT_TRUE(r.ok()) << r.status().ToString();
    BallbarReport out;
    out.source = "bb.csv";
    out.setup_source = "setup.yaml";
    out.machine = "bhead_ctable";
    out.readings = static_cast<int>(readings.size());
    BallbarAxisReport axis(std::move(*r));
    axis.axis = "C";
    axis.installations = names;
    axis.lines = lines;
    out.axes.push_back(std::move(axis));
    BallbarCircleReport circle;
    circle.installation = "XY_R150";
    circle.lines = {4, 5};
    circle.result.plane = "XY";
    circle.result.radius_mm = 150.0;
    circle.result.rows = 2;
    circle.result.residuals_um = {0.1, -0.1};
    kinematics::CircularFigure g;
    g.name = "circular_deviation";
    g.symbol = "G";
    g.unit = "um";
    g.value = 12.5;
    g.u = 0.4;
    kinematics::CircularFigure h;
    h.name = "circular_hysteresis";
    h.symbol = "H";
    h.unit = "um";
    h.identifiable = false;
    h.note = "needs both directions";
    circle.result.figures = {g, h};
    out.circles.push_back(circle);
    return out;
  }();
  return report;
}

TEST(BallbarReport, JsonHoldsTheAxisEntriesSetupTermsAndFit) {
  const BallbarReport& report = BbrReport();
  const auto& r = report.axes[0].result;
  const auto j = nlohmann::json::parse(BallbarJson(report));
  EXPECT_EQ(j["schema"], "tpcal.identification/1");
  EXPECT_EQ(j["instrument"], "ballbar");
  EXPECT_EQ(j["source"], "bb.csv");
  EXPECT_EQ(j["setup_source"], "setup.yaml");
  EXPECT_EQ(j["readings"], 126);
  ASSERT_EQ(j["axes"].size(), 1u);
  const auto& a = j["axes"][0];
  EXPECT_EQ(a["axis"], "C");
  EXPECT_EQ(a["installations"].size(), 7u);
  EXPECT_EQ(a["fit"]["readings"], r.rows);
  EXPECT_EQ(a["fit"]["rank"], r.rank);
  EXPECT_EQ(a["fit"]["dof"], r.dof);
  EXPECT_EQ(a["fit"]["sigma_um"], r.sigma_um);
  EXPECT_EQ(a["angles_deg"].size(), 18u);
  ASSERT_EQ(a["errors"].size(), r.entries.size());
  for (std::size_t e = 0; e < r.entries.size(); ++e) {
    const auto& je = a["errors"][e];
    const auto& x = r.entries[e];
    EXPECT_EQ(je["coefficient"], x.coefficient);
    EXPECT_EQ(je["angle_deg"], x.angle_deg);
    EXPECT_EQ(je["identifiable"], x.identifiable);
    EXPECT_EQ(je["convention_dependent"], x.convention_dependent);
    if (x.identifiable) {
      EXPECT_EQ(je["value"], x.value);
      EXPECT_EQ(je["u"], x.u);
      EXPECT_EQ(je["ci95"][0], x.ci95_low);
    } else {
      EXPECT_TRUE(je["value"].is_null());
      EXPECT_TRUE(je["ci95"].is_null());
    }
  }
  ASSERT_EQ(a["setup_terms"].size(), r.setup_terms.size());
  EXPECT_EQ(a["setup_terms"][0]["installation"], report.axes[0].installations[0]);
  EXPECT_EQ(a["not_separable"].size(), r.not_separable.size());
  EXPECT_EQ(a["residuals"].size(), 126u);
  EXPECT_EQ(a["residuals"][0]["line"], 4);
  EXPECT_EQ(a["residuals"][0]["residual_um"], r.residuals_um[0]);
}

// Truth: a map response (here a made-up 2-column matrix, entry k's row (k, -k)) is written as the
// axis's "response_to" and each entry's "response", exactly; without one neither key is written.
TEST(BallbarReport, JsonWritesTheMapResponsePerEntry) {
  EXPECT_FALSE(nlohmann::json::parse(BallbarJson(BbrReport()))["axes"][0].contains("response_to"));
  BallbarReport report = BbrReport();
  BallbarAxisReport& axis = report.axes[0];
  axis.response_to = {"E_C(0X)Y", "E_B(0X)Z"};
  const auto n = static_cast<Eigen::Index>(axis.result.entries.size());
  axis.map_response.resize(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) axis.map_response.row(k) << static_cast<double>(k), -static_cast<double>(k);
  const auto a = nlohmann::json::parse(BallbarJson(report))["axes"][0];
  EXPECT_EQ(a["response_to"], (std::vector<std::string>{"E_C(0X)Y", "E_B(0X)Z"}));
  ASSERT_EQ(a["errors"].size(), static_cast<std::size_t>(n));
  EXPECT_EQ(a["errors"][5]["response"], (std::vector<double>{5.0, -5.0}));
  EXPECT_EQ(a["errors"][0]["response"], (std::vector<double>{0.0, 0.0}));
}

TEST(BallbarReport, JsonGivesCircleFiguresAndNullWithoutANumber) {
  const auto j = nlohmann::json::parse(BallbarJson(BbrReport()));
  ASSERT_EQ(j["circles"].size(), 1u);
  const auto& c = j["circles"][0];
  EXPECT_EQ(c["installation"], "XY_R150");
  EXPECT_EQ(c["plane"], "XY");
  EXPECT_EQ(c["radius_mm"], 150.0);
  ASSERT_EQ(c["figures"].size(), 2u);
  EXPECT_EQ(c["figures"][0]["value"], 12.5);
  EXPECT_EQ(c["figures"][0]["u"], 0.4);
  EXPECT_TRUE(c["figures"][1]["value"].is_null());
  EXPECT_EQ(c["figures"][1]["note"], "needs both directions");
  EXPECT_TRUE(c["fit"]["sigma_um"].is_null());
}

TEST(BallbarReport, TextHasOneRowPerAngleAndNamesTheFamilies) {
  const BallbarReport& report = BbrReport();
  const std::string t = BallbarText(report);
  EXPECT_NE(t.find("126 readings from bb.csv"), std::string::npos);
  for (const std::string& f : report.axes[0].result.not_separable) EXPECT_NE(t.find(f), std::string::npos) << f;
  std::istringstream lines(t);
  int rows = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream ls(line);
    double angle = 0.0;
    std::string first_value;
    if (ls >> angle >> first_value && line.find("+-") != std::string::npos && line.rfind("  ", 0) == 0 &&
        line.find("offset") == std::string::npos && line.find("centring") == std::string::npos)
      ++rows;
  }
  EXPECT_EQ(rows, 18);
  EXPECT_NE(t.find("circular_deviation (G)"), std::string::npos);
  EXPECT_NE(t.find("12.500 +- 0.400"), std::string::npos);
  EXPECT_NE(t.find("needs both directions"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
