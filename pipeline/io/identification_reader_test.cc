// The identification reader (pipeline/io/identification_reader.h) on a ball bar's map response:
// a well-formed file gives the names and one row per entry; each malformed response fails at the
// axis or entry it names. On a datum ball's parameter covariance likewise.
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

// A datum ball's parameter file with its covariance (two parameters, 2 x 2): read row-major;
// absent or null gives none; a wrong size, a non-number, an asymmetric or an indefinite matrix (a
// correlation beyond 1: eigenvalue 0.125 - 0.501 < 0) fails naming the key.
constexpr const char* kIrtBall = R"({"schema": "tpcal.identification/1", "instrument": "datum_ball", "machine": "ac_table",
 "parameters": [{"name": "E_X0C", "unit": "um", "identifiable": true, "value": 1.5, "u": 0.3},
                {"name": "E_A0C", "unit": "urad", "identifiable": true, "value": -2, "u": 0.4}],
 "parameter_covariance": [[0.09, 0.06], [0.06, 0.16]]})";

TEST(IdentificationReader, ReadsAParameterCovariance) {
  auto f = ParseIdentificationJson(kIrtBall, "ball.json");
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(f->parameter_covariance, (std::vector<double>{0.09, 0.06, 0.06, 0.16}));
  std::string text = kIrtBall;
  text.replace(text.find("[[0.09"), std::string("[[0.09, 0.06], [0.06, 0.16]]").size(), "null");
  auto none = ParseIdentificationJson(text, "ball.json");
  ASSERT_TRUE(none.ok()) << none.status().ToString();
  EXPECT_TRUE(none->parameter_covariance.empty());
  struct Case { const char* to; const char* message; };
  const Case cases[] = {
      {"[[0.09, 0.06]]", "\"parameter_covariance\": expected 2 rows of 2 finite numbers"},
      {"[[0.09, 0.06], [0.06]]", "expected 2 rows of 2 finite numbers (one per parameter): row 1"},
      {"[[0.09, \"x\"], [0.06, 0.16]]", "row 0"},
      {"[[0.09, 0.06], [0.07, 0.16]]", "expected a symmetric matrix (rows 0 and 1 differ)"},
      {"[[0.09, 0.5], [0.5, 0.16]]", "expected a positive semi-definite matrix"},
      {"{}", "expected 2 rows of 2 finite numbers"},
  };
  for (const Case& c : cases) {
    std::string bad = kIrtBall;
    bad.replace(bad.find("[[0.09"), std::string("[[0.09, 0.06], [0.06, 0.16]]").size(), c.to);
    auto f2 = ParseIdentificationJson(bad, "bad.json");
    ASSERT_FALSE(f2.ok()) << c.to;
    EXPECT_EQ(f2.status().code(), StatusCode::kParseError);
    EXPECT_NE(f2.status().message().find(c.message), std::string::npos) << f2.status().ToString();
  }
}

}  // namespace
}  // namespace tpcal::pipeline
