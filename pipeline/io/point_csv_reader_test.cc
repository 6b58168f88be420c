#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "core/units.h"
#include "pipeline/io/point_io.h"

namespace tpcal::pipeline {
namespace {

// Same size and the same bytes (bit-identical doubles; -0.0 differs from 0.0, NaN equals itself).
template <typename T>
bool ReaderBitsEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}


std::string ReaderDataPath(const std::string& name) {
  return std::string(TPCAL_SOURCE_DIR) + "/tests/data/points/" + name;
}

PointReadOptions Serial() {
  PointReadOptions o;
  o.threads = 1;
  return o;
}

// Many tiny chunks: every chunk boundary case is exercised even on small inputs.
PointReadOptions Parallel(int threads) {
  PointReadOptions o;
  o.threads = threads;
  o.min_chunk_bytes = 1;
  return o;
}

PointSet ParseOk(const std::string& text, const PointReadOptions& options = Serial()) {
  Result<PointFile> r = ParsePointCsv(text, "mem.csv", options);
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? r->points : PointSet{};
}

Status ParseError(const std::string& text, const PointReadOptions& options = Serial()) {
  Result<PointFile> r = ParsePointCsv(text, "mem.csv", options);
  EXPECT_FALSE(r.ok());
  return r.status();
}

// ---- malformed inputs: exact file, line and message ------------------------------------

struct BadCase {
  const char* file;
  std::size_t line;
  const char* message;  // the full message
};

const BadCase kBadCases[] = {
    {"empty.csv", 0, "empty file: expected a header line such as 'feature,x,y,z' and data rows"},
    {"comments_only.csv", 0,
     "no header: the file has only comments and blank lines; expected a header line such as "
     "'feature,x,y,z' and data rows"},
    {"header_only.csv", 3, "no points: expected at least one data row after the header"},
    {"short_row.csv", 4, "row has 6 cells, header has 7 (feature,x,y,z,i,j,k)"},
    {"long_row.csv", 2, "row has 5 cells, header has 4 (feature,x,y,z)"},
    {"text_in_number.csv", 5, "column 'y': expected a number, got 'abc'"},
    {"nan.csv", 3, "column 'x': expected a finite number, got 'nan'"},
    {"inf.csv", 3, "column 'z': expected a finite number, got '-inf'"},
    {"zero_normal.csv", 4, "normal (i,j,k) = (0,0,0) has zero length; expected a unit vector"},
    {"non_unit_normal.csv", 2,
     "normal (i,j,k) = (0,0,0.5) has length 0.5; expected a unit vector (length within 0.001 of 1)"},
    {"duplicate_column.csv", 2, "duplicate header column 'X' (columns 2 and 5)"},
    {"missing_column.csv", 3,
     "header lacks the required column 'z' (expected feature,x,y,z in any order, optionally "
     "i,j,k, separated by ',' ';' or tabs; got 'feature,x,y,i,j,k')"},
    {"partial_normal.csv", 1, "header has normal column(s) i,j but not k (normals need all of i,j,k)"},
    {"unknown_unit.csv", 2,
     "unknown unit 'cm' in the units comment (expected '# units: mm' or '# units: in')"},
    {"late_units.csv", 3, "units comment after the header: '# units:' must come before it"},
    {"bad_version.csv", 1,
     "unsupported format tag 'tpcal points v2' (this reader knows 'tpcal points v1' and "
     "'tpcal plan v1')"},
    {"unterminated_quote.csv", 2, "cell 4 has an opening quote but no closing quote"},
};

TEST(PointCsvReader, MalformedFilesGiveFileLineAndExpectation) {
  for (const BadCase& c : kBadCases) {
    const std::string path = ReaderDataPath(std::string("bad/") + c.file);
    for (int threads : {1, 3}) {
      PointReadOptions options = threads == 1 ? Serial() : Parallel(threads);
      Result<PointFile> r = ReadPointCsv(path, options);
      ASSERT_FALSE(r.ok()) << c.file;
      EXPECT_EQ(r.status().code(), StatusCode::kParseError) << c.file;
      EXPECT_EQ(r.status().file(), path) << c.file;
      EXPECT_EQ(r.status().line(), c.line) << c.file << " threads " << threads;
      EXPECT_EQ(r.status().message(), c.message) << c.file;
    }
  }
}

TEST(PointCsvReader, ErrorStringIsFileColonLine) {
  const std::string path = ReaderDataPath("bad/short_row.csv");
  Result<PointFile> r = ReadPointCsv(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().ToString(), path + ":4: row has 6 cells, header has 7 (feature,x,y,z,i,j,k)");
}

TEST(PointCsvReader, MissingFileIsIoError) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("no_such_file.csv"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kIoError);
  EXPECT_NE(r.status().message().find("No such file"), std::string::npos);
}

TEST(PointCsvReader, MoreMalformedRows) {
  EXPECT_EQ(ParseError("feature,x,y,z\nA,1,,3\n").message(),
            "column 'y': expected a number, got an empty cell");
  EXPECT_EQ(ParseError("feature,x,y,z\nA,1,2,1e999\n").message(),
            "column 'z': expected a finite number, got '1e999'");
  EXPECT_EQ(ParseError("feature,x,y,z\nA,1,2,3 # note\n").message(),
            "column 'z': expected a number, got '3 # note'");
  EXPECT_EQ(ParseError("feature,x,y,z\nA,1,2,+-3\n").message(),
            "column 'z': expected a number, got '+-3'");
  EXPECT_EQ(ParseError("feature,x,y,z\nA,\"1\"\"\",2,3\n").message(),
            "cell 2 contains a doubled quote (\"\"), which this reader does not support");
  EXPECT_EQ(ParseError("feature,x,y,z\nA,\"1\"x,2,3\n").message(), "cell 2 has text after its closing quote");
  EXPECT_EQ(ParseError("feature,,y,z\nA,1,2,3\n").message(),
            "header column 2 has no name (expected names such as feature,x,y,z)");
  EXPECT_EQ(ParseError("feature,x,y,z\rA,1,2,3\r").message(),
            "line ends are bare CR characters (classic Mac); expected LF or CRLF");
  EXPECT_EQ(ParseError("# units: mm\n# units: in\nfeature,x,y,z\nA,1,2,3\n").message(),
            "conflicting units comments (line 1 says mm)");
  EXPECT_EQ(ParseError("# units\nfeature,x,y,z\nA,1,2,3\n").message(),
            "unknown unit '' in the units comment (expected '# units: mm' or '# units: in')");
  // A long row is reported as such even when one of its cells is also bad.
  EXPECT_EQ(ParseError("feature,x,y,z\nA,abc,2,3,4\n").message(), "row has 5 cells, header has 4 (feature,x,y,z)");
}

TEST(PointCsvReader, LongCellIsTruncatedInTheMessage) {
  const std::string cell(100, 'q');
  EXPECT_EQ(ParseError("feature,x,y,z\nA," + cell + ",2,3\n").message(),
            "column 'x': expected a number, got '" + std::string(37, 'q') + "...'");
}

// ---- what is accepted ------------------------------------------------------------------

TEST(PointCsvReader, ContractExample) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("canonical.csv"), Serial());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  EXPECT_EQ(r->info.kind, PointFileKind::kPoints);
  EXPECT_EQ(r->info.source_units, LengthUnit::kMm);
  EXPECT_EQ(r->info.format, PointFormat::kCsv);
  ASSERT_EQ(ps.size(), 5u);
  EXPECT_EQ(ps.source, ReaderDataPath("canonical.csv"));
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"S_R", "H1", "B_R"}));
  EXPECT_EQ(ps.feature, (std::vector<int>{0, 1, 0, 2, 1}));  // S_R and H1 not contiguous
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{4, 5, 6, 7, 8}));
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(118.99871, 0.00312, -4.99960));
  EXPECT_EQ(ps.xyz_mm[4], Eigen::Vector3d(144.99998, 0.35021, -7.49987));
  ASSERT_TRUE(ps.has_normals());
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(-1, 0, 0));  // exact unit: kept bit-exact
  // 0.7071068 printed to 7 decimals: |n| = 1 + 1.8e-7, normalised.
  EXPECT_NEAR(ps.normal[4].norm(), 1.0, 4e-16);
  EXPECT_NEAR(ps.normal[4].x(), std::sqrt(0.5), 1e-15);
  EXPECT_TRUE(ps.attributes.empty());
  EXPECT_TRUE(ps.has_labels());
  const int h1 = *ps.FeatureIndex("H1");
  EXPECT_EQ(FirstLineOfFeature(ps, h1), 5u);
  EXPECT_EQ(FirstLineOfFeature(ps, 99), 0u);
  EXPECT_EQ(AtFeature(ps, h1, Status(StatusCode::kTooFewPoints, "H1 has 2 points, a circle needs 3"))
                .ToString(),
            ReaderDataPath("canonical.csv") + ":5: H1 has 2 points, a circle needs 3");
}

TEST(PointCsvReader, ColumnsInAnyOrderAnyCaseAndExtraColumnsKept) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("columns_any_order.csv"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  EXPECT_EQ(r->info.kind, PointFileKind::kUntagged);
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(118.99871, 0.00312, -4.99960));
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(-1, 0, 0));
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"S_R", "H1"}));
  ASSERT_EQ(ps.attributes.size(), 1u);
  EXPECT_EQ(ps.attributes[0].name, "probe_id");
  EXPECT_TRUE(ps.attributes[0].is_numeric());
  EXPECT_EQ(ps.attributes[0].values, (std::vector<double>{7, 8}));
}

TEST(PointCsvReader, PlanFileColumnsBecomeAttributes) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("plan.csv"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  EXPECT_EQ(r->info.kind, PointFileKind::kPlan);
  ASSERT_EQ(ps.size(), 4u);
  std::vector<std::string> names;
  for (const auto& a : ps.attributes) names.push_back(a.name);
  EXPECT_EQ(names, (std::vector<std::string>{"op", "t_s", "A_deg", "C_deg", "X_mm", "Y_mm", "Z_mm"}));
  ASSERT_NE(ps.Attribute("t_s"), nullptr);
  EXPECT_EQ(ps.Attribute("t_s")->values, (std::vector<double>{812.5, 815.25, 830, 1402.125}));
  EXPECT_EQ(ps.Attribute("C_deg")->values, (std::vector<double>{0, 90, 0, 0}));
  EXPECT_EQ(ps.Attribute("op")->values, (std::vector<double>{3, 3, 3, 7}));
}

TEST(PointCsvReader, InchesAreConvertedToMm) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("inches.csv"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->info.source_units, LengthUnit::kInch);
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 2u);
  // Truth: the inch values times exactly 25.4 mm/in (the conversion is one multiplication).
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1 * kMmPerInch, 2 * kMmPerInch, -0.5 * kMmPerInch));
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(0.1 * kMmPerInch, 0.0, 10 * kMmPerInch));
  EXPECT_DOUBLE_EQ(ps.xyz_mm[1].x(), 2.54);
}

TEST(PointCsvReader, UnitsDirectiveSpellings) {
  for (const char* line : {"# units: in", "#units:in", "# Units = IN", "#   units   in  "}) {
    PointSet ps = ParseOk(std::string(line) + "\nfeature,x,y,z\nA,1,0,0\n");
    ASSERT_EQ(ps.size(), 1u) << line;
    EXPECT_EQ(ps.xyz_mm[0].x(), 25.4) << line;
  }
  EXPECT_EQ(ParseOk("# unitsless comment\nfeature,x,y,z\nA,1,0,0\n").xyz_mm[0].x(), 1.0);
  EXPECT_EQ(ParseOk("# tpcal run 7 by lab 3\nfeature,x,y,z\nA,1,0,0\n").size(), 1u);
}

TEST(PointCsvReader, RawScanHasNoLabels) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("raw_scan.csv"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_FALSE(ps.has_labels());
  EXPECT_TRUE(ps.feature_names.empty());
  for (int f : ps.feature) EXPECT_EQ(f, PointSet::kUnlabelled);
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{4, 5, 6}));
}

TEST(PointCsvReader, MixedLabelledAndUnlabelledRows) {
  PointSet ps = ParseOk("feature,x,y,z\nA,1,2,3\n,4,5,6\n  ,7,8,9\n");
  EXPECT_EQ(ps.feature, (std::vector<int>{0, PointSet::kUnlabelled, PointSet::kUnlabelled}));
  EXPECT_TRUE(ps.has_labels());
}

TEST(PointCsvReader, CrlfTrailingBlanksBlankLinesAndQuotes) {
  Result<PointFile> r = ReadPointCsv(ReaderDataPath("crlf.csv"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{5, 7, 8}));
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(ps.feature, (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(ps.xyz_mm[2], Eigen::Vector3d(7, 8, 9));
}

TEST(PointCsvReader, TextAttributesKeepTheirText) {
  for (int threads : {1, 2}) {
    Result<PointFile> r = ReadPointCsv(ReaderDataPath("text_attribute.csv"), threads == 1 ? Serial() : Parallel(2));
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    const PointSet& ps = r->points;
    ASSERT_EQ(ps.attributes.size(), 2u);
    EXPECT_FALSE(ps.attributes[0].is_numeric());
    EXPECT_EQ(ps.attributes[0].text, (std::vector<std::string>{"007", "probe, star", ""}));
    EXPECT_TRUE(ps.attributes[1].is_numeric());
    EXPECT_EQ(ps.attributes[1].values, (std::vector<double>{1, 2, 3}));
  }
}

TEST(PointCsvReader, NumberSpellings) {
  PointSet ps = ParseOk("feature,x,y,z\nA,+1.5,-2e-3,.25\nA,1.,1E+2,  -0  \n");
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.5, -0.002, 0.25));
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(1.0, 100.0, 0.0));
  EXPECT_TRUE(std::signbit(ps.xyz_mm[1].z()));
}

TEST(PointCsvReader, ToleratedOddities) {
  // UTF-8 BOM, upper-case header, trailing comma on every line, spreadsheet empty rows.
  PointSet ps = ParseOk("\xEF\xBB\xBF" "Feature,X,Y,Z,\nA,1,2,3,\n,,,,\n , , ,,\nB,4,5,6,\n");
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{2, 5}));
  EXPECT_TRUE(ps.attributes.empty());
  // No final newline.
  EXPECT_EQ(ParseOk("feature,x,y,z\nA,1,2,3").size(), 1u);
}

TEST(PointCsvReader, SpreadsheetQuotingEverywhere) {
  PointSet ps = ParseOk("\"feature\",\"x\",\"y\",\"z\"\n\"H1, wall\",\"1.5\", \"2\" ,\"3\"\n");
  ASSERT_EQ(ps.size(), 1u);
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"H1, wall"}));
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.5, 2, 3));
  EXPECT_EQ(ParseError("feature|x|y|z\nA|1|2|3\n").message(),
            "header lacks the required column 'feature' (expected feature,x,y,z in any order, optionally "
            "i,j,k, separated by ',' ';' or tabs; got 'feature|x|y|z')");
}

// Tables other software writes (docs/formats/points.md, "Tables from other software"): ';' with
// decimal commas (spreadsheets in most of Europe), tabs, and the column names of CMM exports.
TEST(PointCsvReader, SemicolonTableWithDecimalCommas) {
  PointSet ps = ParseOk("Name;X;Y;Z;I;J;K\nH1;12,5;-0,25;3;0;0,6;0,8\n\"S;2\";1.5;2;1e1;1;0;0\n;;;;;;\n");
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"H1", "S;2"}));
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(12.5, -0.25, 3));
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(0, 0.6, 0.8));
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(1.5, 2, 10));
  EXPECT_TRUE(ps.attributes.empty());
  EXPECT_EQ(ParseError("name;x;y;z\nA;1,2,3;0;0\n").message(),
            "column 'x': expected a number, got '1,2,3'");
  // In a ','-separated file a decimal comma is a cell count error, as before.
  EXPECT_EQ(ParseError("feature,x,y,z\nA,1,5,2,3\n").message(), "row has 5 cells, header has 4 (feature,x,y,z)");
  // A leading '+' as the point form allows it; never two signs.
  EXPECT_EQ(ParseOk("name;x;y;z\nA;+1,5;+2;-0,5\n").xyz_mm[0], Eigen::Vector3d(1.5, 2, -0.5));
  EXPECT_EQ(ParseError("name;x;y;z\nA;+-1,5;0;0\n").message(), "column 'x': expected a number, got '+-1,5'");
  EXPECT_EQ(ParseError("name;x;y;z\nA;+;0;0\n").message(), "column 'x': expected a number, got '+'");
}

TEST(PointCsvReader, TabTableKeepsEmptyCellsAndBlanksInNames) {
  PointSet ps = ParseOk("feature name\tx\ty\tz\tprobe id\n\t1\t2\t3\tT 1\nH 2\t4\t5\t6\tT 2\n");
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps.feature, (std::vector<int>{PointSet::kUnlabelled, 0}));
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"H 2"}));
  ASSERT_EQ(ps.attributes.size(), 1u);
  EXPECT_EQ(ps.attributes[0].name, "probe id");
  EXPECT_EQ(ps.attributes[0].text, (std::vector<std::string>{"T 1", "T 2"}));
  EXPECT_EQ(ParseError("label\tx\ty\tz\nA\t1\t2\n").message(),
            "row has 3 cells, header has 4 (label<tab>x<tab>y<tab>z)");
}

TEST(PointCsvReader, ContractNamesWinOverAliases) {
  // `feature` is the label; `name` stays an attribute. nx,ny,nz are the normal when i,j,k are absent.
  PointSet ps = ParseOk("name,feature,x,y,z,nx,ny,nz\nP1,A,1,2,3,1,0,0\n");
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"A"}));
  ASSERT_EQ(ps.attributes.size(), 1u);
  EXPECT_EQ(ps.attributes[0].name, "name");
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(1, 0, 0));
  // A ','-separated header that holds every required column stays ','-separated.
  PointSet comma = ParseOk("feature,x,y,z,a;b\nA,1,2,3,4\n");
  ASSERT_EQ(comma.attributes.size(), 1u);
  EXPECT_EQ(comma.attributes[0].name, "a;b");
  // The normal's aliases count only as a whole triple: `i` with `ny,nz` is not one normal.
  EXPECT_EQ(ParseError("feature,x,y,z,i,ny,nz\nA,1,2,3,1,0,0\n").message(),
            "header has normal column(s) i but not j,k (normals need all of i,j,k)");
}

// A column mapping names the header's own columns for roles: it wins over contract names and
// aliases (which then stay attributes), a mapped name the header lacks is an error, and the
// separator is found with it.
TEST(PointCsvReader, ColumnMappingNamesTheTablesOwnColumns) {
  PointReadOptions o = Serial();
  o.columns = {{"feature", "Pt ID"}, {"x", "px"}, {"y", "PY"}, {"z", "PZ"}};
  PointSet ps = ParseOk("Pt ID;PX;PY;PZ;feature\nH1;1,5;2;3;other\n", o);
  ASSERT_EQ(ps.size(), 1u);
  EXPECT_EQ(ps.feature_names, (std::vector<std::string>{"H1"}));
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.5, 2, 3));
  ASSERT_EQ(ps.attributes.size(), 1u);
  EXPECT_EQ(ps.attributes[0].name, "feature");
  o.columns = {{"feature", "Point"}};
  EXPECT_EQ(ParseError("Pt ID,x,y,z\nH1,1,2,3\n", o).message(),
            "header has no column 'Point' (the column mapping's feature=Point); got 'Pt ID,x,y,z'");
  o.columns = {{"x", "A"}, {"y", "a"}};
  EXPECT_EQ(ParseError("feature,A,y,z\nH1,1,2,3\n", o).message(), "column 'a' is mapped to both x and y");
  o.columns = {{"x", "A"}};
  Result<PointFile> xyz = ParsePointXyz("1 2 3\n", "mem.xyz", o);
  ASSERT_FALSE(xyz.ok());
  EXPECT_NE(xyz.status().message().find("CSV and TSV tables only"), std::string::npos) << xyz.status().ToString();
}

TEST(PointCsvReader, NormalTolerance) {
  // Within 1e-3 of unit: normalised. Beyond: error. Tolerance is an option.
  PointSet ps = ParseOk("feature,x,y,z,i,j,k\nA,0,0,0,0,0,1.0009\n");
  EXPECT_EQ(ps.normal[0], Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(ParseError("feature,x,y,z,i,j,k\nA,0,0,0,0,0,1.0011\n").line(), 2u);
  PointReadOptions loose = Serial();
  loose.normal_tolerance = 0.5;
  EXPECT_NEAR(ParseOk("feature,x,y,z,i,j,k\nA,0,0,0,0,0.6,0.6\n", loose).normal[0].norm(), 1.0, 4e-16);
}

TEST(PointCsvReader, OptionsAreValidated) {
  PointReadOptions bad;
  bad.threads = -2;
  Result<PointFile> r = ParsePointCsv("feature,x,y,z\nA,1,2,3\n", "mem.csv", bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  bad = PointReadOptions{};
  bad.normal_tolerance = std::nan("");
  EXPECT_FALSE(bad.Validate().ok());
}

// ---- parallel == serial --------------------------------------------------------------

// A big file with everything the parser must get right across chunk boundaries: comments,
// blank lines, CRLF rows, quoted labels, empty labels, many features, a text attribute whose
// only non-number is near the end.
std::string GenerateBigCsv(std::size_t n_rows, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-500.0, 500.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 99);
  std::string out = "# tpcal points v1\n# units: mm\nfeature,x,y,z,i,j,k,t_s,note\n";
  for (std::size_t r = 0; r < n_rows; ++r) {
    const int kind = pick(rng);
    if (kind == 0) out += "# a comment line\n";
    if (kind == 1) out += "\n";
    Eigen::Vector3d n{gauss(rng), gauss(rng), gauss(rng)};
    n.normalize();
    const std::string label = kind == 2 ? "" : fmt::format("F{}", pick(rng) % 37);
    const std::string note = r == n_rows - 10 ? "late text" : fmt::format("{}", pick(rng));
    const double x = coord(rng), y = coord(rng), z = coord(rng);  // drawn in this order under every compiler
    out += fmt::format("{}{}{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.6f},{}{}\n",
                       kind == 3 ? "\"" : "", label, kind == 3 ? "\"" : "", x, y, z, n.x(), n.y(), n.z(), r * 0.01,
                       note, kind == 4 ? "\r" : "");
  }
  return out;
}

void ExpectBitIdentical(const PointSet& a, const PointSet& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(ReaderBitsEqual(a.xyz_mm, b.xyz_mm));
  EXPECT_TRUE(ReaderBitsEqual(a.normal, b.normal));
  EXPECT_EQ(a.feature, b.feature);
  EXPECT_EQ(a.feature_names, b.feature_names);
  EXPECT_EQ(a.line, b.line);
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  for (std::size_t k = 0; k < a.attributes.size(); ++k) {
    EXPECT_EQ(a.attributes[k].name, b.attributes[k].name);
    EXPECT_EQ(a.attributes[k].text, b.attributes[k].text);
    EXPECT_TRUE(ReaderBitsEqual(a.attributes[k].values, b.attributes[k].values));
  }
}

TEST(PointCsvReader, ParallelParseIsBitIdenticalToSerial) {
  const std::string text = GenerateBigCsv(60000, 20240611);
  Result<PointFile> serial = ParsePointCsv(text, "big.csv", Serial());
  ASSERT_TRUE(serial.ok()) << serial.status().ToString();
  EXPECT_EQ(serial->info.chunks, 1);
  ASSERT_EQ(serial->points.size(), 60000u);
  EXPECT_FALSE(serial->points.attributes[1].is_numeric());  // "late text"
  EXPECT_EQ(serial->points.attributes[1].text[60000 - 10], "late text");
  EXPECT_TRUE(serial->points.attributes[0].is_numeric());
  for (int threads : {2, 3, 8, 17}) {
    PointReadOptions o;
    o.threads = threads;
    o.min_chunk_bytes = 4096;
    Result<PointFile> parallel = ParsePointCsv(text, "big.csv", o);
    ASSERT_TRUE(parallel.ok()) << parallel.status().ToString();
    EXPECT_EQ(parallel->info.chunks, threads);
    ExpectBitIdentical(serial->points, parallel->points);
  }
}

TEST(PointCsvReader, ParallelReportsTheFirstErrorInFileOrder) {
  std::string text = GenerateBigCsv(20000, 7);
  // Two errors: one in the middle, one near the end. Both parses must report the first.
  const std::size_t mid = text.find('\n', text.size() / 2) + 1;
  const std::size_t late = text.find('\n', text.size() * 9 / 10) + 1;
  text.insert(late, "F1,1,2,3,0,0,1,0,x,extra\n");
  text.insert(mid, "F1,1,2,3,0,0,0,0,x\n");
  const std::size_t mid_line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + mid, '\n'));
  Status serial = ParseError(text, Serial());
  EXPECT_EQ(serial.line(), mid_line);
  EXPECT_EQ(serial.message(), "normal (i,j,k) = (0,0,0) has zero length; expected a unit vector");
  for (int threads : {2, 5, 16}) {
    PointReadOptions o;
    o.threads = threads;
    o.min_chunk_bytes = 1024;
    Status parallel = ParseError(text, o);
    EXPECT_EQ(parallel.line(), serial.line()) << threads;
    EXPECT_EQ(parallel.message(), serial.message()) << threads;
  }
}

}  // namespace
}  // namespace tpcal::pipeline
