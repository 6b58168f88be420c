// The nominal B-rep of every test piece carries every probing-plan point on its boundary with the
// normal pointing out of the material; STEP export writes a readable file.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "testpieces/brep.h"
#include "testpieces/probing_plan.h"

namespace tpcal::testpieces {
namespace {

constexpr double kOnSurface_mm = 1e-6;  // the brief's criterion (OCC distances are ~1e-12 here)
constexpr double kStep_mm = 0.01;       // p +- 0.01 mm n must be outside / inside

struct NamedConfig {
  std::string name;
  PieceConfig config;
};

std::vector<NamedConfig> AllPieces() {
  std::vector<NamedConfig> out;
  out.push_back({"turning", PieceConfig{}});
  PieceConfig inner;
  TurningPieceParams p;
  p.groove_inner_wall_pass = true;
  inner.params = p;
  out.push_back({"turning_inner_wall", inner});
  for (double size : {320.0, 160.0}) {
    PieceConfig c;
    c.params = ContourPieceParams::ForSize(size);
    out.push_back({"m1_" + std::to_string(static_cast<int>(size)), c});
  }
  PieceConfig m2;
  m2.params = FaceMillingPieceParams{};
  out.push_back({"m2", m2});
  PieceConfig cone;
  cone.params = ConeFrustumParams{};
  out.push_back({"cone", cone});
  PieceConfig two_cones;
  ConeFrustumParams tc;
  tc.base_size_mm = 380;
  tc.second_cone_offset_mm = 130;
  two_cones.params = tc;
  out.push_back({"cone_two_cones", two_cones});
  PieceConfig three_cones;  // samples/testpieces/cone_frustum_enriched.yaml's geometry
  tc.third_cone_offset_mm = 130;
  three_cones.params = tc;
  out.push_back({"cone_three_cones", three_cones});
  return out;
}

kinematics::MachineModel BrepAcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

TEST(Brep, EveryPlanPointLiesOnTheSolidWithAnOutwardNormal) {
  for (const NamedConfig& nc : AllPieces()) {
    SCOPED_TRACE(nc.name);
    auto piece = MakeTestPiece(nc.config, BrepAcTable());
    ASSERT_TRUE(piece.ok()) << piece.status().ToString();
    for (const ProbingOptions& density : {ProbingOptions::Paper(), ProbingOptions::Dense()}) {
      auto plan = MakeProbingPlan(*piece, density);
      ASSERT_TRUE(plan.ok()) << plan.status().ToString();
      std::vector<Eigen::Vector3d> pts, normals;
      for (const auto& q : plan->points) {
        pts.push_back(q.point_part_mm);
        normals.push_back(q.normal_part);
      }
      auto checks = CheckPointsOnBrep(*piece, pts, normals, kStep_mm, kOnSurface_mm);
      ASSERT_TRUE(checks.ok()) << checks.status().ToString();
      int bad = 0;
      for (std::size_t i = 0; i < checks->size(); ++i) {
        const auto& c = (*checks)[i];
        if (!c.ok && ++bad <= 5) {
          ADD_FAILURE() << plan->points[i].feature << " point " << i << ": distance " << c.distance_mm
                        << " mm, outside(+n) " << c.outside_plus << ", inside(-n) " << c.inside_minus;
        }
      }
      EXPECT_EQ(bad, 0) << "of " << checks->size() << " points";
    }
  }
}

TEST(Brep, CheckDetectsPointsOffTheSurfaceAndInwardNormals) {
  auto piece = MakeTestPiece(PieceConfig{}, BrepAcTable());
  ASSERT_TRUE(piece.ok());
  // A point on S1 with its normal flipped, and a point 0.1 mm outside S1.
  const Eigen::Vector3d on(160, 0, 400.702), n(1, 0, 0);
  auto checks = CheckPointsOnBrep(*piece, {on, on, on + 0.1 * n}, {n, -n, n});
  ASSERT_TRUE(checks.ok());
  EXPECT_TRUE((*checks)[0].ok);
  EXPECT_FALSE((*checks)[1].ok);
  EXPECT_FALSE((*checks)[2].ok);
  EXPECT_NEAR((*checks)[2].distance_mm, 0.1, 1e-9);
}

TEST(Brep, SolidsHaveTheDesignedSizeAndStepFilesAreWritten) {
  for (const NamedConfig& nc : AllPieces()) {
    SCOPED_TRACE(nc.name);
    auto piece = MakeTestPiece(nc.config, BrepAcTable());
    ASSERT_TRUE(piece.ok());
    auto s = SummarizeBrep(*piece);
    ASSERT_TRUE(s.ok()) << s.status().ToString();
    EXPECT_GT(s->volume_mm3, 0.0);
    EXPECT_GT(s->num_faces, 5);
    const std::string path = ::testing::TempDir() + "/tpcal_" + nc.name + ".step";
    ASSERT_TRUE(WriteStep(*piece, path).ok());
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first.rfind("ISO-10303-21", 0), 0u) << first;
    std::remove(path.c_str());
  }
  // Turning piece: bounding box = base flange and top face, volume of the revolved profile.
  auto piece = MakeTestPiece(PieceConfig{}, BrepAcTable());
  ASSERT_TRUE(piece.ok());
  auto s = SummarizeBrep(*piece);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->box_max_mm.z(), 410.702, 1e-6);
  EXPECT_NEAR(s->box_min_mm.z(), 115.702, 1e-6);
  EXPECT_NEAR(s->box_max_mm.x(), 195.0, 1e-6);
  EXPECT_FALSE(WriteStep(*piece, "/nonexistent-dir/x.step").ok());
}

}  // namespace
}  // namespace tpcal::testpieces
