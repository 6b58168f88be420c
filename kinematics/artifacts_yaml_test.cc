// Artifact files (tpcal.artifacts/1): the header's example reads as written, Format -> Parse of
// seed 000's set is exact, and bad input fails with the file, the line and the key.
#include "kinematics/artifacts_yaml.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace tpcal::kinematics {
namespace {

using ::testing::HasSubstr;

// Format writes the shortest text that reads back bit for bit: the round trip compares with
// EXPECT_EQ, tolerance 0.
void ExpectSameArtifacts(const ArtifactSet& a, const ArtifactSet& b) {
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (std::size_t i = 0; i < a.boxes.size(); ++i) {
    SCOPED_TRACE("box " + std::to_string(i));
    EXPECT_EQ(a.boxes[i].name, b.boxes[i].name);
    EXPECT_EQ(a.boxes[i].base_centre_mm, b.boxes[i].base_centre_mm);
    EXPECT_EQ(a.boxes[i].size_mm, b.boxes[i].size_mm);
    EXPECT_EQ(a.boxes[i].rotation_deg, b.boxes[i].rotation_deg);
  }
}

TEST(ArtifactsYaml, HeaderExampleReadsAsWritten) {
  const std::string text =
      "schema: tpcal.artifacts/1\n"
      "artifacts:\n"
      "  - {name: \"1\", base_centre_mm: [100, 0, 0], size_mm: [30, 30, 60], rotation_deg: 0}\n"
      "  - name: tall\n"
      "    base_centre_mm: [-100, 0.5, 2]\n"
      "    size_mm: [20, 40, 80]\n";
  Result<ArtifactSet> s = ParseArtifactsYaml(text, "a.yaml");
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_EQ(s->boxes.size(), 2u);
  EXPECT_EQ(s->boxes[0].name, "1");
  EXPECT_EQ(s->boxes[0].base_centre_mm, Eigen::Vector3d(100, 0, 0));
  EXPECT_EQ(s->boxes[0].size_mm, Eigen::Vector3d(30, 30, 60));
  EXPECT_EQ(s->boxes[1].name, "tall");
  EXPECT_EQ(s->boxes[1].base_centre_mm, Eigen::Vector3d(-100, 0.5, 2));
  EXPECT_EQ(s->boxes[1].size_mm, Eigen::Vector3d(20, 40, 80));
  EXPECT_EQ(s->boxes[1].rotation_deg, 0.0);  // optional, 0 when absent
  EXPECT_EQ(s->Find("tall"), 1);
  // The schema line is optional.
  Result<ArtifactSet> bare = ParseArtifactsYaml(
      "artifacts:\n  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1], rotation_deg: -12.5}\n", "a.yaml");
  ASSERT_TRUE(bare.ok()) << bare.status().ToString();
  EXPECT_EQ(bare->boxes[0].rotation_deg, -12.5);
}

TEST(ArtifactsYaml, FormatRoundTripsSeed000Exactly) {
  const ArtifactSet seed = Seed000Artifacts();
  const std::string text = FormatArtifactsYaml(seed);
  EXPECT_EQ(text,
            "schema: tpcal.artifacts/1\n"
            "artifacts:\n"
            "  - {name: \"1\", base_centre_mm: [100, 0, 0], size_mm: [30, 30, 60], rotation_deg: 0}\n"
            "  - {name: \"2\", base_centre_mm: [-100, 0, 0], size_mm: [30, 30, 60], rotation_deg: 0}\n"
            "  - {name: \"3\", base_centre_mm: [0, 100, 0], size_mm: [30, 30, 60], rotation_deg: 0}\n");
  Result<ArtifactSet> back = ParseArtifactsYaml(text, "<formatted>");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSameArtifacts(seed, *back);
}

TEST(ArtifactsYaml, FormatRoundTripsAwkwardValuesAndNames) {
  ArtifactSet set;
  ArtifactBox a;
  a.name = "box \"A\" \\ 1";  // quote and backslash escaped in the YAML
  a.base_centre_mm = Eigen::Vector3d(0.1 + 0.2, -1.0 / 3.0, 123456.78901234567);
  a.size_mm = Eigen::Vector3d(30.000000000000004, 1e-3, 6e4);
  a.rotation_deg = std::nextafter(45.0, 90.0);
  set.boxes.push_back(a);
  ArtifactBox b;
  b.name = "true";  // would read as a bool unquoted; it stays text
  b.rotation_deg = -0.0;
  set.boxes.push_back(b);
  Result<ArtifactSet> back = ParseArtifactsYaml(FormatArtifactsYaml(set), "<formatted>");
  ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << FormatArtifactsYaml(set);
  ExpectSameArtifacts(set, *back);
}

TEST(ArtifactsYaml, BadInputNamesLineAndKey) {
  const std::string head = "artifacts:\n";
  const std::string ok_box = "  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1]}\n";
  struct Case {
    const char* what;
    std::string text;
    std::size_t line;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"empty file", "", 1, "empty file"},
      {"syntax", head + "  - {name: a, base_centre_mm: [0, 0, 0\n", 3, "YAML syntax"},
      {"not a map", "- 1\n- 2\n", 1, "expected a map"},
      {"wrong schema", "schema: tpcal.machine/1\n" + head + ok_box, 1, "schema: expected tpcal.artifacts/1"},
      {"unknown top key", head + ok_box + "probe_radius_mm: 3\n", 3, "unknown key 'probe_radius_mm'"},
      {"duplicate top key", head + ok_box + "artifacts: []\n", 3, "duplicate key 'artifacts'"},
      {"no artifacts key", "schema: tpcal.artifacts/1\n", 1, "missing 'artifacts'"},
      {"artifacts not a list", "artifacts: {a: 1}\n", 1, "expected a list of boxes"},
      {"no artifacts", "schema: tpcal.artifacts/1\nartifacts: []\n", 2, "no artifacts"},
      {"unknown box key", head + "  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1], colour: red}\n", 2,
       "unknown key 'colour' in artifacts[0]"},
      {"missing name", head + "  - {base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1]}\n", 2, "missing 'name'"},
      {"missing size", head + ok_box + "  - {name: b, base_centre_mm: [0, 0, 0]}\n", 3,
       "artifacts[1]: missing 'size_mm'"},
      {"missing base", head + "  - name: a\n    size_mm: [1, 1, 1]\n", 2, "missing 'base_centre_mm'"},
      {"empty name", head + "  - name: \"\"\n    base_centre_mm: [0, 0, 0]\n    size_mm: [1, 1, 1]\n", 2,
       "non-empty name"},
      {"name with comma", head + "  - {name: \"a,b\", base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1]}\n", 2,
       "no comma"},
      {"repeated name", head + ok_box + ok_box, 3, "name 'a' repeated"},
      {"zero size", head + "  - name: a\n    base_centre_mm: [0, 0, 0]\n    size_mm: [1, 0, 1]\n", 4,
       "every extent must be > 0"},
      {"negative size", head + "  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, -60]}\n", 2, "> 0"},
      {"two coordinates", head + "  - {name: a, base_centre_mm: [0, 0], size_mm: [1, 1, 1]}\n", 2,
       "expected [x, y, z]"},
      {"not finite", head + "  - name: a\n    base_centre_mm: [0, .inf, 0]\n    size_mm: [1, 1, 1]\n", 3,
       "base_centre_mm[1]: expected a finite number"},
      {"nan rotation", head + "  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1], rotation_deg: .nan}\n",
       2, "rotation_deg: expected a finite number"},
      {"text rotation", head + "  - {name: a, base_centre_mm: [0, 0, 0], size_mm: [1, 1, 1], rotation_deg: ten}\n",
       2, "rotation_deg: expected a number, got 'ten'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Result<ArtifactSet> s = ParseArtifactsYaml(c.text, "a.yaml");
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.status().code(), StatusCode::kParseError);
    EXPECT_EQ(s.status().line(), c.line) << s.status().ToString();
    EXPECT_THAT(s.status().ToString(), HasSubstr("a.yaml:" + std::to_string(c.line) + ": "));
    EXPECT_THAT(s.status().message(), HasSubstr(c.expect));
  }
}

TEST(ArtifactsYaml, LoadNamesTheMissingFile) {
  Result<ArtifactSet> s = LoadArtifactsYaml("/nonexistent/artifacts.yaml");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kIoError);
}

}  // namespace
}  // namespace tpcal::kinematics
