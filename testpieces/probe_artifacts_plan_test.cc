// The probe-artifacts plan (testpieces/probe_artifacts_plan.h) on the nominal A/C table with seed
// 000's three columns, and small hand-made layouts whose answer is known.
//
// Truths: kinematics/conventions.h (A/C table: machine_from_part = RotX(-A) RotZ(-C); at A = -90
// deg part +Z points along machine -Y, so part -Y points along machine -Z); the geometry of the
// layouts (gaps between columns against clearance + 2 r). Tolerances: kGeomTol_mm = 1e-9 (one
// rigid transform and its inverse of points within 200 mm, double precision); kUnitTol = 1e-12.
#include "testpieces/probe_artifacts_plan.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

using kinematics::BoxFace;

constexpr double kGeomTol_mm = 1e-9;  // transform round trip of points within 200 mm
constexpr double kUnitTol = 1e-12;    // rotation of a unit vector

kinematics::MachineModel AcTable() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  return *m;
}

kinematics::ArtifactSet TwoColumnsAt(double dx_mm) {
  kinematics::ArtifactSet s;
  kinematics::ArtifactBox a, b;
  a.name = "1";
  b.name = "2";
  b.base_centre_mm = Eigen::Vector3d(dx_mm, 0.0, 0.0);
  s.boxes = {a, b};
  return s;
}

const SkippedTouch* FindSkipped(const ProbeArtifactsPlan& plan, int artifact, BoxFace face) {
  for (const SkippedTouch& s : plan.skipped)
    if (s.artifact == artifact && s.face == face) return &s;
  return nullptr;
}

TEST(ProbeArtifactsPlan, DefaultIsSeed000sFourTiltsTimesSixCPositions) {
  auto plan = MakeProbeArtifactsPlan(AcTable(), kinematics::Seed000Artifacts());
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->poses.size(), 24u);  // A 0, -30, -60, -90 x C 0..300 step 60
  EXPECT_EQ(plan->poses[7].a_rad, DegToRad(-30.0));
  EXPECT_EQ(plan->poses[7].c_rad, DegToRad(60.0));
  EXPECT_EQ(plan->poses[23].a_rad, DegToRad(-90.0));
  EXPECT_EQ(plan->poses[23].c_rad, DegToRad(300.0));
  EXPECT_EQ(plan->probe_radius_mm, 3.0);
  // Every face of every box at every pose is either planned or skipped, once.
  EXPECT_EQ(plan->touches.size() + plan->skipped.size(), 24u * 3u * 5u);
}

// Upright columns 200 mm / 141 mm apart: nothing is in the way of any of the 15 faces at any C.
TEST(ProbeArtifactsPlan, AtZeroTiltAllFifteenTouchesArePlannedAtEveryC) {
  auto plan = MakeProbeArtifactsPlan(AcTable(), kinematics::Seed000Artifacts(), {.a_deg = {0.0}});
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->poses.size(), 6u);
  EXPECT_EQ(plan->touches.size(), 6u * 15u);
  EXPECT_TRUE(plan->skipped.empty());
  // Order: pose by pose, box by box, faces in kBoxFaces order.
  EXPECT_EQ(plan->touches[0].face, BoxFace::kPlusX);
  EXPECT_EQ(plan->touches[4].face, BoxFace::kPlusZ);
  EXPECT_EQ(plan->touches[5].artifact, 1);
  EXPECT_EQ(plan->touches[15].rotary.c_rad, DegToRad(60.0));
}

// A = -90, C = 0: part -Y points along machine -Z (conventions.h), so each column's -Y face is
// skipped as facing down; everything else is reachable (the lying columns are 200 / 141 mm apart).
TEST(ProbeArtifactsPlan, AtMinusNinetyTheFacesPointingDownAreSkipped) {
  auto plan =
      MakeProbeArtifactsPlan(AcTable(), kinematics::Seed000Artifacts(), {.a_deg = {-90.0}, .c_step_deg = 360.0});
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->skipped.size(), 3u);
  for (int box = 0; box < 3; ++box) {
    const SkippedTouch* s = FindSkipped(*plan, box, BoxFace::kMinusY);
    ASSERT_NE(s, nullptr) << "box " << box;
    EXPECT_EQ(s->reason, "faces down");
  }
  EXPECT_EQ(plan->touches.size(), 12u);
}

// A = -90, C = 60 (worked by hand from machine = RotX(90) RotZ(-60) p_part): part +X and -Y
// point down (n_z = -0.866, -0.5); the columns lie along machine -Y with column 3's axis at
// machine (x, z) = (86.6, 50) above column 1's at (50, -86.6). Column 1's +Y face starts its
// vertical corridor at machine x = 76.9, which passes through column 3 grown by 3 mm; nothing
// else is in the way.
TEST(ProbeArtifactsPlan, AtMinusNinetyCSixtyColumnThreeHangsOverColumnOnesYSide) {
  auto c60 = MakeProbeArtifactsPlan(AcTable(), kinematics::Seed000Artifacts(), {.a_deg = {-90.0}, .c_step_deg = 60.0});
  ASSERT_TRUE(c60.ok()) << c60.status().ToString();
  std::vector<SkippedTouch> at60;
  for (const SkippedTouch& s : c60->skipped)
    if (s.rotary.c_rad == DegToRad(60.0)) at60.push_back(s);
  ASSERT_EQ(at60.size(), 7u);
  for (const SkippedTouch& s : at60) {
    if (s.face == BoxFace::kPlusX || s.face == BoxFace::kMinusY) {
      EXPECT_EQ(s.reason, "faces down");
    } else {
      EXPECT_EQ(s.artifact, 0);
      EXPECT_EQ(s.face, BoxFace::kPlusY);
      EXPECT_EQ(s.reason, "corridor meets artifact 3");
    }
  }
}

// Over the default plan: "faces down" exactly when the machine-frame normal has n_z < -0.1.
TEST(ProbeArtifactsPlan, FacesDownIsDecidedByTheMachineFrameNormal) {
  const kinematics::MachineModel m = AcTable();
  auto plan = MakeProbeArtifactsPlan(m, kinematics::Seed000Artifacts());
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  int down = 0;
  for (const SkippedTouch& s : plan->skipped) {
    const Eigen::Vector3d n_m = kinematics::NominalMachineFromTable(m, s.rotary).linear() *
                                kinematics::FaceOf(plan->artifacts.boxes[s.artifact], s.face).normal;
    EXPECT_EQ(s.reason == "faces down", n_m.z() < -0.1) << s.reason << " n_z " << n_m.z();
    down += s.reason == "faces down";
  }
  for (const PlannedTouch& t : plan->touches) EXPECT_GE(-t.approach.z(), -0.1);
  // A = -30 and -60 tip part -Y down (n_z = -sin 30, -sin 60 at C = 0, and the C turns bring
  // the other sides down in turn); A = 0 never. At least one face per box is down at every
  // tilted pose.
  EXPECT_GE(down, 3 * 18);
}

// Two columns 30 mm wide with a 10 mm gap: the start point (13 mm off the face) lies inside the
// neighbour grown by r = 3 mm (which begins 7 mm off the face). With a 17 mm gap (> 13 + 3) both
// facing sides are reachable.
TEST(ProbeArtifactsPlan, AColumnRightNextToAnotherBlocksTheFacingSides) {
  const kinematics::MachineModel m = AcTable();
  const ProbeArtifactsPlanOptions o{.a_deg = {0.0}, .c_step_deg = 360.0};
  auto near = MakeProbeArtifactsPlan(m, TwoColumnsAt(40.0), o);
  ASSERT_TRUE(near.ok()) << near.status().ToString();
  ASSERT_EQ(near->skipped.size(), 2u);
  const SkippedTouch* a = FindSkipped(*near, 0, BoxFace::kPlusX);
  const SkippedTouch* b = FindSkipped(*near, 1, BoxFace::kMinusX);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(a->reason, "corridor meets artifact 2");
  EXPECT_EQ(b->reason, "corridor meets artifact 1");
  EXPECT_EQ(near->touches.size(), 8u);

  auto apart = MakeProbeArtifactsPlan(m, TwoColumnsAt(47.0), o);
  ASSERT_TRUE(apart.ok()) << apart.status().ToString();
  EXPECT_TRUE(apart->skipped.empty());
  EXPECT_EQ(apart->touches.size(), 10u);
}

// A 4 mm high plate: the centres of its sides are 2 mm above the table, closer than the stylus
// radius; its top (4 mm up) is reachable.
TEST(ProbeArtifactsPlan, ASideCloserToTheTableThanTheStylusRadiusMeetsTheTable) {
  kinematics::ArtifactSet s;
  kinematics::ArtifactBox plate;
  plate.name = "P";
  plate.size_mm = Eigen::Vector3d(30.0, 30.0, 4.0);
  s.boxes = {plate};
  auto plan = MakeProbeArtifactsPlan(AcTable(), s, {.a_deg = {0.0}, .c_step_deg = 360.0});
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->skipped.size(), 4u);
  for (const SkippedTouch& k : plan->skipped) EXPECT_EQ(k.reason, "corridor meets the table");
  ASSERT_EQ(plan->touches.size(), 1u);
  EXPECT_EQ(plan->touches[0].face, BoxFace::kPlusZ);
}

// Every planned contact, mapped back to the part frame, is the face centre on the face's plane;
// the approach is unit, equals -(machine-frame normal) and kinematics::NominalApproach.
TEST(ProbeArtifactsPlan, ContactsLieOnTheFacesAndApproachesAreTheInwardNormals) {
  const kinematics::MachineModel m = AcTable();
  auto plan = MakeProbeArtifactsPlan(m, kinematics::Seed000Artifacts());
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_FALSE(plan->touches.empty());
  for (const PlannedTouch& t : plan->touches) {
    const kinematics::FaceGeometry g = kinematics::FaceOf(plan->artifacts.boxes[t.artifact], t.face);
    const Rigid3 machine_from_table = kinematics::NominalMachineFromTable(m, t.rotary);
    const Eigen::Vector3d p_part = machine_from_table.inverse() * t.contact_mm;
    EXPECT_NEAR(g.normal.dot(p_part), g.offset_mm(), kGeomTol_mm);
    EXPECT_LT((p_part - g.centre_mm).norm(), kGeomTol_mm);
    EXPECT_LT((t.target_part_mm - g.centre_mm).norm(), kGeomTol_mm);
    EXPECT_NEAR(t.approach.norm(), 1.0, kUnitTol);
    EXPECT_LT((t.approach + machine_from_table.linear() * g.normal).norm(), kUnitTol);
    EXPECT_LT((t.approach - kinematics::NominalApproach(m, t.rotary, g)).norm(), kUnitTol);
  }
}

TEST(ProbeArtifactsPlan, BadInputIsNamed) {
  const kinematics::MachineModel m = AcTable();
  const kinematics::ArtifactSet seed = kinematics::Seed000Artifacts();
  auto bc_machine = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  ASSERT_TRUE(bc_machine.ok());
  auto bc = MakeProbeArtifactsPlan(*bc_machine, seed);
  ASSERT_FALSE(bc.ok());
  EXPECT_NE(bc.status().message().find("expected ac_table"), std::string::npos);
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, seed, {.a_deg = {}}).ok());
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, seed, {.c_step_deg = 0.0}).ok());
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, seed, {.c_step_deg = 400.0}).ok());
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, seed, {.probe_radius_mm = 0.0}).ok());
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, seed, {.probe_radius_mm = 3.0, .clearance_mm = -1.0}).ok());
  EXPECT_FALSE(MakeProbeArtifactsPlan(m, kinematics::ArtifactSet{}, {}).ok());
  kinematics::AxisLink* a_link = nullptr;
  kinematics::MachineModel limited = m;
  for (kinematics::AxisLink& l : limited.links)
    if (l.axis == kinematics::Axis::kA) a_link = &l;
  ASSERT_NE(a_link, nullptr);
  a_link->min_position = DegToRad(-60.0);
  auto stroke = MakeProbeArtifactsPlan(limited, seed);
  ASSERT_FALSE(stroke.ok());
  EXPECT_NE(stroke.status().message().find("A -90"), std::string::npos) << stroke.status().ToString();
}

}  // namespace
}  // namespace tpcal::testpieces
