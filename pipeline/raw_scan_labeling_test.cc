



// Raw-scan labelling on simulated scans of the turning test piece (truth: the simulator's labels
// and placement): random, identity and upside-down placements, no normals, and garbage input.
#include "pipeline/raw_scan_labeling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <numbers>
#include <random>

#include "kinematics/error_state.h"
#include "pipeline/io/point_io.h"
#include "pipeline/piece_loader.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::pipeline {
namespace {

// Placement recovered to well inside the labelling tolerance (0.2 mm): machine errors of tens of
// um and 0.5 um noise only.
constexpr double kPlacementTol_mm = 0.05;
constexpr double kPlacementTol_rad = 2e-4;
constexpr double kMinCorrectFraction = 0.99;  // the acceptance figure

struct Simulated {
  testpieces::TestPiece piece;
  PointSet scan_datum;     // points with true labels, nominal datum frame (no placement)
  Rigid3 datum_from_part;  // simulator's cmm_from_part without placement
};

// A small scan (ASan runs the suite at -O0): 32 points per circle, 3 levels per face, 8 points
// on 2 levels per hole; the seed 002 Table 2 errors scaled to tens of um; 0.5 um noise.
const Simulated& Scan() {
  static const Simulated s = [] {
    auto setup = LoadPiece({.testpiece = "turning"});
    EXPECT_TRUE(setup.ok()) << setup.status().ToString();
    kinematics::ErrorState errors(setup->machine);
    EXPECT_TRUE(errors.SetParameter(setup->machine, "dx_CR(0)", 0.030).ok());     // mm
    EXPECT_TRUE(errors.SetParameter(setup->machine, "dy_AR(-90)", 0.040).ok());   // mm
    EXPECT_TRUE(errors.SetParameter(setup->machine, "alpha_ZY", 40e-6).ok());     // rad
    testpieces::PieceSimOptions o;
    o.noise_um = 0.5;
    o.seed = 7;
    testpieces::ProbingOptions d;
    d.points_per_circle = 32;
    d.levels_per_face = 3;
    d.points_per_hole = 8;
    d.levels_per_hole = 2;
    o.density = d;
    auto sim = testpieces::SimulatePiece(setup->piece, setup->machine, errors, o);
    EXPECT_TRUE(sim.ok()) << sim.status().ToString();
    return Simulated{setup->piece, sim->points, sim->truth.cmm_from_part};
  }();
  return s;
}

PointSet Placed(const PointSet& in, const Rigid3& cmm_from_datum, bool keep_labels = false) {
  PointSet out = in;
  out.source = "placed_scan.csv";
  for (std::size_t i = 0; i < out.size(); ++i) {
    out.xyz_mm[i] = cmm_from_datum * in.xyz_mm[i];
    if (out.has_normals()) out.normal[i] = cmm_from_datum.linear() * in.normal[i];
  }
  if (!keep_labels) {
    out.feature.assign(out.size(), PointSet::kUnlabelled);
    out.feature_names.clear();
  }
  return out;
}

// Fraction of points given their true feature; checks the recovered placement too.
void ExpectRecovered(const Rigid3& cmm_from_datum, bool with_normals = true) {
  const Simulated& s = Scan();
  PointSet scan = Placed(s.scan_datum, cmm_from_datum);
  if (!with_normals) scan.normal.clear();
  auto r = LabelRawScan(s.piece, scan);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::size_t correct = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const std::string& truth = s.scan_datum.feature_names[static_cast<std::size_t>(s.scan_datum.feature[i])];
    const int f = r->piece_feature[i];
    if (f != PointSet::kUnlabelled && s.piece.features[static_cast<std::size_t>(f)].name == truth) ++correct;
  }
  const double fraction = static_cast<double>(correct) / static_cast<double>(scan.size());
  EXPECT_GE(fraction, kMinCorrectFraction) << r->BriefReport();
  ::testing::Test::RecordProperty("correct_fraction", std::to_string(fraction));
  EXPECT_EQ(r->symmetry_order, 16) << r->message;  // 16 holes
  // part_from_cmm = part_from_datum * datum_from_cmm.
  const Rigid3 expected = s.datum_from_part.inverse() * cmm_from_datum.inverse();
  const Rigid3 diff = expected.inverse() * r->part_from_cmm;
  EXPECT_LT(diff.translation().norm(), kPlacementTol_mm) << diff.matrix();
  EXPECT_LT(Eigen::AngleAxisd(Eigen::Matrix3d(diff.linear())).angle(), kPlacementTol_rad) << diff.matrix();
  // The labelled set holds exactly the labelled points, under the piece's names.
  EXPECT_EQ(r->labelled.size(), r->num_points - r->num_rejected);
  std::size_t counted = 0;
  for (const auto& c : r->counts) counted += c.points;
  EXPECT_EQ(counted, r->labelled.size());
  EXPECT_LT(r->rms_distance_um, 100.0);
}

TEST(RawScanLabeling, IdentityPlacement) { ExpectRecovered(Rigid3::Identity()); }

TEST(RawScanLabeling, UpsideDownPlacement) {
  // 180 deg about the CMM X axis: the part's top faces down, plus an offset.
  ExpectRecovered(MakeRigid(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                            Eigen::Vector3d(250.0, -40.0, 600.0)));
}

TEST(RawScanLabeling, RandomPlacements) {
  std::mt19937_64 rng(2026);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-300.0, 300.0);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Quaterniond q{g(rng), g(rng), g(rng), g(rng)};
    SCOPED_TRACE(trial);
    ExpectRecovered(MakeRigid(q.normalized().toRotationMatrix(), Eigen::Vector3d{u(rng), u(rng), u(rng)}));
  }
}

TEST(RawScanLabeling, ScanWithoutNormals) {
  ExpectRecovered(MakeRigid(RotY(0.7) * RotZ(-1.9), Eigen::Vector3d(10.0, 20.0, -30.0)), /*with_normals=*/false);
}

TEST(RawScanLabeling, PointsOffThePieceAreRejected) {
  const Simulated& s = Scan();
  PointSet scan = Placed(s.scan_datum, Rigid3::Identity());
  const std::size_t n_true = scan.size();
  // 1 % stray points 1 to 3 mm off the surfaces (fixture, dust): never labelled.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> off(1.0, 3.0);
  for (std::size_t i = 0; i < n_true; i += 100) {
    scan.xyz_mm.push_back(scan.xyz_mm[i] + off(rng) * scan.normal[i]);
    scan.normal.push_back(scan.normal[i]);
    scan.feature.push_back(PointSet::kUnlabelled);
  }
  auto r = LabelRawScan(s.piece, scan);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  for (std::size_t i = n_true; i < scan.size(); ++i) EXPECT_EQ(r->piece_feature[i], PointSet::kUnlabelled) << i;
  EXPECT_GE(r->num_rejected, scan.size() - n_true);
}

// Rows in random order (a scanner, not a CMM program): the file order no longer tells H1 from the
// other 15 holes. Every point still gets its feature up to that symmetry: the turned faces and
// the groove exactly, and the points of each physical hole one common hole label, a different
// one per hole (a rotation of the true labels).
// The points of `in` (with their normals and labels) in a random order (fixed seed).
PointSet Shuffled(const PointSet& in, std::uint64_t seed) {
  std::vector<std::size_t> order(in.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  PointSet out = in;
  for (std::size_t i = 0; i < order.size(); ++i) {
    out.xyz_mm[i] = in.xyz_mm[order[i]];
    out.normal[i] = in.normal[order[i]];
    out.feature[i] = in.feature[order[i]];
  }
  return out;
}

TEST(RawScanLabeling, ShuffledScanIsLabelledUpToTheHoleSymmetry) {
  const Simulated& s = Scan();
  const PointSet shuffled = Shuffled(s.scan_datum, 17);
  PointSet placed = Placed(shuffled, MakeRigid(RotY(2.5) * RotZ(1.1), Eigen::Vector3d(40.0, -70.0, 15.0)));
  auto r = LabelRawScan(s.piece, placed);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::map<std::string, std::set<std::string>> given_for_true_hole;  // true hole -> labels given
  std::set<std::string> hole_labels_given;
  std::size_t non_hole = 0, non_hole_correct = 0;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const std::string& truth = shuffled.feature_names[static_cast<std::size_t>(shuffled.feature[i])];
    const int f = r->piece_feature[i];
    const std::string given = f == PointSet::kUnlabelled ? "" : s.piece.features[static_cast<std::size_t>(f)].name;
    if (truth[0] == 'H') {
      given_for_true_hole[truth].insert(given);
      hole_labels_given.insert(given);
    } else {
      ++non_hole;
      if (given == truth) ++non_hole_correct;
    }
  }
  EXPECT_GE(static_cast<double>(non_hole_correct) / static_cast<double>(non_hole), kMinCorrectFraction);
  EXPECT_EQ(given_for_true_hole.size(), 16u);
  for (const auto& [hole, given] : given_for_true_hole) EXPECT_EQ(given.size(), 1u) << hole;
  EXPECT_EQ(hole_labels_given.size(), 16u);  // one distinct hole label per hole
  EXPECT_EQ(hole_labels_given.count(""), 0u);
}

// The same shuffled scan with an anchor: H1's approximate centre in the scan frame (its true
// centroid moved by 5 mm, a fraction of the 55 mm between neighbouring holes). Truth: the
// simulator's labels; every hole point gets its own hole's name, and a wrong anchor name is a
// clear error.
TEST(RawScanLabeling, AnchorResolvesTheHoleSymmetryOfAShuffledScan) {
  const Simulated& s = Scan();
  const PointSet shuffled = Shuffled(s.scan_datum, 23);
  const Rigid3 cmm_from_datum = MakeRigid(RotX(0.7) * RotZ(-2.2), Eigen::Vector3d(-25.0, 60.0, 5.0));
  PointSet placed = Placed(shuffled, cmm_from_datum);
  Eigen::Vector3d h1 = Eigen::Vector3d::Zero();
  int m = 0;
  for (std::size_t i = 0; i < placed.size(); ++i)
    if (shuffled.feature_names[static_cast<std::size_t>(shuffled.feature[i])] == "H1") h1 += placed.xyz_mm[i], ++m;
  ASSERT_GT(m, 0);
  h1 /= m;
  RawScanLabelingOptions o;
  o.anchor_feature = "H1";
  o.anchor_near_mm = h1 + Eigen::Vector3d(3.0, -4.0, 0.0);
  auto r = LabelRawScan(s.piece, placed, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->symmetry_resolved_by, "anchor H1");
  std::size_t holes = 0, correct = 0;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const std::string& truth = shuffled.feature_names[static_cast<std::size_t>(shuffled.feature[i])];
    if (truth[0] != 'H') continue;
    ++holes;
    const int f = r->piece_feature[i];
    if (f != PointSet::kUnlabelled && s.piece.features[static_cast<std::size_t>(f)].name == truth) ++correct;
  }
  EXPECT_GE(static_cast<double>(correct) / static_cast<double>(holes), kMinCorrectFraction) << r->message;
  o.anchor_feature = "H99";
  auto bad = LabelRawScan(s.piece, placed, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("H99"), std::string::npos) << bad.status().ToString();
}

// A real scan also covers surfaces the piece does not inspect: here 20 % more points on the top
// face (between the groove and the holes) and 10 % on a fixture plate beside the base, off to
// one side. They are rejected; the features' points are labelled as without them.
TEST(RawScanLabeling, UninspectedSurfacesAreRejected) {
  const Simulated& s = Scan();
  const auto& params = std::get<testpieces::TurningPieceParams>(s.piece.config.params);
  PointSet scan = s.scan_datum;
  const std::size_t n_true = scan.size();
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi), ring(121.0, 133.0);
  std::uniform_real_distribution<double> plate_x(200.0, 260.0), plate_y(-30.0, 30.0);
  const Eigen::Vector3d up_datum = s.datum_from_part.linear() * Eigen::Vector3d::UnitZ();
  auto add = [&](const Eigen::Vector3d& p_part) {
    scan.xyz_mm.push_back(s.datum_from_part * p_part);
    scan.normal.push_back(up_datum);
    scan.feature.push_back(PointSet::kUnlabelled);
  };
  for (std::size_t i = 0; i < n_true / 5; ++i) {
    const double a = angle(rng), r = ring(rng);
    add({r * std::cos(a), r * std::sin(a), params.top_z_mm()});
  }
  for (std::size_t i = 0; i < n_true / 10; ++i) add({plate_x(rng), plate_y(rng), params.base_bottom_z_mm});
  const Rigid3 cmm_from_datum = MakeRigid(RotX(2.2) * RotZ(0.4), Eigen::Vector3d(-120.0, 35.0, 80.0));
  PointSet placed = Placed(scan, cmm_from_datum);
  auto r = LabelRawScan(s.piece, placed);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::size_t correct = 0, clutter_labelled = 0;
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const int f = r->piece_feature[i];
    if (i >= n_true) {
      if (f != PointSet::kUnlabelled) ++clutter_labelled;
      continue;
    }
    if (f != PointSet::kUnlabelled && s.piece.features[static_cast<std::size_t>(f)].name ==
                                          s.scan_datum.feature_names[static_cast<std::size_t>(s.scan_datum.feature[i])])
      ++correct;
  }
  EXPECT_GE(static_cast<double>(correct) / static_cast<double>(n_true), kMinCorrectFraction) << r->BriefReport();
  EXPECT_EQ(clutter_labelled, 0u) << r->BriefReport();
}

TEST(RawScanLabeling, RandomPointsAreAClearError) {
  const Simulated& s = Scan();
  PointSet garbage;
  garbage.source = "garbage_scan.csv";
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-200.0, 200.0);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    garbage.xyz_mm.push_back(Eigen::Vector3d{u(rng), u(rng), u(rng)});
    garbage.normal.push_back(Eigen::Vector3d{g(rng), g(rng), g(rng)}.normalized());
    garbage.feature.push_back(PointSet::kUnlabelled);
  }
  auto r = LabelRawScan(s.piece, garbage);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kNotConverged);
  EXPECT_EQ(r.status().file(), "garbage_scan.csv");
  EXPECT_NE(r.status().message().find("registration"), std::string::npos) << r.status().ToString();
  ::testing::Test::RecordProperty("message", r.status().ToString());
}

TEST(RawScanLabeling, TooFewPoints) {
  const Simulated& s = Scan();
  PointSet few = Placed(s.scan_datum, Rigid3::Identity());
  few.xyz_mm.resize(10);
  few.normal.resize(10);
  few.feature.resize(10);
  auto r = LabelRawScan(s.piece, few);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kTooFewPoints);
}

TEST(RawScanLabeling, OptionsAreValidated) {
  RawScanLabelingOptions o;
  EXPECT_TRUE(o.Validate().ok());
  o.label_tolerance_mm = 0.0;
  EXPECT_EQ(o.Validate().code(), StatusCode::kInvalidArgument);
}

// The other bundled samples with their labels removed: the labelling gives back the lab's labels.
class RawScanBundledSample : public ::testing::TestWithParam<const char*> {};

TEST_P(RawScanBundledSample, LabelsComeBack) {
  const std::string dir = std::string(TPCAL_SOURCE_DIR) + "/samples/";
  const std::string name = GetParam();
  auto file = ReadPoints(dir + name + "/cmm_points.csv");
  ASSERT_TRUE(file.ok()) << file.status().ToString();
  auto setup = LoadPiece({.testpiece = name == "m1" ? "iso10791_m1" : "turning"});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  PointSet scan = *file;
  scan.feature.assign(scan.size(), PointSet::kUnlabelled);
  auto r = LabelRawScan(setup->piece, scan);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::size_t correct = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const int f = r->piece_feature[i];
    if (f != PointSet::kUnlabelled && setup->piece.features[static_cast<std::size_t>(f)].name ==
                                          file->feature_names[static_cast<std::size_t>(file->feature[i])])
      ++correct;
  }
  const double fraction = static_cast<double>(correct) / static_cast<double>(scan.size());
  ::testing::Test::RecordProperty("correct_fraction", std::to_string(fraction));
  ::testing::Test::RecordProperty("labelling", r->BriefReport() + " | " + r->message);
  EXPECT_GE(fraction, kMinCorrectFraction) << r->BriefReport() << "\n" << r->message;
}

// Every kind of test piece: its default probing plan, simulated without machine errors in a
// random placement (any orientation), labels stripped, is labelled as simulated.
class RawScanEveryPiece : public ::testing::TestWithParam<const char*> {};

TEST_P(RawScanEveryPiece, DefaultPlanInRandomPlacement) {
  auto setup = LoadPiece({.testpiece = GetParam()});
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  kinematics::ErrorState errors(setup->machine);
  testpieces::PieceSimOptions o;
  o.noise_um = 0.5;
  o.seed = 23;
  o.random_placement = true;
  auto sim = testpieces::SimulatePiece(setup->piece, setup->machine, errors, o);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  PointSet scan = sim->points;
  scan.feature.assign(scan.size(), PointSet::kUnlabelled);
  auto r = LabelRawScan(setup->piece, scan);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  std::size_t correct = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const int f = r->piece_feature[i];
    if (f != PointSet::kUnlabelled && setup->piece.features[static_cast<std::size_t>(f)].name ==
                                          sim->points.feature_names[static_cast<std::size_t>(sim->points.feature[i])])
      ++correct;
  }
  const double fraction = static_cast<double>(correct) / static_cast<double>(scan.size());
  ::testing::Test::RecordProperty("correct_fraction", std::to_string(fraction));
  ::testing::Test::RecordProperty("labelling", r->BriefReport() + " | " + r->message);
  EXPECT_GE(fraction, kMinCorrectFraction) << r->BriefReport() << "\n" << r->message;
}

INSTANTIATE_TEST_SUITE_P(RawScanLabeling, RawScanEveryPiece,
                         ::testing::Values("turning", "iso10791_m1", "iso10791_m2", "cone_frustum"));

INSTANTIATE_TEST_SUITE_P(RawScanLabeling, RawScanBundledSample, ::testing::Values("turning", "m1"));

}  // namespace
}  // namespace tpcal::pipeline
