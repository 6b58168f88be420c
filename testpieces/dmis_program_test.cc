#include "testpieces/dmis_program.h"

#include <gtest/gtest.h>

#include <sstream>

#include "testpieces/named_pieces.h"

namespace tpcal::testpieces {
namespace {

int CountLinesStartingWith(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0 ? 1 : 0;
  return n;
}

// Every named piece: one F(<feature>_<k>) point, MEAS and OUTPUT per planned point, in plan
// order, after a datum alignment; nothing but DMIS statements and $$ comments.
TEST(DmisProgram, EveryPlannedPointIsMeasuredAndOutput) {
  for (const char* name : {"turning", "iso10791_m1_160", "iso10791_m2", "cone_frustum"}) {
    auto named = NamedPieceConfig(name);
    ASSERT_TRUE(named.ok());
    auto machine = kinematics::MakeMachine(UsualMachine(named->config));
    ASSERT_TRUE(machine.ok());
    auto piece = MakeTestPiece(named->config, *machine);
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    auto plan = MakeProbingPlan(*piece);
    ASSERT_TRUE(plan.ok());
    auto dmi = FormatDmisProgram(*piece, *plan);
    ASSERT_TRUE(dmi.ok()) << name << ": " << dmi.status().ToString();
    const int n = static_cast<int>(plan->points.size());
    EXPECT_EQ(CountLinesStartingWith(*dmi, "OUTPUT/FA("), n) << name;
    EXPECT_EQ(CountLinesStartingWith(*dmi, "MEAS/POINT,F(") - CountLinesStartingWith(*dmi, "MEAS/POINT,F(TPCAL_"), n)
        << name;
    EXPECT_EQ(CountLinesStartingWith(*dmi, "D(TPCAL_DATUM)=DATSET/DAT(A),ZDIR,ZORIG,"), 1) << name;
    EXPECT_EQ(CountLinesStartingWith(*dmi, "DMISMN/"), 1) << name;
    EXPECT_EQ(dmi->substr(dmi->size() - 7), "ENDFIL\n") << name;
    // The first and last planned points, by label, at their nominal coordinates.
    const PlanPoint& first = plan->points.front();
    EXPECT_NE(dmi->find("F(" + DmisPointLabel(first.feature, 1) + ")=FEAT/POINT,CART,"), std::string::npos) << name;
    int last_k = 0;
    for (const PlanPoint& p : plan->points) last_k += p.feature == plan->points.back().feature ? 1 : 0;
    EXPECT_NE(dmi->find("OUTPUT/FA(" + DmisPointLabel(plan->points.back().feature, last_k) + ")\nENDFIL"),
              std::string::npos)
        << name;
    std::istringstream in(*dmi);
    for (std::string line; std::getline(in, line);) {
      ASSERT_FALSE(line.empty()) << name;
      const bool ok = line.rfind("$$", 0) == 0 || line.find('/') != std::string::npos || line == "ENDMES" || line == "ENDFIL";
      EXPECT_TRUE(ok) << name << ": " << line;
    }
  }
}

TEST(DmisProgram, OptionsAreChecked) {
  auto named = NamedPieceConfig("turning");
  ASSERT_TRUE(named.ok());
  auto machine = kinematics::MakeMachine(UsualMachine(named->config));
  ASSERT_TRUE(machine.ok());
  auto piece = MakeTestPiece(named->config, *machine);
  ASSERT_TRUE(piece.ok());
  auto plan = MakeProbingPlan(*piece);
  ASSERT_TRUE(plan.ok());
  DmisProgramOptions bad;
  bad.approach_mm = 0;
  auto r = FormatDmisProgram(*piece, *plan, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(DmisPointLabel("S_R", 12), "S_R_12");
}

}  // namespace
}  // namespace tpcal::testpieces
