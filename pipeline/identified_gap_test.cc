#include "pipeline/identified_gap.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

#include "pipeline/io/point_io.h"
#include "pipeline/report/diagnosis_json.h"
#include "pipeline/testing/turning_fixture.h"

namespace tpcal::pipeline {
namespace {

using test_support::AcTable;
using test_support::Turning;

// A validation trial's piece (tests/data/points/straightness_patches_on_b_r.csv: 0.5 um noise, a
// straightness E_ZY withheld) whose straightness the outlier screen, with no effect in the model,
// flags as two patches on B_R on both sides of the model (lines 30-31 and 34-37). Truth: the
// straightness. `tpcal diagnose` names it (the screen with the straightness in the model flags
// nothing); the identification leaves the patches out first, and its gap diagnosis (`tpcal run`,
// `tpcal identify`) read local_defect while it was handed only the points the identification
// kept. Both now name the straightness, local_defect indistinguishable, and list the patches.
TEST(IdentifiedGap, PatchesAStraightnessExplainsAreNamedAsItInRun) {
  auto points = ReadPoints(std::string(TPCAL_SOURCE_DIR) + "/tests/data/points/straightness_patches_on_b_r.csv");
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  auto stage = RunIdentifyStage(Turning(), AcTable(), *points);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  ASSERT_EQ(stage->local_defects.size(), 2u);  // the identification leaves them out
  ASSERT_TRUE(stage->unscreened_observations.has_value());
  auto direct = Diagnose(Turning(), AcTable(), *points);
  auto identified = DiagnoseIdentified(Turning(), AcTable(), *stage, *points, {});
  for (const auto* d : {&direct, &identified}) {
    ASSERT_TRUE(d->ok()) << d->status().ToString();
    const DiagnosisResult& r = **d;
    EXPECT_EQ(r.verdict.family, "linear_straightness");
    const auto& alike = r.verdict.indistinguishable_from;
    EXPECT_NE(std::find(alike.begin(), alike.end(), "local_defect"), alike.end());
    EXPECT_TRUE(r.local_defects.empty());
    ASSERT_EQ(r.explained_patches.size(), 2u);
    EXPECT_EQ(r.explained_patches[0].feature, "B_R");
    EXPECT_EQ(r.explained_patches[0].lines, (std::vector<std::size_t>{30, 31}));
    EXPECT_EQ(r.explained_patches[1].lines, (std::vector<std::size_t>{34, 35, 36, 37}));
  }
  const auto json = DiagnosisJsonValue(*identified);
  ASSERT_TRUE(json.contains("explained_patches"));
  EXPECT_EQ(json["explained_patches"][1]["lines"], nlohmann::ordered_json({34, 35, 36, 37}));
  EXPECT_NE(DiagnosisText(*identified).find("a patch the screen flagged, explained by it (kept): B_R: 4 points"),
            std::string::npos);
  // The HTML: the text report in its <pre> (each patch once) and a row of the screen table per
  // patch; no bare text line outside an element.
  const std::string html = DiagnosisHtml(*identified, "piece");
  auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("a patch the screen flagged, explained by it (kept)"), 2u);
  EXPECT_EQ(count("patch explained by the verdict (kept)</td>"), 2u);
}

}  // namespace
}  // namespace tpcal::pipeline
