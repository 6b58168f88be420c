#include "pipeline/plan_stage.h"

#include <gtest/gtest.h>

#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

TEST(PlanStage, TurningPlanHasTheAcTableColumnsAndTheLibraryRows) {
  auto loaded = LoadPiece({.testpiece = "turning"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  auto stage = RunPlanStage(*loaded, "plan.csv");
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  EXPECT_EQ(stage->csv.rfind("# tpcal plan v1\n# units: mm\nfeature,x,y,z,i,j,k,op,t_s,A_deg,C_deg,X_mm,Y_mm,Z_mm\n", 0), 0u)
      << stage->csv.substr(0, 200);
  auto plan = testpieces::MakeProbingPlan(loaded->piece);
  ASSERT_TRUE(plan.ok());
  const auto rows = testpieces::PlanRows(*plan);
  ASSERT_EQ(stage->points.size(), rows.size());
  const PointAttribute* a = stage->points.Attribute("A_deg");
  ASSERT_NE(a, nullptr);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(a->values[i], rows[i].a_deg) << i;
  EXPECT_EQ(stage->csv.find(",-0,"), std::string::npos);  // no negative zeros
}

TEST(PlanStage, ThreeAxisPlanHasNoRotaryColumns) {
  auto loaded = LoadPiece({.testpiece = "iso10791_m2"});
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  auto stage = RunPlanStage(*loaded, "plan.csv");
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  EXPECT_EQ(stage->points.Attribute("A_deg"), nullptr);
  EXPECT_EQ(stage->points.Attribute("C_deg"), nullptr);
  EXPECT_NE(stage->points.Attribute("X_mm"), nullptr);
  EXPECT_NE(stage->csv.find("feature,x,y,z,i,j,k,op,t_s,X_mm,Y_mm,Z_mm\n"), std::string::npos);
}

}  // namespace
}  // namespace tpcal::pipeline
