#include "pipeline/gcode_stage.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

TEST(GcodeStage, ProgramNameFromTheOutputStem) {
  EXPECT_EQ(ProgramNameOf("out/m2-face.nc"), "M2_FACE");
  EXPECT_EQ(ProgramNameOf("123.ngc"), "P123");
  EXPECT_EQ(ProgramNameOf("a_very_long_program_name_indeed.nc").size(), 24u);
}

TEST(GcodeStage, PostsTheProgramAndListsEveryFileToWrite) {
  const std::string dir = (fs::temp_directory_path() / "tpcal_gcode_stage").string();
  fs::create_directories(dir);
  GcodeRequest request;
  request.dialect = "linuxcnc";
  request.output = dir + "/m2.ngc";
  request.svg = dir + "/m2.svg";
  request.date = "2025-01-01";
  auto stage = RunGcodeStage({.testpiece = "iso10791_m2"}, request);
  ASSERT_TRUE(stage.ok()) << stage.status().ToString();
  EXPECT_EQ(stage->options.program_name, "M2");
  EXPECT_EQ(stage->options.date, "2025-01-01");
  EXPECT_EQ(stage->machine_type, kinematics::MachineType::kXyz);
  std::vector<std::string> paths;
  for (const GcodeFile& f : stage->files) paths.push_back(f.path);
  const std::vector<std::string> expected = {request.output, request.output + ".tbl", request.svg,
                                             request.output + ".testpiece.yaml", request.output + ".post.yaml"};
  EXPECT_EQ(paths, expected);
  EXPECT_EQ(stage->files[0].text, stage->posted.program_text);
  EXPECT_NE(stage->files[3].text.find("(--testpiece iso10791_m2)"), std::string::npos);

  request.dialect = "fanuc";
  request.effective_config = false;
  auto fanuc = RunGcodeStage({.testpiece = "iso10791_m2"}, request);
  ASSERT_TRUE(fanuc.ok()) << fanuc.status().ToString();
  EXPECT_EQ(fanuc->files.size(), 2u);  // program and backplot: no tool table, no effective configuration
}

TEST(GcodeStage, BadInputIsNamedBeforeAnythingIsPosted) {
  GcodeRequest request;
  request.dialect = "haas";
  request.output = "p.nc";
  auto dialect = RunGcodeStage({.testpiece = "no_such_piece"}, request);  // the dialect is checked first
  ASSERT_FALSE(dialect.ok());
  EXPECT_EQ(dialect.status().ToString(),
            "tpcal gcode: --dialect: expected fanuc, linuxcnc, sinumerik or heidenhain, got 'haas'");
  request.dialect = "fanuc";
  request.date = "today";
  EXPECT_EQ(RunGcodeStage({.testpiece = "iso10791_m2"}, request).status().ToString(),
            "tpcal gcode: --date: expected YYYY-MM-DD or none, got 'today'");
  request.date = "none";
  request.output = "no_such_dir/p.nc";
  auto dir = RunGcodeStage({.testpiece = "iso10791_m2"}, request);
  ASSERT_FALSE(dir.ok());
  EXPECT_EQ(dir.status().ToString(), "no_such_dir/p.nc: cannot write here: 'no_such_dir' is not a writable directory");
}

}  // namespace
}  // namespace tpcal::pipeline
