// The ball-bar program (gcode/ballbar_program.h) on the nominal B-head / C-table machine of seed
// 003: a C-table radial installation (C 0..360 every 20 deg), a B-head tangential one (B 0..-100
// every 5 deg) and ISO 230-4 circles in XY, ZX and YZ.
//
// Truth: kinematics::BallbarCommand (the nominal commands) and the bar geometry: on the nominal
// machine every commanded point of the circle arcs keeps the tool ball at the nominal length from
// the workpiece ball (kinematics::BallbarLengthMm with zero errors). Tolerances: the programs carry
// 4 decimals (0.05 um rounding), 1e-4 mm; the IR itself is exact to 1e-9 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>

#include "core/units.h"
#include "gcode/ballbar_program.h"
#include "gcode/dialect_check.h"
#include "gcode/internal/test_support.h"
#include "gcode/rs274_canon.h"
#include "kinematics/error_state.h"

namespace tpcal::gcode {
namespace {

struct BarCase {
  kinematics::MachineModel machine;
  std::vector<BallbarProgramTest> tests;
};

kinematics::BallbarInstallation BarCircleInstallation(const std::string& name, kinematics::BallbarPlane plane) {
  kinematics::BallbarInstallation i;
  i.name = name;
  i.kind = kinematics::BallbarKind::kCircle;
  i.plane = plane;
  i.workpiece_ball_in_part_mm = Eigen::Vector3d(0.0, 0.0, 200.0);
  i.nominal_length_mm = 100.0;
  return i;
}

BarCase SeedBarCase() {
  BarCase c;
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBheadCtable);
  EXPECT_TRUE(m.ok());
  c.machine = *m;
  kinematics::BallbarInstallation radial;
  radial.name = "C_radial";
  radial.kind = kinematics::BallbarKind::kRadial;
  radial.axis = kinematics::Axis::kC;
  radial.workpiece_ball_in_part_mm = Eigen::Vector3d(100.0, 0.0, 50.0);
  radial.nominal_length_mm = 150.0;
  radial.hold_deg = {{kinematics::Axis::kB, 0.0}};
  kinematics::BallbarInstallation tangential;
  tangential.name = "B_tangential";
  tangential.kind = kinematics::BallbarKind::kTangential;
  tangential.axis = kinematics::Axis::kB;
  tangential.workpiece_ball_in_part_mm = Eigen::Vector3d(-150.0, 0.0, 0.0);
  tangential.nominal_length_mm = 150.0;
  tangential.sense = -1;
  std::vector<double> c_deg, b_deg;
  for (int k = 0; k <= 18; ++k) c_deg.push_back(20.0 * k);
  for (int k = 0; k <= 20; ++k) b_deg.push_back(-5.0 * k);
  for (const auto& [inst, angles] :
       std::vector<std::pair<kinematics::BallbarInstallation, std::vector<double>>>{
           {radial, c_deg},
           {tangential, b_deg},
           {BarCircleInstallation("XY", kinematics::BallbarPlane::kXY), {}},
           {BarCircleInstallation("ZX", kinematics::BallbarPlane::kZX), {}},
           {BarCircleInstallation("YZ", kinematics::BallbarPlane::kYZ), {}}}) {
    auto g = kinematics::MakeBallbarGeometry(c.machine, inst);
    EXPECT_TRUE(g.ok()) << g.status().ToString();
    c.tests.push_back({*g, angles});
  }
  return c;
}

GcodeOptions BarOptions(Dialect d) {
  GcodeOptions o = GcodeOptions::ForDialect(d);
  o.program_name = "BALLBAR";
  o.date = "2025-01-01";
  return o;
}

int BarCount(const std::string& text, const std::regex& re) {
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

class BallbarDialect : public ::testing::TestWithParam<Dialect> {};

// Every dialect posts the program and passes its whitelist: a stop to mount and one to remove the
// bar per installation, six arcs per circle in the circle's plane (ccw, then cw).
TEST_P(BallbarDialect, PostsStopsAndArcsInThePlaneOfEachCircle) {
  const BarCase bc = SeedBarCase();
  const GcodeOptions o = BarOptions(GetParam());
  auto p = PostBallbarProgram(bc.tests, bc.machine, {}, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  const auto syntax = CheckDialectSyntax(p->program_text, o);
  ASSERT_TRUE(syntax.ok()) << syntax.status().ToString();
  const std::string& t = p->program_text;
  EXPECT_EQ(BarCount(t, std::regex(GetParam() == Dialect::kFanuc ? R"(\bM00\b)" : R"(\bM0\b)")), 10);
  if (GetParam() == Dialect::kHeidenhain) {
    EXPECT_EQ(BarCount(t, std::regex(R"( C X[-+0-9.]+ Y[-+0-9.]+ DR\+)")), 3);
    EXPECT_EQ(BarCount(t, std::regex(R"( C X[-+0-9.]+ Z[-+0-9.]+ DR-)")), 3);
    EXPECT_EQ(BarCount(t, std::regex(R"( CC Y[-+0-9.]+ Z[-+0-9.]+)")), 6);
  } else {
    const std::string g = GetParam() == Dialect::kFanuc ? "G0" : "G";
    EXPECT_EQ(BarCount(t, std::regex("\\b" + g + "3 X[-0-9.]+ Y[-0-9.]+ I")), 3);
    EXPECT_EQ(BarCount(t, std::regex("\\b" + g + "2 X[-0-9.]+ Z[-0-9.]+ I[-0-9.]+ K")), 3);
    EXPECT_EQ(BarCount(t, std::regex("\\b" + g + "3 Y[-0-9.]+ Z[-0-9.]+ J[-0-9.]+ K")), 3);
    EXPECT_EQ(BarCount(t, std::regex(R"(\bG18\b)")), 1);
    EXPECT_EQ(BarCount(t, std::regex(R"(\bG19\b)")), 1);
  }
  const std::regex first("INSTALLATION 1/5: C_radial, radial C, bar 150 mm, 19 readings 0 \\.\\. 360 deg",
                         std::regex::icase);
  EXPECT_TRUE(std::regex_search(t, first));
  EXPECT_NE(t.find("MOUNT THE BALL BAR: YZ"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(AllDialects, BallbarDialect,
                         ::testing::Values(Dialect::kLinuxCnc, Dialect::kFanuc, Dialect::kSinumerik,
                                           Dialect::kHeidenhain),
                         [](const auto& info) { return std::string(DialectName(info.param)); });

// Rotary kinds: a dwell at every reading, each at BallbarCommand of its angle; between readings
// the steps are at most 1 deg and the bar stays within the chord bound of its length. Circles:
// every point of the test circle keeps the nominal length; the feed arcs start feed_in_mm short.
TEST(BallbarIr, ReadingsAtTheCommandsAndCirclesAtTheNominalLength) {
  const BarCase bc = SeedBarCase();
  const BallbarProgramOptions bar;
  auto ir = BuildBallbarIr(bc.tests, bc.machine, bar, BarOptions(Dialect::kLinuxCnc));
  ASSERT_TRUE(ir.ok()) << ir.status().ToString();
  const kinematics::ErrorState zero(bc.machine);
  kinematics::Workspace ws;
  std::vector<int> dwells(bc.tests.size(), 0), arcs(bc.tests.size(), 0);
  for (const Instr& in : ir->instrs) {
    if (in.op < 1) continue;
    const BallbarProgramTest& t = bc.tests[static_cast<std::size_t>(in.op) - 1];
    const kinematics::BallbarGeometry& g = t.geometry;
    const double length_mm = kinematics::BallbarLengthMm(bc.machine, zero, g, in.end, &ws);
    if (in.kind == InstrKind::kDwell && g.installation.kind != kinematics::BallbarKind::kCircle) {
      const int k = dwells[static_cast<std::size_t>(in.op) - 1]++;
      auto c = kinematics::BallbarCommand(bc.machine, g, t.angles_deg[static_cast<std::size_t>(k)]);
      ASSERT_TRUE(c.ok());
      EXPECT_NEAR(in.end.x_mm, c->x_mm, 1e-9);
      EXPECT_NEAR(in.end.y_mm, c->y_mm, 1e-9);
      EXPECT_NEAR(in.end.z_mm, c->z_mm, 1e-9);
      EXPECT_NEAR(in.end.b_rad, c->b_rad, 1e-12);
      EXPECT_NEAR(in.end.c_rad, c->c_rad, 1e-12);
      EXPECT_NEAR(length_mm, g.installation.nominal_length_mm, 1e-9);
    }
    if (in.kind == InstrKind::kLinear && in.start.c_rad + in.start.b_rad != in.end.c_rad + in.end.b_rad) {
      EXPECT_LE(RadToDeg(std::max(std::abs(in.end.b_rad - in.start.b_rad), std::abs(in.end.c_rad - in.start.c_rad))),
                1.0 + 1e-9);
      kinematics::AxisState mid;
      mid.x_mm = 0.5 * (in.start.x_mm + in.end.x_mm), mid.y_mm = 0.5 * (in.start.y_mm + in.end.y_mm);
      mid.z_mm = 0.5 * (in.start.z_mm + in.end.z_mm);
      mid.b_rad = 0.5 * (in.start.b_rad + in.end.b_rad), mid.c_rad = 0.5 * (in.start.c_rad + in.end.c_rad);
      // r (1 - cos 0.5 deg) with r < 400 mm: 0.015 mm.
      EXPECT_NEAR(kinematics::BallbarLengthMm(bc.machine, zero, g, mid, &ws), g.installation.nominal_length_mm,
                  0.015);
    }
    if (in.kind == InstrKind::kArc) {
      const int k = arcs[static_cast<std::size_t>(in.op) - 1]++;
      EXPECT_EQ(in.clockwise, k >= 3);
      if (k == 1 || k == 4) {  // the test circle
        EXPECT_NEAR(in.arc_angle_rad, 2.0 * std::numbers::pi, 1e-12);
        EXPECT_NEAR(length_mm, g.installation.nominal_length_mm, 1e-9);
        // A quarter along: the axes turned about the arc centre in the plane.
        kinematics::AxisState q = in.end;
        const Eigen::Vector3d c(in.arc_center_xy_mm.x(), in.arc_center_xy_mm.y(), in.arc_center_z_mm);
        const Eigen::Vector3d p(in.end.x_mm, in.end.y_mm, in.end.z_mm);
        const int i1 = in.arc_plane == ArcPlane::kXY ? 0 : in.arc_plane == ArcPlane::kZX ? 2 : 1;
        Eigen::Vector3d r = p - c, turned = r;
        turned(i1) = in.clockwise ? r((i1 + 1) % 3) : -r((i1 + 1) % 3);
        turned((i1 + 1) % 3) = in.clockwise ? -r(i1) : r(i1);
        q.x_mm = c.x() + turned.x(), q.y_mm = c.y() + turned.y(), q.z_mm = c.z() + turned.z();
        EXPECT_NEAR(kinematics::BallbarLengthMm(bc.machine, zero, g, q, &ws), g.installation.nominal_length_mm,
                    1e-9);
      }
      if (k == 0) {
        EXPECT_NEAR(kinematics::BallbarLengthMm(bc.machine, zero, g, in.start, &ws),
                    g.installation.nominal_length_mm - bar.feed_in_mm, 0.05);
      }
    }
  }
  EXPECT_EQ(dwells[0], 19);
  EXPECT_EQ(dwells[1], 21);
  for (std::size_t i = 2; i < 5; ++i) EXPECT_EQ(arcs[i], 6) << i;
}

// LinuxCNC's interpreter runs the program cleanly: 18 circle arcs, the planes selected.
TEST(BallbarRs274, LinuxCncProgramRunsWithItsArcsAndPlanes) {
  TPCAL_REQUIRE_RS274(rs274);
  const BarCase bc = SeedBarCase();
  auto p = PostBallbarProgram(bc.tests, bc.machine, {}, BarOptions(Dialect::kLinuxCnc));
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  const testing::Rs274Run run = testing::RunRs274(rs274, testing::OutputDir(), *p);
  ASSERT_EQ(Rs274Errors(run.exit_status, run.out, run.err), "");
  EXPECT_EQ(BarCount(run.out, std::regex(R"(ARC_FEED\()")), 18) << run.out.substr(0, 2000);
  EXPECT_EQ(BarCount(run.out, std::regex(R"(SELECT_PLANE\(CANON_PLANE_XZ\))")), 1);
  EXPECT_EQ(BarCount(run.out, std::regex(R"(SELECT_PLANE\(CANON_PLANE_YZ\))")), 1);
}

// A Z stroke below the safe Z is refused naming the block; bad options name the option.
TEST(BallbarProgramErrors, StrokeAndOptions) {
  BarCase bc = SeedBarCase();
  BallbarProgramOptions bad;
  bad.feed_arc_deg = 200.0;
  auto e = BuildBallbarIr(bc.tests, bc.machine, bad, BarOptions(Dialect::kFanuc));
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.status().message().find("feed_arc_deg"), std::string::npos);
  auto ir = BuildBallbarIr(bc.tests, bc.machine, {}, BarOptions(Dialect::kFanuc));
  ASSERT_TRUE(ir.ok()) << ir.status().ToString();
  for (kinematics::AxisLink& l : bc.machine.links)
    if (l.axis == kinematics::Axis::kZ) l.max_position = ir->safe_z_mm - 1.0;
  auto p = PostBallbarProgram(bc.tests, bc.machine, {}, BarOptions(Dialect::kFanuc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().ToString().find("target outside the machine's travel"), std::string::npos)
      << p.status().ToString();
}

}  // namespace
}  // namespace tpcal::gcode
