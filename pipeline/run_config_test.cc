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

TEST(PipelineOverrides, ColumnMappingFromTheFileOrTheFlagsAndWrittenBack) {
  auto file = ParsePipelineConfig("points: a.csv\nout: o\ncolumns: {feature: Pt ID, x: PX}\n", "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_EQ(file->columns, (std::vector<std::pair<std::string, std::string>>{{"feature", "Pt ID"}, {"x", "PX"}}));
  EXPECT_NE(FormatPipelineConfig(*file).find("columns:\n  feature: Pt ID\n  x: PX\n"), std::string::npos)
      << FormatPipelineConfig(*file);
  auto plain = ParsePipelineConfig("points: a.csv\nout: o\n", "/d/p.yaml");
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(FormatPipelineConfig(*plain).find("columns"), std::string::npos);  // a run without one echoes as before
  PipelineOverrides o;
  o.columns = {"Feature=Name", "z=Z mm"};  // the flags replace the file's mapping; roles are case-insensitive
  auto c = ApplyPipelineOverrides(*file, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->columns, (std::vector<std::pair<std::string, std::string>>{{"feature", "Name"}, {"z", "Z mm"}}));
  o.columns = {"x=A", "x=B"};
  EXPECT_EQ(ApplyPipelineOverrides(*plain, o, false).status().message(), "--column: column role 'x' is mapped twice");
  o.columns = {"x"};
  EXPECT_EQ(ApplyPipelineOverrides(*plain, o, false).status().message(),
            "--column 'x': expected ROLE=NAME (e.g. feature=Name, x=X)");
  auto upper = ParsePipelineConfig("points: a.csv\nout: o\ncolumns: {Feature: Pt ID, X: PX}\n", "/d/p.yaml");
  ASSERT_TRUE(upper.ok()) << upper.status().ToString();  // roles in any case, as after --column
  EXPECT_EQ(upper->columns, file->columns);
  auto twice = ParsePipelineConfig("points: a.csv\nout: o\ncolumns: {x: A, X: B}\n", "/d/p.yaml");
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.status().message().find("column role 'x' is mapped twice"), std::string::npos) << twice.status().ToString();
  auto bad = ParsePipelineConfig("points: a.csv\nout: o\ncolumns:\n  w: PX\n", "/d/p.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().ToString(), "/d/p.yaml:4: 'columns': column role 'w': expected one of feature, x, y, z, i, j, k");
}

TEST(PipelineOverrides, ReferenceBlockFromTheFileOrTheFlagsAndWrittenBack) {
  auto file = ParsePipelineConfig("points: a.csv\nout: o\nreference:\n  instrument: datum_ball\n  file: ball.csv\n",
                                  "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_EQ(file->reference_instrument, "datum_ball");
  EXPECT_EQ(file->reference_file, "/d/ball.csv");
  EXPECT_NE(FormatPipelineConfig(*file).find("reference:\n  instrument: datum_ball\n  file: /d/ball.csv"),
            std::string::npos)
      << FormatPipelineConfig(*file);
  auto plain = ParsePipelineConfig("points: a.csv\nout: o\n", "/d/p.yaml");
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(FormatPipelineConfig(*plain).find("reference"), std::string::npos);
  PipelineOverrides o;
  o.reference_file = "e/ball.csv";
  auto half = ApplyPipelineOverrides(*plain, o, false);
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().ToString().find("instrument and file go together"), std::string::npos);
  o.reference_instrument = "datum_ball";
  auto c = ApplyPipelineOverrides(*plain, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->reference_file, "e/ball.csv");
}

TEST(PipelineOverrides, BadReferenceBlocksNameTheLine) {
  auto unknown = ParsePipelineConfig("points: a.csv\nreference:\n  instrument: laser\n  file: b.csv\n", "/d/p.yaml");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.status().ToString().find("/d/p.yaml:3"), std::string::npos) << unknown.status().ToString();
  EXPECT_NE(unknown.status().ToString().find("expected datum_ball"), std::string::npos);
  auto no_file = ParsePipelineConfig("points: a.csv\nreference:\n  instrument: datum_ball\n", "/d/p.yaml");
  ASSERT_FALSE(no_file.ok());
  EXPECT_NE(no_file.status().ToString().find("/d/p.yaml:3"), std::string::npos) << no_file.status().ToString();
  EXPECT_NE(no_file.status().ToString().find("missing key 'file'"), std::string::npos);
  auto extra = ParsePipelineConfig("points: a.csv\nreference: {file: b.csv, tilt: 3}\n", "/d/p.yaml");
  ASSERT_FALSE(extra.ok());
  EXPECT_NE(extra.status().ToString().find("/d/p.yaml:2"), std::string::npos) << extra.status().ToString();
  auto not_map = ParsePipelineConfig("points: a.csv\nreference: b.csv\n", "/d/p.yaml");
  ASSERT_FALSE(not_map.ok());
  EXPECT_NE(not_map.status().ToString().find("/d/p.yaml:2"), std::string::npos) << not_map.status().ToString();
}

// The set-up of a map instrument: relative to the file, written back, replaced by the flag;
// required by ballbar, refused for datum_ball.
TEST(PipelineOverrides, ReferenceSetupOfTheMapInstruments) {
  auto file = ParsePipelineConfig(
      "points: a.csv\nout: o\nreference: {instrument: ballbar, file: bb.csv, setup: s.yaml}\n", "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  EXPECT_EQ(file->reference_setup, "/d/s.yaml");
  EXPECT_TRUE(file->Validate().ok());
  EXPECT_NE(FormatPipelineConfig(*file).find("reference:\n  instrument: ballbar\n  file: /d/bb.csv\n  setup: /d/s.yaml"),
            std::string::npos)
      << FormatPipelineConfig(*file);
  PipelineOverrides o;
  o.reference_setup = "e/s2.yaml";
  auto c = ApplyPipelineOverrides(*file, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->reference_setup, "e/s2.yaml");
  auto no_setup = ParsePipelineConfig("points: a.csv\nreference: {instrument: ballbar, file: bb.csv}\n", "/d/p.yaml");
  ASSERT_TRUE(no_setup.ok());
  EXPECT_NE(no_setup->Validate().ToString().find("/d/p.yaml: 'reference': instrument ballbar needs its set-up"),
            std::string::npos)
      << no_setup->Validate().ToString();
  auto ball = ParsePipelineConfig("points: a.csv\nreference: {file: b.csv, setup: s.yaml}\n", "/d/p.yaml");
  ASSERT_TRUE(ball.ok());
  EXPECT_NE(ball->Validate().ToString().find("setup is for probe_artifacts"), std::string::npos);
  auto probe = ParsePipelineConfig("points: a.csv\nreference: {instrument: probe_artifacts, file: p.csv}\n", "/d/p.yaml");
  ASSERT_TRUE(probe.ok());
  EXPECT_TRUE(probe->Validate().ok()) << probe->Validate().ToString();
}

// A probing test's stylus radius: read, written back, replaced by the flag; > 0 mm at its line;
// refused for another instrument.
TEST(PipelineOverrides, ReferenceProbeRadiusOfAProbingTest) {
  auto file = ParsePipelineConfig(
      "points: a.csv\nout: o\nreference: {instrument: probe_artifacts, file: p.csv, probe_radius_mm: 1.5}\n", "/d/p.yaml");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  ASSERT_TRUE(file->reference_probe_radius_mm.has_value());
  EXPECT_EQ(*file->reference_probe_radius_mm, 1.5);
  EXPECT_TRUE(file->Validate().ok()) << file->Validate().ToString();
  EXPECT_NE(FormatPipelineConfig(*file).find("file: /d/p.csv\n  probe_radius_mm: 1.5\n"), std::string::npos)
      << FormatPipelineConfig(*file);
  PipelineOverrides o;
  o.reference_probe_radius_mm = 2.5;
  auto c = ApplyPipelineOverrides(*file, o, false);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->reference_probe_radius_mm.value_or(0.0), 2.5);
  for (const char* bad : {"0", "-1", ".nan", "three"}) {
    auto r = ParsePipelineConfig(std::string("points: a.csv\nreference:\n  instrument: probe_artifacts\n  file: p.csv\n"
                                             "  probe_radius_mm: ") + bad + "\n",
                                 "/d/p.yaml");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.status().ToString().find("/d/p.yaml:5: 'reference.probe_radius_mm': expected a stylus radius in mm > 0"),
              std::string::npos)
        << r.status().ToString();
  }
  auto ball = ParsePipelineConfig("points: a.csv\nreference: {file: b.csv, probe_radius_mm: 3}\n", "/d/p.yaml");
  ASSERT_TRUE(ball.ok());
  EXPECT_NE(ball->Validate().ToString().find("probe_radius_mm is for probe_artifacts"), std::string::npos);
  auto plain = ParsePipelineConfig("points: a.csv\n", "/d/p.yaml");
  ASSERT_TRUE(plain.ok());
  PipelineOverrides radius_alone;
  radius_alone.reference_probe_radius_mm = 2.0;
  auto alone = ApplyPipelineOverrides(*plain, radius_alone, false);
  ASSERT_FALSE(alone.ok());
  EXPECT_NE(alone.status().ToString().find("needs a probe_artifacts reference"), std::string::npos)
      << alone.status().ToString();
  o.reference_probe_radius_mm = -1.0;
  auto negative = ApplyPipelineOverrides(*file, o, false);
  ASSERT_FALSE(negative.ok());
  EXPECT_NE(negative.status().ToString().find("expected a stylus radius in mm > 0"), std::string::npos)
      << negative.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
