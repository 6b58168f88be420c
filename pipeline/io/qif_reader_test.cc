#include "pipeline/io/qif_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/base64.h"
#include "core/units.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/io/file_bytes.h"

namespace tpcal::pipeline {
namespace {

std::string QifSamplePath() {
  return std::string(TPCAL_SOURCE_DIR) + "/tests/data/qif/QIF_PTS_SAMPLE_excerpt.QIF";
}

// A QIF document around `sets` (MeasuredPointSet elements) and `features` (measurements),
// with items 1 = "PLANE_A", 2 = "HOLE_B".
std::string Doc(const std::string& units, const std::string& features, const std::string& sets) {
  return "<?xml version=\"1.0\"?>\n"
         "<QIFDocument xmlns=\"http://qifstandards.org/xsd/qif3\" versionQIF=\"3.0.0\">\n" +
         units +
         "<Features><FeatureItems n=\"2\">\n"
         "<PlaneFeatureItem id=\"1\"><FeatureName>PLANE_A</FeatureName></PlaneFeatureItem>\n"
         "<CircleFeatureItem id=\"2\"><FeatureName>HOLE_B</FeatureName></CircleFeatureItem>\n"
         "</FeatureItems></Features>\n"
         "<Results><MeasurementResultsSet n=\"1\"><MeasurementResults id=\"9\">\n"
         "<MeasuredFeatures n=\"1\">\n" +
         features +
         "</MeasuredFeatures>\n"
         "<MeasuredPointSets n=\"1\">\n" +
         sets +
         "</MeasuredPointSets>\n"
         "</MeasurementResults></MeasurementResultsSet></Results>\n"
         "</QIFDocument>\n";
}

const std::string kMm =
    "<FileUnits><PrimaryUnits><LinearUnit><SIUnitName>meter</SIUnitName><UnitName>mm</UnitName>"
    "<UnitConversion><Factor>0.001</Factor></UnitConversion></LinearUnit></PrimaryUnits></FileUnits>\n";
const std::string kInch =
    "<FileUnits><PrimaryUnits><LinearUnit><UnitName>inch</UnitName></LinearUnit></PrimaryUnits></FileUnits>\n";
const std::string kPlaneWhole10 =
    "<PlaneFeatureMeasurement id=\"3\"><FeatureItemId>1</FeatureItemId>"
    "<PointList n=\"1\"><WholePointSetId>10</WholePointSetId></PointList></PlaneFeatureMeasurement>\n";
const std::string kSet10 =
    "<MeasuredPointSet id=\"10\" count=\"3\">\n<Points>\n1 2 3\n4 5 6\n7 8 9\n</Points>\n"
    "<Normals>0 0 1 0 0 1 0 0 1</Normals>\n</MeasuredPointSet>\n";

TEST(QifReader, ReadsPointsNormalsAndLabels) {
  auto r = ParseQif(Doc(kMm, kPlaneWhole10, kSet10), "t.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps.feature_names, std::vector<std::string>{"PLANE_A"});
  EXPECT_EQ(ps.xyz_mm[1], Eigen::Vector3d(4, 5, 6));
  ASSERT_TRUE(ps.has_normals());
  EXPECT_EQ(ps.normal[2], Eigen::Vector3d(0, 0, 1));
  // Points start on the line after <Points> (line 15 of the document).
  EXPECT_EQ(ps.line[0], 15u);
  EXPECT_EQ(ps.line[2], 17u);
  EXPECT_EQ(r->file.info.format, PointFormat::kQif);
  EXPECT_TRUE(ps.attributes.empty());
}

TEST(QifReader, InchUnitsAndRanges) {
  const std::string feats =
      "<CircleFeatureMeasurement id=\"3\"><FeatureItemId>2</FeatureItemId><PointList n=\"2\">"
      "<RangePointSetId range=\"2 3\">10</RangePointSetId><SinglePointSetId index=\"1\">10</SinglePointSetId>"
      "</PointList></CircleFeatureMeasurement>\n";
  auto r = ParseQif(Doc(kInch, feats, kSet10), "t.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_DOUBLE_EQ(ps.xyz_mm[0].x(), 4 * kMmPerInch);
  EXPECT_DOUBLE_EQ(ps.xyz_mm[2].z(), 3 * kMmPerInch);
  EXPECT_EQ(r->file.info.source_units, LengthUnit::kInch);
  EXPECT_EQ(ps.feature_names[0], "HOLE_B");
}

TEST(QifReader, FactorUnits) {
  const std::string units =
      "<FileUnits><PrimaryUnits><LinearUnit><SIUnitName>meter</SIUnitName><UnitName>decimetre</UnitName>"
      "<UnitConversion><Factor>0.1</Factor></UnitConversion></LinearUnit></PrimaryUnits></FileUnits>\n";
  auto r = ParseQif(Doc(units, kPlaneWhole10, kSet10), "t.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_DOUBLE_EQ(r->file.points.xyz_mm[0].x(), 100.0);
}

TEST(QifReader, UncompensatedWithNormalsIsCompensatedAndStated) {
  const std::string set =
      "<MeasuredPointSet id=\"10\"><Points>0 0 2.5</Points><Normals>0 0 1</Normals>"
      "<Compensated>false</Compensated><ProbeRadius>2.5</ProbeRadius></MeasuredPointSet>\n";
  auto r = ParseQif(Doc(kMm, kPlaneWhole10, set), "t.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->file.points.xyz_mm[0], Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(r->report.sets_compensated_by_reader, 1u);
  const PointAttribute* a = r->file.points.Attribute("probe_compensation_mm");
  ASSERT_NE(a, nullptr);
  EXPECT_DOUBLE_EQ(a->values[0], 2.5);
}

TEST(QifReader, RoundTripOfTpcalsOwnFileIsBitExact) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-300, 300);
  PointSet ps;
  for (int i = 0; i < 500; ++i) {
    ps.xyz_mm.push_back(Eigen::Vector3d{u(rng), u(rng), u(rng)});
    ps.normal.push_back(Eigen::Vector3d{u(rng), u(rng), u(rng)}.normalized());
    ps.feature.push_back(ps.InternFeature(i % 3 == 0 ? "S_R" : (i % 3 == 1 ? "B_R" : "H<1>&")));
  }
  auto r = ParseQif(FormatPointQif(ps), "own.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& back = r->file.points;
  ASSERT_EQ(back.size(), ps.size());
  // Grouped by feature in order of first appearance.
  std::vector<std::size_t> order;
  for (int f = 0; f < 3; ++f)
    for (std::size_t i = 0; i < ps.size(); ++i)
      if (ps.feature[i] == f) order.push_back(i);
  for (std::size_t k = 0; k < order.size(); ++k) {
    EXPECT_EQ(std::memcmp(back.xyz_mm[k].data(), ps.xyz_mm[order[k]].data(), sizeof(double) * 3), 0);
    EXPECT_NEAR((back.normal[k] - ps.normal[order[k]]).norm(), 0.0, 1e-15);
    EXPECT_EQ(back.feature_names[static_cast<std::size_t>(back.feature[k])],
              ps.feature_names[static_cast<std::size_t>(ps.feature[order[k]])]);
  }
}

TEST(QifReader, PublishedSampleIsRefusedAsUncompensated) {
  auto bytes = ReadFileBytes(QifSamplePath());
  ASSERT_TRUE(bytes.ok());
  auto r = ParseQif(bytes->view(), "sample.QIF");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kParseError);
  EXPECT_NE(r.status().message().find("not probe-compensated"), std::string::npos) << r.status().ToString();
  EXPECT_EQ(r.status().line(), 223u);  // <MeasuredPointSet id="29">
  // Through the dispatch by extension: the same refusal.
  auto d = ReadPointFile(QifSamplePath());
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.status().ToString().find("QIF_PTS_SAMPLE_excerpt.QIF:223: "), std::string::npos);
}

TEST(QifReader, PublishedSampleReadsAsCentresWithLenientReferences) {
  auto bytes = ReadFileBytes(QifSamplePath());
  ASSERT_TRUE(bytes.ok());
  QifReadOptions o;
  o.accept_uncompensated = true;
  // Strict references: set 777 belongs to no feature (the sample's PointFeatureMeasurement 776
  // has no PointList), and measurement 828 names a set that does not exist.
  auto strict = ParseQif(bytes->view(), "sample.QIF", o);
  ASSERT_FALSE(strict.ok());
  EXPECT_NE(strict.status().message().find("828"), std::string::npos) << strict.status().ToString();
  o.lenient_references = true;
  auto r = ParseQif(bytes->view(), "sample.QIF", o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  // plane 6 (range 3..8) + 3 circles x 12 + line 2 + points 757, 767, 787, 834 + cylinder 18,
  // then the unreferenced sets 777 and 829 unlabelled.
  EXPECT_EQ(ps.size(), 6u + 36u + 2u + 4u + 18u + 2u);
  EXPECT_EQ(r->report.point_sets, 12u);
  EXPECT_EQ(r->report.sets_read_as_centres, 12u);
  EXPECT_EQ(r->report.unreferenced_sets, 2u);
  EXPECT_EQ(r->report.dropped_points, 2u);  // points 1, 2 of the plane set
  EXPECT_EQ(ps.feature_names.front(), "DATUMA");
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(17.02290609066, -6.12985679561, 2.50307291306));
  EXPECT_EQ(ps.PointsOf("CYL_1").size(), 18u);
  EXPECT_EQ(ps.PointsOf("DATUMC").size(), 2u);
  EXPECT_FALSE(ps.has_normals());
  EXPECT_EQ(ps.feature.back(), PointSet::kUnlabelled);
}

// A scan-sized <Points> text is parsed in parallel pieces: the same points, normals, lines and
// first error as the serial scan.
TEST(QifReader, ParallelScanOfLargePointsEqualsSerial) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-300, 300);
  PointSet ps;
  for (int i = 0; i < 200000; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng);  // drawn in this order under every compiler
    ps.xyz_mm.emplace_back(x, y, z);
    ps.normal.push_back(Eigen::Vector3d(y, z, x).normalized());
    ps.feature.push_back(ps.InternFeature("SCAN"));
  }
  std::string text = FormatPointQif(ps);
  ASSERT_GT(text.size(), std::size_t{4} << 20);
  QifReadOptions serial, parallel;
  serial.threads = 1;
  parallel.threads = 3;
  auto a = ParseQif(text, "big.qif", serial);
  auto b = ParseQif(text, "big.qif", parallel);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->file.points.size(), 200000u);
  EXPECT_EQ(a->file.points.xyz_mm, b->file.points.xyz_mm);
  EXPECT_EQ(a->file.points.line, b->file.points.line);
  EXPECT_EQ(a->file.points.normal, b->file.points.normal);
  EXPECT_EQ(a->file.points.normal[7], ps.normal[7]);
  EXPECT_EQ(a->file.points.xyz_mm[123456], ps.xyz_mm[123456]);
  // A bad token three quarters in.
  const std::size_t at = text.find('\n', text.size() * 3 / 4) + 1;
  text.insert(at, "1.5e ");
  auto ea = ParseQif(text, "big.qif", serial);
  auto eb = ParseQif(text, "big.qif", parallel);
  ASSERT_FALSE(ea.ok());
  ASSERT_FALSE(eb.ok());
  EXPECT_EQ(ea.status().ToString(), eb.status().ToString());
  EXPECT_NE(ea.status().message().find("'1.5e'"), std::string::npos) << ea.status().ToString();
}

// A plain <Points> text is parsed from the file's bytes; any other (a comment, a character
// reference, CR line ends) reaches the reader in libxml2's pieces, with numbers cut at a piece's
// end carried over. Truth: both give the same points and lines; a comment ends a number.
TEST(QifReader, PlainAndPiecewisePointsTextsReadAlike) {
  auto read = [](const std::string& points_text) {
    const std::string set = "<MeasuredPointSet id=\"10\"><Points>" + points_text + "</Points></MeasuredPointSet>\n";
    return ParseQif(Doc(kMm, kPlaneWhole10, set), "t.qif");
  };
  auto plain = read("\n1.25 2 3\n4 5 6\n");
  ASSERT_TRUE(plain.ok()) << plain.status().ToString();
  for (const std::string& text : {std::string("\r\n1.25 2 3\r\n4 5 6\r\n"), std::string("\n1.2&#53; 2 3\n4 5 6\n"),
                                  std::string("\n1.25 2<!-- c\n -->3\n4 5 6\n"), std::string("\n1.25&#x20;2 3\n4 5 6\n")}) {
    auto other = read(text);
    ASSERT_TRUE(other.ok()) << other.status().ToString();
    EXPECT_EQ(other->file.points.xyz_mm, plain->file.points.xyz_mm) << text;
  }
  auto lines = read("\n1.25 2<!-- c\n -->\n3 4 5 6\n");
  ASSERT_TRUE(lines.ok());
  EXPECT_EQ(lines->file.points.line, (std::vector<std::size_t>{14, 16}));
  EXPECT_EQ(plain->file.points.line, (std::vector<std::size_t>{14, 15}));
  auto cut = read("\n1.2<!-- -->5 2\n4 5 6\n");  // "1.2" and "5": a number does not run across a comment
  ASSERT_TRUE(cut.ok());
  EXPECT_EQ(cut->file.points.xyz_mm[0], Eigen::Vector3d(1.2, 5, 2));
  auto bad = read("\n1 2 3\n4 5 caf\xC3\xA9\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().line(), 15u);
  EXPECT_NE(bad.status().message().find("'caf\xC3\xA9' in <Points>"), std::string::npos) << bad.status().ToString();
}

// A parallel block is handed to libxml2 as its newlines only: lines after it stay the file's.
// Truth: a bad <Compensated> after 200 000 points is reported on its own line of the file.
TEST(QifReader, LinesAfterALargeBlockAreTheFilesLines) {
  PointSet ps;
  for (int i = 0; i < 200000; ++i) {
    ps.xyz_mm.emplace_back(i * 1e-3, 2.0, 3.0);
    ps.normal.emplace_back(0, 0, 1);
    ps.feature.push_back(ps.InternFeature("SCAN"));
  }
  std::string text = FormatPointQif(ps);
  const std::size_t at = text.find("</Normals>") + std::strlen("</Normals>");
  text.insert(at, "\n<Compensated>maybe</Compensated>");
  const auto line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 2;
  for (int threads : {1, 2}) {
    QifReadOptions o;
    o.threads = threads;
    auto r = ParseQif(text, "big.qif", o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.status().line(), line) << r.status().ToString();
    EXPECT_NE(r.status().message().find("<Compensated> 'maybe'"), std::string::npos) << r.status().ToString();
  }
}

// CR LF line ends with blank lines send libxml2 down its slow text path, which hands the text
// over from a copy (no file offset). Truth: a block parsed from the file is still read once:
// 3 points in a set of count 3; 20 000 points in a large block, each with its own line.
TEST(QifReader, CrLfBlocksWithBlankLinesAreReadOnce) {
  const std::string small = "<MeasuredPointSet id=\"10\" count=\"3\"><Points>\r\n42 0 5\r\n\r\n0 42 5\r\n-42 0 5\r\n"
                            "</Points></MeasuredPointSet>\n";
  auto a = ParseQif(Doc(kMm, kPlaneWhole10, small), "crlf.qif");
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  EXPECT_EQ(a->file.points.size(), 3u);
  std::string big = "<MeasuredPointSet id=\"10\" count=\"20000\"><Points>\r\n\r\n";
  for (int i = 0; i < 20000; ++i) big += std::to_string(i) + " 1 2\r\n" + (i % 997 == 0 ? "\r\n" : "");
  big += "</Points></MeasuredPointSet>\n";
  for (int threads : {1, 2}) {
    QifReadOptions o;
    o.threads = threads;
    auto b = ParseQif(Doc(kMm, kPlaneWhole10, big), "crlf.qif", o);
    ASSERT_TRUE(b.ok()) << b.status().ToString();
    ASSERT_EQ(b->file.points.size(), 20000u);
    EXPECT_EQ(b->file.points.xyz_mm[19999], Eigen::Vector3d(19999, 1, 2));
    EXPECT_EQ(b->file.points.line[1] - b->file.points.line[0], 2u);  // a blank line after the first point
    EXPECT_EQ(b->file.points.line[2] - b->file.points.line[1], 1u);
  }
}

// Little-endian IEEE numbers of `size` bytes, base64.
std::string Binary(const std::vector<double>& v, int size) {
  std::string bytes;
  for (double d : v) {
    std::uint64_t u = size == 8 ? std::bit_cast<std::uint64_t>(d) : std::bit_cast<std::uint32_t>(static_cast<float>(d));
    for (int b = 0; b < size; ++b) bytes.push_back(static_cast<char>((u >> (8 * b)) & 0xFF));
  }
  return EncodeBase64(bytes);
}

// Truth: <BinaryPoints> of doubles and <BinaryNormals> of floats (values exact in float) give
// the points and normals of the text form, the line of the start tag for every point.
TEST(QifReader, BinaryPointsAndNormalsReadAsTheirText) {
  const std::vector<double> xyz = {1.25, 2, 3, 4, 5, 6, 7, 8, -9.5}, ijk = {0, 0, 1, 0, 1, 0, 1, 0, 0};
  const std::string set = "<MeasuredPointSet id=\"10\" count=\"3\">\n<BinaryPoints count=\"9\" sizeElement=\"8\">\n" +
                          Binary(xyz, 8) + "\n</BinaryPoints>\n<BinaryNormals count=\"3\" sizeElement=\"4\">" +
                          Binary(ijk, 4) + "</BinaryNormals>\n</MeasuredPointSet>\n";
  auto r = ParseQif(Doc(kMm, kPlaneWhole10, set), "b.qif");
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const PointSet& ps = r->file.points;
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps.xyz_mm[0], Eigen::Vector3d(1.25, 2, 3));
  EXPECT_EQ(ps.xyz_mm[2], Eigen::Vector3d(7, 8, -9.5));
  EXPECT_EQ(ps.normal[1], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(ps.line, (std::vector<std::size_t>{14, 14, 14}));
  // The other spelling of the element names (NIST's QIF checks): the same points.
  std::string other = set;
  for (auto [from, to] : {std::pair<std::string, std::string>{"BinaryPoints", "PointsBinary"}, {"BinaryNormals", "NormalsBinary"}})
    for (std::size_t at = other.find(from); at != std::string::npos; at = other.find(from)) other.replace(at, from.size(), to);
  auto r2 = ParseQif(Doc(kMm, kPlaneWhole10, other), "b.qif");
  ASSERT_TRUE(r2.ok()) << r2.status().ToString();
  EXPECT_EQ(r2->file.points.xyz_mm, ps.xyz_mm);
  EXPECT_EQ(r2->file.points.normal, ps.normal);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"<BinaryPoints sizeElement=\"3\">AAAA</BinaryPoints>", "expected 8 (64-bit IEEE numbers) or 4"},
      {"<BinaryPoints sizeElement=\"8\">AA*A</BinaryPoints>", "character 3 of its text is not base64"},
      {"<BinaryPoints sizeElement=\"8\">" + Binary({1, 2}, 8) + "</BinaryPoints>", "expected whole x y z triples"},
      {"<BinaryPoints count=\"4\" sizeElement=\"8\">" + Binary(xyz, 8) + "</BinaryPoints>", "expected count to give"},
      {"<BinaryPoints sizeElement=\"8\">" + Binary({1, 2, std::nan("")}, 8) + "</BinaryPoints>", "is not finite"},
      {"<BinaryPoints sizeElement=\"8\"><x/></BinaryPoints>", "<x> inside <BinaryPoints>"},
      {"<BinaryPoints sizeElement=\"8\">AAAAAAAA8D8</BinaryPoints>", "ends inside a group of 4 characters"},
      {"<Points>1 2 3</Points><BinaryPoints sizeElement=\"8\">" + Binary(xyz, 8) + "</BinaryPoints>", "a second list of points"},
      {"<Points>1 2 3</Points><Points>1 2 3</Points>", "a second list of points"},
  };
  for (const auto& [points, expect] : bad) {
    auto e = ParseQif(Doc(kMm, kPlaneWhole10, "<MeasuredPointSet id=\"10\">" + points + "</MeasuredPointSet>\n"), "b.qif");
    ASSERT_FALSE(e.ok()) << points;
    EXPECT_EQ(e.status().line(), 13u) << e.status().ToString();
    EXPECT_NE(e.status().message().find(expect), std::string::npos) << e.status().ToString();
  }
}

struct QifBadCase {
  const char* what;
  std::string text;
  std::size_t line;
  const char* expect;
};

TEST(QifReader, BadFilesSayFileLineAndWhatWasExpected) {
  const std::vector<QifBadCase> cases = {
      {"unclosed", Doc(kMm, kPlaneWhole10, kSet10).substr(0, 300), 0, "malformed XML"},
      {"unknown unit",
       Doc("<FileUnits><PrimaryUnits><LinearUnit><UnitName>furlong</UnitName></LinearUnit></PrimaryUnits>"
           "</FileUnits>\n",
           kPlaneWhole10, kSet10),
       3, "unknown length unit 'furlong'"},
      {"no units", Doc("", kPlaneWhole10, kSet10), 1, "no <FileUnits>"},
      {"set without feature", Doc(kMm, "", kSet10), 12, "belongs to no feature"},
      {"missing set",
       Doc(kMm,
           "<PlaneFeatureMeasurement id=\"3\"><FeatureItemId>1</FeatureItemId>"
           "<PointList n=\"1\"><WholePointSetId>11</WholePointSetId></PointList></PlaneFeatureMeasurement>\n",
           kSet10),
       10, "which the file does not hold"},
      {"bad number", Doc(kMm, kPlaneWhole10, "<MeasuredPointSet id=\"10\"><Points>\n1 2 x\n</Points></MeasuredPointSet>\n"),
       14, "'x' in <Points>"},
      {"not triples", Doc(kMm, kPlaneWhole10, "<MeasuredPointSet id=\"10\"><Points>\n1 2 3\n4 5\n</Points></MeasuredPointSet>\n"),
       15, "ends inside a triple"},
      {"range beyond set",
       Doc(kMm,
           "<PlaneFeatureMeasurement id=\"3\"><FeatureItemId>1</FeatureItemId>"
           "<PointList n=\"1\"><RangePointSetId range=\"2 4\">10</RangePointSetId></PointList></PlaneFeatureMeasurement>\n",
           kSet10),
       10, "expected indices 1..3"},
      {"uncompensated without normals",
       Doc(kMm, kPlaneWhole10,
           "<MeasuredPointSet id=\"10\"><Points>1 2 3</Points><Compensated>false</Compensated>"
           "<ProbeRadius>1</ProbeRadius></MeasuredPointSet>\n"),
       13, "no <Normals>"},
      {"not qif", "<?xml version=\"1.0\"?>\n<html/>\n", 2, "expected <QIFDocument>"},
      {"empty", "", 0, "malformed XML"},
      {"doctype", "<?xml version=\"1.0\"?>\n<!-- c -->\n<!DOCTYPE lol [<!ENTITY a \"aaaa\">]>\n<QIFDocument/>\n", 3,
       "expected no document type declaration"},
  };
  for (const QifBadCase& c : cases) {
    auto r = ParseQif(c.text, "bad.qif");
    ASSERT_FALSE(r.ok()) << c.what;
    EXPECT_EQ(r.status().code(), StatusCode::kParseError) << c.what;
    EXPECT_EQ(r.status().file(), "bad.qif") << c.what;
    if (c.line != 0) {
      EXPECT_EQ(r.status().line(), c.line) << c.what << ": " << r.status().ToString();
    }
    EXPECT_GT(r.status().line(), 0u) << c.what;
    EXPECT_NE(r.status().message().find(c.expect), std::string::npos) << c.what << ": " << r.status().ToString();
  }
}

}  // namespace
}  // namespace tpcal::pipeline
