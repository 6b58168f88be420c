// The identification reader (pipeline/io/identification_reader.h) on a ball bar's map response:
// a well-formed file gives the names and one row per entry; each malformed response fails at the
// axis or entry it names.
#include "pipeline/io/identification_reader.h"

#include <gtest/gtest.h>

#include <string>

namespace tpcal::pipeline {
namespace {

constexpr const char* kIrtBallbar = R"({"schema": "tpcal.identification/1", "instrument": "ballbar", "machine": "ac_table",
 "axes": [{"axis": "C", "response_to": ["E_C(0X)Y", "E_B(0X)Z"],
           "errors": [{"coefficient": "E_XC.n0", "identifiable": true, "u": 0.2, "response": [0.5, -0.25]},
                      {"coefficient": "E_XC.n1", "identifiable": false, "response": [0, 1e-3]}]}],
 "errors_yaml": "schema: tpcal.errors/1\nmachine: ac_table\n"})";

TEST(IdentificationReader, ReadsABallbarsMapResponse) {
  auto f = ParseIdentificationJson(kIrtBallbar, "bb.json");
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(f->map_unmodelled, (std::vector<std::string>{"E_C(0X)Y", "E_B(0X)Z"}));
  ASSERT_EQ(f->map_unmodelled_response.size(), 2u);
  EXPECT_EQ(f->map_unmodelled_response[0].first, "E_XC.n0");
  EXPECT_EQ(f->map_unmodelled_response[0].second, (std::vector<double>{0.5, -0.25}));
  EXPECT_EQ(f->map_unmodelled_response[1].second, (std::vector<double>{0.0, 1e-3}));
  EXPECT_EQ(f->map_entries, 2);
  EXPECT_EQ(f->map_undetermined, std::vector<std::string>{"E_XC.n1"});
}

TEST(IdentificationReader, AMalformedMapResponseFailsWhereItIs) {
  struct Case { const char* from; const char* to; const char* message; };
  const Case cases[] = {
      {"\"response_to\": [\"E_C(0X)Y\", \"E_B(0X)Z\"]", "\"response_to\": [\"E_C(0X)Y\", 3]",
       "axes[0]: expected \"response_to\" to be a non-empty array of error names"},
      {"\"response_to\": [\"E_C(0X)Y\", \"E_B(0X)Z\"]", "\"response_to\": []",
       "axes[0]: expected \"response_to\" to be a non-empty array of error names"},
      {"\"response\": [0.5, -0.25]", "\"response\": [0.5]", "axes[0].errors[0]: expected a \"response\" of 2 numbers"},
      {"\"response\": [0, 1e-3]", "\"response\": [0, \"x\"]", "axes[0].errors[1]: expected finite numbers in \"response\""},
      {", \"response\": [0, 1e-3]", "", "axes[0].errors[1]: expected a \"response\" of 2 numbers"},
      {"\"coefficient\": \"E_XC.n1\", ", "", "axes[0].errors[1]: expected a string \"coefficient\""},
      {"}]}],", "}]}, {\"axis\": \"A\", \"response_to\": [\"E_C(0X)Y\"], \"errors\": []}],",
       "axes[1]: expected the same \"response_to\" as the axes before it"},
      {"}]}],", "}]}, {\"axis\": \"A\", \"errors\": []}],", "axes[1]: expected \"response_to\" on every axis or on none"},
  };
  for (const Case& c : cases) {
    std::string text = kIrtBallbar;
    const std::size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    text.replace(at, std::string(c.from).size(), c.to);
    auto f = ParseIdentificationJson(text, "bad.json");
    ASSERT_FALSE(f.ok()) << c.to;
    EXPECT_EQ(f.status().code(), StatusCode::kParseError);
    EXPECT_EQ(f.status().file(), "bad.json");
    EXPECT_NE(f.status().message().find(c.message), std::string::npos) << f.status().ToString();
  }
}

}  // namespace
}  // namespace tpcal::pipeline
