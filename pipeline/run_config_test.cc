#include "pipeline/run_config.h"

#include <gtest/gtest.h>

namespace tpcal::pipeline {
namespace {

TEST(PipelineOverrides, SetMembersReplaceTheFileAndTheRestStays) {
  auto file = ParsePipelineConfig("testpiece: cone_frustum\npoints: /d/a.csv\nseed: 3\nout: /d/out\n"
                                  "raw_scan: {anchor_feature: H1, anchor_near_mm: [1, 2, 3]}\n",
                                  "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  PipelineOverrides o;
  o.points = "/e/b.csv";
  o.seed = 5;
  o.monte_carlo_trials = 0;
  auto c = ApplyPipelineOverrides(*file, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->testpiece, "cone_frustum");
  EXPECT_EQ(c->points, "/e/b.csv");
  EXPECT_EQ(c->seed, 5u);
  EXPECT_EQ(c->monte_carlo_trials, 0);
  EXPECT_EQ(c->out, "/d/out");
  EXPECT_EQ(c->anchor_feature, "H1");
  o.anchor_feature = "H5";
  o.anchor_near_mm = Eigen::Vector3d(4, 5, 6);
  c = ApplyPipelineOverrides(*file, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->anchor_feature, "H5");
  ASSERT_TRUE(c->anchor_near_mm.has_value());
  EXPECT_EQ(c->anchor_near_mm->z(), 6.0);
}

TEST(PipelineOverrides, BatchNeedsNoPointsButEveryRunAnOutputDirectory) {
  PipelineOverrides o;
  o.out = "out";
  auto batch = ApplyPipelineOverrides(PipelineConfig{}, o, true);
  ASSERT_TRUE(batch.ok()) << batch.status().ToString();
  EXPECT_EQ(batch->points, "(batch)");
  auto single = ApplyPipelineOverrides(PipelineConfig{}, o, false);
  ASSERT_FALSE(single.ok());
  EXPECT_EQ(single.status().ToString(), "no point file given ('points' / --points)");
  o = PipelineOverrides{};
  o.points = "a.csv";
  auto no_out = ApplyPipelineOverrides(PipelineConfig{}, o, false);
  ASSERT_FALSE(no_out.ok());
  EXPECT_EQ(no_out.status().ToString(), "no output directory: give --out DIR (or 'out' in the pipeline file)");
}

TEST(PipelineOverrides, KeepOutliersFromTheFileOrTheFlagAndWrittenBack) {
  auto file = ParsePipelineConfig("points: a.csv\nout: o\nkeep_outliers: true\n", "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_TRUE(file->keep_outliers);
  EXPECT_NE(FormatPipelineConfig(*file).find("keep_outliers: true"), std::string::npos);
  auto plain = ParsePipelineConfig("points: a.csv\nout: o\n", "/d/p.yaml");
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE(plain->keep_outliers);
  PipelineOverrides o;
  o.keep_outliers = true;
  auto c = ApplyPipelineOverrides(*plain, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_TRUE(c->keep_outliers);
  auto bad = ParsePipelineConfig("points: a.csv\nkeep_outliers: maybe\n", "/d/p.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().ToString().find("/d/p.yaml:2"), std::string::npos) << bad.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
