// The probed-point file (`tpcal probepts v1`): the contract's example reads as written, columns in
// any order, Format -> Parse is exact, and every error of the header names its line.
#include "pipeline/io/probepts_io.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace tpcal::pipeline {
namespace {

using ::testing::HasSubstr;

// Numbers written by FormatProbePoints read back bit for bit (shortest round-trip text), so the
// round trip compares with EXPECT_EQ: tolerance 0.
void ExpectSameProbeRows(const ProbePointFile& a, const ProbePointFile& b) {
  EXPECT_EQ(a.rotary_axes, b.rotary_axes);
  EXPECT_EQ(a.has_t, b.has_t);
  EXPECT_EQ(a.has_u, b.has_u);
  EXPECT_EQ(a.is_plan, b.is_plan);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t r = 0; r < a.rows.size(); ++r) {
    SCOPED_TRACE("row " + std::to_string(r));
    EXPECT_EQ(a.rows[r].rotary_deg, b.rows[r].rotary_deg);
    EXPECT_EQ(a.rows[r].artifact, b.rows[r].artifact);
    EXPECT_EQ(a.rows[r].face, b.rows[r].face);
    EXPECT_EQ(a.rows[r].point_mm, b.rows[r].point_mm);
    EXPECT_EQ(a.rows[r].approach, b.rows[r].approach);
    EXPECT_EQ(a.rows[r].t_s, b.rows[r].t_s);
    EXPECT_EQ(a.rows[r].u_um, b.rows[r].u_um);
  }
}

TEST(ProbePointsIo, ContractExampleReadsAsWritten) {
  const std::string text =
      "# tpcal probepts v1\n"
      "# units: mm\n"
      "A_deg,C_deg,artifact,face,x,y,z,i,j,k\n"
      "0,0,1,+X,150.0031,20.0000,30.0000,-1,0,0\n"
      "-90,45,3,+Z,0.5,100,60.0004,0,0,-1\n";
  auto r = ParseProbePoints(text, "p.csv");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->source, "p.csv");
  EXPECT_EQ(r->rotary_axes, (std::vector<char>{'A', 'C'}));
  EXPECT_FALSE(r->has_t);
  EXPECT_FALSE(r->has_u);
  EXPECT_FALSE(r->is_plan);
  ASSERT_EQ(r->rows.size(), 2u);
  const ProbePointRow& p = r->rows[0];
  EXPECT_EQ(p.line, 4u);
  EXPECT_EQ(p.rotary_deg, (std::map<char, double>{{'A', 0.0}, {'C', 0.0}}));
  EXPECT_EQ(p.artifact, "1");
  EXPECT_EQ(p.face, "+X");
  EXPECT_EQ(p.point_mm, Eigen::Vector3d(150.0031, 20.0, 30.0));  // decimal text -> nearest double
  EXPECT_EQ(p.approach, Eigen::Vector3d(-1, 0, 0));
  EXPECT_EQ(p.t_s, 0.0);
  EXPECT_EQ(p.u_um, 0.0);
  EXPECT_EQ(r->rows[1].line, 5u);
  EXPECT_EQ(r->rows[1].rotary_deg.at('A'), -90.0);
  EXPECT_EQ(r->rows[1].face, "+Z");
}

TEST(ProbePointsIo, ColumnsInAnyOrderOptionalColumnsAndPlanComment) {
  const std::string text =
      "# tpcal probepts v1\r\n"
      "# units: mm\n"
      "# plan: nominal contact points\n"
      "# another comment\n"
      "\n"
      "face, k, u_um, x, B_deg, y, z, artifact, j, i, C_deg, t_s\n"
      "-Y, 0, 0.8, 1, 30, 2, 3, box A, 1, 0, 90, 12.5\n";
  auto r = ParseProbePoints(text, "p.csv");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_TRUE(r->is_plan);
  EXPECT_TRUE(r->has_t);
  EXPECT_TRUE(r->has_u);
  EXPECT_EQ(r->rotary_axes, (std::vector<char>{'B', 'C'}));
  ASSERT_EQ(r->rows.size(), 1u);
  const ProbePointRow& p = r->rows[0];
  EXPECT_EQ(p.line, 7u);
  EXPECT_EQ(p.artifact, "box A");  // fields are trimmed, inner blanks kept
  EXPECT_EQ(p.face, "-Y");
  EXPECT_EQ(p.rotary_deg, (std::map<char, double>{{'B', 30.0}, {'C', 90.0}}));
  EXPECT_EQ(p.point_mm, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(p.approach, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(p.t_s, 12.5);
  EXPECT_EQ(p.u_um, 0.8);
}

TEST(ProbePointsIo, FormatThenParseIsExact) {
  ProbePointFile f;
  f.rotary_axes = {'A', 'C'};
  f.has_t = true;
  f.has_u = true;
  f.is_plan = true;
  const Eigen::Vector3d tilted = Eigen::Vector3d(1.0, -2.0, 3.0).normalized();  // not exactly 1
  const double values[] = {150.0031, 1.0 / 3.0, -1e-300, 123456789.123456789, 0.1 + 0.2};
  for (int n = 0; n < 5; ++n) {
    ProbePointRow r;
    r.rotary_deg = {{'A', -90.0 + 17.3 * n}, {'C', std::nextafter(45.0, 90.0) * n}};
    r.artifact = std::to_string(n + 1);
    r.face = n % 2 ? "+Z" : "-X";
    r.point_mm = Eigen::Vector3d(values[n], -values[(n + 1) % 5], values[(n + 2) % 5]);
    r.approach = n % 2 ? Eigen::Vector3d(0, 0, -1) : tilted;
    r.t_s = 0.25 * n + 1e-9;
    r.u_um = n * 0.7;
    f.rows.push_back(r);
  }
  const std::string text = FormatProbePoints(f);
  EXPECT_EQ(text.rfind("# tpcal probepts v1\n# units: mm\n# plan: nominal contact points\n"
                       "A_deg,C_deg,artifact,face,x,y,z,i,j,k,t_s,u_um\n",
                       0),
            0u)
      << text;
  EXPECT_THAT(text, HasSubstr(",150.0031,"));  // shortest text, not 150.00309999999999
  auto back = ParseProbePoints(text, "f.csv");
  ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << text;
  ExpectSameProbeRows(f, *back);
  EXPECT_EQ(back->rows[0].line, 5u);

  // Without the optional columns and the plan line: the same columns come back, no more.
  f.has_t = f.has_u = f.is_plan = false;
  for (ProbePointRow& r : f.rows) r.t_s = r.u_um = 0.0;
  auto plain = ParseProbePoints(FormatProbePoints(f), "f.csv");
  ASSERT_TRUE(plain.ok()) << plain.status().ToString();
  ExpectSameProbeRows(f, *plain);
}

TEST(ProbePointsIo, EveryErrorNamesItsLine) {
  const std::string head = "# tpcal probepts v1\n# units: mm\n";
  const std::string cols = "A_deg,C_deg,artifact,face,x,y,z,i,j,k\n";
  struct Case {
    const char* what;
    std::string text;
    std::size_t line;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"empty file", "", 1, "empty file"},
      {"wrong first line", "# tpcal ballpos v1\n# units: mm\n" + cols + "0,0,1,+X,1,2,3,-1,0,0\n", 1,
       "# tpcal probepts v1"},
      {"units in", "# tpcal probepts v1\n# units: in\n" + cols + "0,0,1,+X,1,2,3,-1,0,0\n", 2, "only mm"},
      {"no k", head + "A_deg,C_deg,artifact,face,x,y,z,i,j\n0,0,1,+X,1,2,3,-1,0\n", 3, "header needs"},
      {"no artifact", head + "C_deg,face,x,y,z,i,j,k\n0,+X,1,2,3,-1,0,0\n", 3, "header needs"},
      {"no rotary", head + "artifact,face,x,y,z,i,j,k\n1,+X,1,2,3,-1,0,0\n", 3, "at least one of A_deg"},
      {"unknown column", head + "A_deg,artifact,face,x,y,z,i,j,k,ball\n", 3, "unknown column 'ball'"},
      {"repeated column", head + "A_deg,artifact,face,x,y,z,i,j,k,x\n", 3, "column 'x' repeated"},
      {"short row", head + cols + "0,0,1,+X,1,2,3,-1,0,0\n0,0,1,+X,1,2,3,-1,0\n", 5, "expected 10 fields, got 9"},
      {"long row", head + cols + "0,0,1,+X,1,2,3,-1,0,0,7\n", 4, "expected 10 fields, got 11"},
      {"empty artifact", head + cols + "0,0, ,+X,1,2,3,-1,0,0\n", 4, "empty artifact"},
      {"empty face", head + cols + "0,0,1,,1,2,3,-1,0,0\n", 4, "empty face"},
      {"not a number", head + cols + "0,0,1,+X,1,2,3mm,-1,0,0\n", 4, "field 7: expected a finite number, got '3mm'"},
      {"nan", head + cols + "0,nan,1,+X,1,2,3,-1,0,0\n", 4, "field 2: expected a finite number"},
      {"overflow", head + cols + "0,0,1,+X,1e999,2,3,-1,0,0\n", 4, "field 5: expected a finite number"},
      {"approach long", head + cols + "0,0,1,+X,1,2,3,-1,0.01,0\n", 4, "expected a unit vector"},
      {"approach zero", head + cols + "0,0,1,+X,1,2,3,0,0,0\n", 4, "has length 0"},
      {"u negative", head + "A_deg,artifact,face,x,y,z,i,j,k,u_um\n0,1,+X,1,2,3,-1,0,0,-0.5\n", 4, "u_um -0.5"},
      {"no rows", head + cols + "# only a comment\n", 4, "no probed points"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    auto r = ParseProbePoints(c.text, "bad.csv");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.status().code(), StatusCode::kParseError);
    EXPECT_EQ(r.status().file(), "bad.csv");
    EXPECT_EQ(r.status().line(), c.line) << r.status().ToString();
    EXPECT_THAT(r.status().message(), HasSubstr(c.expect));
  }
}

TEST(ProbePointsIo, ApproachUnitToOneMicro) {
  // 1e-6 is the header's tolerance on |(i, j, k)| - 1; 4 decimals of a 45 deg direction pass.
  const std::string head = "# tpcal probepts v1\nC_deg,artifact,face,x,y,z,i,j,k\n";
  EXPECT_TRUE(ParseProbePoints(head + "0,1,+X,1,2,3,-1.0000009,0,0\n", "a.csv").ok());
  EXPECT_TRUE(ParseProbePoints(head + "0,1,+X,1,2,3,0.70710678,0.70710678,0\n", "a.csv").ok());
  EXPECT_FALSE(ParseProbePoints(head + "0,1,+X,1,2,3,-1.0000011,0,0\n", "a.csv").ok());
  EXPECT_FALSE(ParseProbePoints(head + "0,1,+X,1,2,3,0.7071,0.7071,0\n", "a.csv").ok());
}

TEST(ProbePointsIo, ReadNamesTheMissingFile) {
  auto r = ReadProbePoints("/nonexistent/probe.csv");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kIoError);
  EXPECT_THAT(r.status().ToString(), HasSubstr("/nonexistent/probe.csv"));
}

}  // namespace
}  // namespace tpcal::pipeline
