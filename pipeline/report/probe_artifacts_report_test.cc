// The JSON, text and HTML of a probe-artifact identification (probe_artifacts_report.h), from a
// real identification (kinematics::IdentifyProbeArtifacts) of simulated touches: seed 000's three
// columns on the A/C table, one touch at the centre of every face not facing down, A at 0, -30,
// -60, -90 deg and C every 60 deg (24 positions), each contact where the nominal approach line
// meets the face plane moved by the table's actual pose under E_X0C = 10 um, plus 0.5 um of
// Gaussian noise (fixed seed) so that every u is non-zero. The writers must carry the result's
// numbers unchanged (compared exactly after the JSON round trip: nlohmann writes shortest
// round-trip doubles) and name what the touches cannot determine.
#include "pipeline/report/probe_artifacts_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/portable_random.h"
#include "core/xml_escape.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::pipeline {
namespace {

using kinematics::BoxFace;
using kinematics::ProbeTouch;

constexpr double kParRadPerDeg = 3.14159265358979323846 / 180.0;
constexpr double kParNoiseUm = 0.5;
// The position whose touches the not-identifiable case removes.
constexpr double kParDroppedA = -30.0, kParDroppedC = 60.0;

kinematics::MachineModel ParMachine() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

kinematics::AxisState ParRotary(double a_deg, double c_deg) {
  kinematics::AxisState s;
  s.a_rad = a_deg * kParRadPerDeg;
  s.c_rad = c_deg * kParRadPerDeg;
  return s;
}

// The touches of the grid under `truth`, with their source lines; `drop` leaves out the touches
// at (kParDroppedA, kParDroppedC).
std::vector<ProbeTouch> ParTouches(const kinematics::MachineModel& m, const kinematics::ErrorState& truth, bool drop) {
  const kinematics::ArtifactSet set = kinematics::Seed000Artifacts();
  std::mt19937_64 rng(7);
  std::vector<ProbeTouch> out;
  kinematics::Workspace ws;
  for (double a : {0.0, -30.0, -60.0, -90.0}) {
    for (double c = 0.0; c < 360.0; c += 60.0) {
      if (drop && a == kParDroppedA && c == kParDroppedC) continue;
      const kinematics::AxisState s = ParRotary(a, c);
      const Rigid3 actual = kinematics::MachineFromPart(m, truth, s, &ws);
      for (int b = 0; b < 3; ++b) {
        for (BoxFace f : kinematics::kBoxFaces) {
          const kinematics::FaceGeometry g = kinematics::FaceOf(set.boxes[static_cast<std::size_t>(b)], f);
          const Eigen::Vector3d d = kinematics::NominalApproach(m, s, g);
          if (-d.z() < -0.1) continue;  // faces down
          const Eigen::Vector3d p0 = kinematics::NominalMachineFromTable(m, s) * g.centre_mm;
          const Eigen::Vector3d na = actual.linear() * g.normal, q = actual * g.centre_mm;
          const double t = na.dot(q - p0) / na.dot(d);  // the line p0 + t d meets the moved plane
          ProbeTouch touch;
          touch.rotary = s;
          touch.artifact = b;
          touch.face = f;
          touch.approach = d;
          touch.contact_mm = p0 + (t + 1e-3 * kParNoiseUm * StandardNormal(rng)) * d;
          touch.line = out.size() + 2;
          out.push_back(touch);
        }
      }
    }
  }
  return out;
}

ProbeArtifactsReport ParReport(bool drop) {
  const kinematics::MachineModel m = ParMachine();
  kinematics::ErrorState truth(m);
  EXPECT_TRUE(truth.SetParameter(m, "E_X0C", 0.010).ok());
  const auto touches = ParTouches(m, truth, drop);
  auto r = kinematics::IdentifyProbeArtifacts(m, kinematics::Seed000Artifacts(), touches);
  EXPECT_TRUE(r.ok()) << r.status().message();
  ProbeArtifactsReport report(*r);
  report.source = "touches<1>.txt";  // escaped in the HTML
  report.machine = "ac_table";
  report.artifacts = kinematics::Seed000Artifacts();
  for (const ProbeTouch& t : touches) report.lines.push_back(t.line);
  return report;
}

const ProbeArtifactsReport& ParFull() {
  static const ProbeArtifactsReport r = ParReport(false);
  return r;
}

const ProbeArtifactsReport& ParDropped() {
  static const ProbeArtifactsReport r = ParReport(true);
  return r;
}

std::size_t ParCount(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// The whitespace-separated tokens of the text line that follows the block header starting with
// "\n<symbol> (" and begins (after spaces) with `row_start`; empty when not found.
std::vector<std::string> ParMapRow(const std::string& text, const std::string& symbol, const std::string& row_start) {
  auto at = text.find("\n" + symbol + " (");
  if (at == std::string::npos) return {};
  const auto end = text.find("\n\n", at + 1);
  std::istringstream block(text.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1));
  std::string line;
  while (std::getline(block, line)) {
    std::istringstream ls(line);
    std::vector<std::string> tokens;
    for (std::string t; ls >> t;) tokens.push_back(t);
    if (!tokens.empty() && tokens.front() == row_start) return tokens;
  }
  return {};
}

TEST(ProbeArtifactsReport, JsonHoldsPosesMapsAndFitAsIdentified) {
  const ProbeArtifactsReport& report = ParFull();
  const auto& r = report.result;
  const auto j = nlohmann::json::parse(ProbeArtifactsJson(report));
  EXPECT_EQ(j["schema"], "tpcal.identification/1");
  EXPECT_EQ(j["instrument"], "probe_artifacts");
  EXPECT_EQ(j["source"], "touches<1>.txt");
  EXPECT_EQ(j["artifacts_source"], "");
  EXPECT_EQ(j["machine"], "ac_table");
  ASSERT_EQ(j["artifacts"].size(), 3u);
  EXPECT_EQ(j["artifacts"][0]["name"], "1");
  EXPECT_EQ(j["artifacts"][0]["base_centre_mm"][0], 100.0);
  EXPECT_EQ(j["artifacts"][0]["size_mm"][2], 60.0);
  EXPECT_EQ(j["fit"]["touches"], r.poses.num_touches);
  EXPECT_EQ(j["fit"]["rank"], r.poses.rank);
  EXPECT_EQ(j["fit"]["dof"], r.poses.dof);
  EXPECT_EQ(j["fit"]["sigma_um"], r.poses.sigma_um);
  EXPECT_EQ(j["fit"]["weighted"], false);
  EXPECT_TRUE(j["fit"]["chi_scale"].is_null());
  EXPECT_EQ(j["reference"]["a_deg"], 0.0);
  EXPECT_EQ(j["reference"]["c_deg"], 0.0);
  EXPECT_EQ(j["conventions"].size(), r.maps.conventions.size());
  EXPECT_TRUE(j["not_identifiable"].empty());
  EXPECT_EQ(j["residuals"].size(), static_cast<std::size_t>(r.poses.num_touches));
  EXPECT_EQ(j["residuals"][0]["line"], 2);

  ASSERT_EQ(j["poses"].size(), 24u);
  for (std::size_t p = 0; p < 24; ++p) {
    const auto& jp = j["poses"][p];
    const auto& pose = r.poses.poses[p];
    EXPECT_EQ(jp["a_deg"], pose.a_deg);
    EXPECT_EQ(jp["touches"], pose.touches);
    EXPECT_EQ(jp["reference"], pose.reference);
    for (int c = 0; c < 6; ++c) {
      const auto& jc = jp[kinematics::kPoseComponents[c]];
      EXPECT_EQ(jc["unit"], kinematics::kPoseUnits[c]);
      EXPECT_EQ(jc["identifiable"], true);
      EXPECT_EQ(jc["value"], pose.value(c));
      // u is sqrt of the covariance diagonal, 6 components per pose in pose order.
      const Eigen::Index i = static_cast<Eigen::Index>(6 * p) + c;
      EXPECT_EQ(jc["u"], std::sqrt(r.poses.covariance(i, i)));
      if (!pose.reference) {
        EXPECT_GT(jc["u"].get<double>(), 0.0) << p << " " << c;
      }
    }
    // The pose's 6 x 6 covariance block, symmetric, its diagonal the u^2 above.
    const auto& cov = jp["covariance"];
    ASSERT_EQ(cov.size(), 6u);
    const Eigen::Index base = static_cast<Eigen::Index>(6 * p);
    for (int a = 0; a < 6; ++a) {
      ASSERT_EQ(cov[a].size(), 6u);
      for (int b = 0; b < 6; ++b) {
        EXPECT_EQ(cov[a][b], r.poses.covariance(base + a, base + b)) << p << " " << a << " " << b;
        EXPECT_EQ(cov[a][b], cov[b][a]);
      }
    }
  }
  // The touched faces, artifact then face order.
  ASSERT_EQ(j["faces"].size(), r.poses.faces.size());
  EXPECT_EQ(j["faces"][0]["artifact"], "1");
  EXPECT_EQ(j["faces"][0]["face"], kinematics::BoxFaceName(r.poses.faces[0].face));

  // 6 A maps x 4 A + 6 C maps x 4 A x 6 C.
  ASSERT_EQ(j["maps"].size(), 168u);
  std::set<std::string> symbols;
  for (std::size_t e = 0; e < 168; ++e) {
    const auto& je = j["maps"][e];
    const auto& x = r.maps.entries[e];
    symbols.insert(je["symbol"].get<std::string>());
    EXPECT_EQ(je["coefficient"], x.coefficient);
    EXPECT_EQ(je["unit"], x.unit);
    EXPECT_EQ(je["a_deg"], x.a_deg);
    EXPECT_EQ(je.contains("c_deg"), x.c_map) << x.coefficient;
    EXPECT_EQ(je["identifiable"], true);
    EXPECT_EQ(je["value"], x.value);
    EXPECT_EQ(je["u"], x.u);
    EXPECT_EQ(je["ci95"][0], x.ci95_low);
    EXPECT_EQ(je["ci95"][1], x.ci95_high);
  }
  EXPECT_EQ(symbols.size(), 12u);
}

TEST(ProbeArtifactsReport, TextNamesEveryMapAndTheFitHeader) {
  const ProbeArtifactsReport& report = ParFull();
  const std::string t = ProbeArtifactsText(report);
  EXPECT_NE(t.find("touches<1>.txt"), std::string::npos);
  EXPECT_NE(t.find("ac_table"), std::string::npos);
  EXPECT_NE(t.find(fmt::format("{} touches", report.result.poses.num_touches)), std::string::npos);
  EXPECT_NE(t.find("sigma"), std::string::npos);
  for (const std::string& c : report.result.maps.conventions) EXPECT_NE(t.find(c), std::string::npos);
  for (const char* s : {"E_XA", "E_YA", "E_ZA", "E_AA", "E_BA", "E_CA", "E_XC", "E_YC", "E_ZC", "E_AC", "E_BC", "E_CC"})
    EXPECT_NE(t.find(std::string("\n") + s + " ("), std::string::npos) << s;
  // A C-axis map: one row per A with one value +- u per C (6 C positions: 18 tokens after A).
  const auto row = ParMapRow(t, "E_XC", "-60");
  ASSERT_EQ(row.size(), 1u + 6u * 3u);
  EXPECT_EQ(row[2], "+-");
  // An A-axis map: one row per A ("-60 value +- u").
  const auto a_row = ParMapRow(t, "E_XA", "-60");
  ASSERT_EQ(a_row.size(), 4u);
  EXPECT_EQ(a_row[2], "+-");
  EXPECT_NE(t.find("not identifiable: none"), std::string::npos);
}

// The stylus radius the touches were taken with is stated in the JSON's fit block and the text's
// header, whatever it is (not seed 000's 3 mm).
TEST(ProbeArtifactsReport, TheStylusRadiusIsStated) {
  ProbeArtifactsReport report = ParFull();
  report.probe_radius_mm = 2.5;
  EXPECT_EQ(nlohmann::json::parse(ProbeArtifactsJson(report))["fit"]["probe_radius_mm"], 2.5);
  EXPECT_NE(ProbeArtifactsText(report).find("; stylus radius 2.5 mm"), std::string::npos);
}

TEST(ProbeArtifactsReport, TextGivesEachPosesLargestCorrelation) {
  const ProbeArtifactsReport& report = ParFull();
  const auto& fit = report.result.poses;
  const std::string t = ProbeArtifactsText(report);
  const std::size_t at = t.find("largest correlation between two components of each pose");
  ASSERT_NE(at, std::string::npos);
  // Truth for the first non-reference pose: the largest |rho| over its 15 component pairs.
  std::size_t p = 0;
  while (fit.poses[p].reference) ++p;
  const Eigen::Index b = static_cast<Eigen::Index>(6 * p);
  double best = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int k = i + 1; k < 6; ++k) {
      const double rho = fit.covariance(b + i, b + k) / std::sqrt(fit.covariance(b + i, b + i) * fit.covariance(b + k, b + k));
      if (std::abs(rho) > std::abs(best)) best = rho;
    }
  std::istringstream lines(t.substr(at));
  std::string line;
  std::getline(lines, line);  // the section title
  std::getline(lines, line);  // the column heads
  int rows = 0;
  double first = 0.0;
  while (std::getline(lines, line) && !line.empty()) {
    std::istringstream ls(line);
    double a_deg = 0.0, c_deg = 0.0, rho = 0.0;
    ASSERT_TRUE(ls >> a_deg >> c_deg >> rho) << line;
    EXPECT_LE(std::abs(rho), 1.0);
    if (rows++ == 0) first = rho;
  }
  EXPECT_EQ(rows, 23);  // every pose but the reference
  EXPECT_NEAR(first, best, 5e-4);  // printed to 3 decimals
}

TEST(ProbeArtifactsReport, HtmlIsSelfContainedWithOneFigurePerMap) {
  const std::string h = ProbeArtifactsHtml(ParFull());
  EXPECT_EQ(h.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(ParCount(h, "<svg"), 12u);
  EXPECT_EQ(ParCount(h, "</svg>"), 12u);
  EXPECT_EQ(h.find("<script"), std::string::npos);
  EXPECT_EQ(h.find("src="), std::string::npos);
  EXPECT_EQ(h.find("href="), std::string::npos);
  EXPECT_EQ(h.find("touches<1>"), std::string::npos);
  EXPECT_NE(h.find("touches&lt;1&gt;.txt"), std::string::npos);
  // Units in the axis labels; a band per curve (C maps: one per A).
  EXPECT_NE(h.find("E_XA (um)"), std::string::npos);
  EXPECT_NE(h.find("E_AC (urad)"), std::string::npos);
  EXPECT_NE(h.find("C (deg)"), std::string::npos);
  EXPECT_EQ(ParCount(h, "<polygon"), 6u * 1u + 6u * 4u);
}

TEST(ProbeArtifactsReport, UnprobedPositionIsNamedAndGetsNoNumber) {
  const ProbeArtifactsReport& report = ParDropped();
  const auto& r = report.result;
  ASSERT_FALSE(r.maps.not_identifiable.empty());
  const auto j = nlohmann::json::parse(ProbeArtifactsJson(report));
  EXPECT_EQ(j["poses"].size(), 23u);
  EXPECT_EQ(j["maps"].size(), 168u);
  ASSERT_EQ(j["not_identifiable"].size(), r.maps.not_identifiable.size());
  std::size_t nulls = 0;
  for (const auto& e : j["maps"]) {
    if (e["identifiable"] == true) continue;
    ++nulls;
    EXPECT_TRUE(e["value"].is_null());
    EXPECT_TRUE(e["u"].is_null());
    EXPECT_TRUE(e["ci95"].is_null());
  }
  EXPECT_EQ(nulls, r.maps.not_identifiable.size());

  // The first entry without a number shows as "-" in its table row, and by name in the list.
  const kinematics::ErrorMapEntry* missing = nullptr;
  for (const auto& e : r.maps.entries)
    if (!e.identifiable && !missing) missing = &e;
  ASSERT_NE(missing, nullptr);
  const std::string t = ProbeArtifactsText(report);
  const auto row = ParMapRow(t, missing->symbol, fmt::format("{:g}", missing->a_deg));
  if (missing->c_map) {
    std::size_t col = 0;
    while (col < r.maps.c_deg.size() && std::abs(r.maps.c_deg[col] - missing->c_deg) > 1e-9) ++col;
    // Tokens: A, then per C either "v +- u" (3 tokens) or "-" (1 token).
    std::size_t k = 1;
    for (std::size_t c = 0; c < col && k < row.size(); ++c) k += row[k] == "-" ? 1 : 3;
    ASSERT_LT(k, row.size());
    EXPECT_EQ(row[k], "-");
  } else {
    ASSERT_EQ(row.size(), 2u);
    EXPECT_EQ(row[1], "-");
  }
  for (const std::string& name : r.maps.not_identifiable) EXPECT_NE(t.find("  " + name + "\n"), std::string::npos);
  EXPECT_NE(t.find("  position A -30 deg, C 60 deg: no touches\n"), std::string::npos);
  EXPECT_EQ(t.find("not identifiable: none"), std::string::npos);
  EXPECT_NE(ProbeArtifactsHtml(report).find(XmlEscape(r.maps.not_identifiable.front())), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
