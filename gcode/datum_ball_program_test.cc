// The datum-ball probing program (gcode/datum_ball_program.h) on the nominal B/C table with seed
// 001's plan (B 0, +-30 deg, C every 30 deg: 36 positions, 5 touches each).
//
// Truth: the nominal centring command c of each position (kinematics::BallCentreCommand, zero
// errors) and the sphere geometry: the stylus centre touches the ball at distance R + r from c
// (ball radius R = 12.5 mm, stylus radius r = 3 mm). Tolerance: the program and rs274's listing
// both carry 4 decimals (0.05 um rounding each): 0.1 um per coordinate, taken as kNcTol_mm = 1e-4.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "core/units.h"
#include "gcode/datum_ball_program.h"
#include "gcode/dialect_check.h"
#include "gcode/internal/test_support.h"
#include "kinematics/datum_ball.h"
#include "kinematics/error_state.h"

namespace tpcal::gcode {
namespace {

constexpr double kNcTol_mm = 1e-4;
constexpr int kTouches = 5 * 36;

struct BallCase {
  kinematics::MachineModel machine;
  testpieces::DatumBallPlan plan;
};

BallCase SeedBallCase() {
  BallCase c;
  auto m = kinematics::MakeMachine(kinematics::MachineType::kBcTable);
  EXPECT_TRUE(m.ok());
  c.machine = *m;
  auto plan = testpieces::MakeDatumBallPlan(c.machine);
  EXPECT_TRUE(plan.ok());
  c.plan = *plan;
  return c;
}

GcodeOptions BallOptions(Dialect d) {
  GcodeOptions o = GcodeOptions::ForDialect(d);
  o.program_name = "DATUM_BALL";
  o.date = "2025-01-01";
  return o;
}

int CountMatches(const std::string& text, const std::regex& re) {
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

class DatumBallDialect : public ::testing::TestWithParam<Dialect> {};

// Every dialect posts the program, passes its whitelist and holds one probing block per touch.
TEST_P(DatumBallDialect, PostsFiveTouchesPerPositionWithTheDialectsProbingBlock) {
  const BallCase bc = SeedBallCase();
  const GcodeOptions o = BallOptions(GetParam());
  auto p = PostDatumBallProgram(bc.plan, bc.machine, {}, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_TRUE(CheckDialectSyntax(p->program_text, o).ok());
  const std::string& t = p->program_text;
  switch (GetParam()) {
    case Dialect::kLinuxCnc: EXPECT_EQ(CountMatches(t, std::regex(R"(\bG38\.2 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\b)")), kTouches); break;
    case Dialect::kFanuc: EXPECT_EQ(CountMatches(t, std::regex(R"(\bG31 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\.)")), kTouches); break;
    case Dialect::kSinumerik: EXPECT_EQ(CountMatches(t, std::regex(R"(\bMEAS=1 G1 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\b)")), kTouches); break;
    case Dialect::kHeidenhain:
      EXPECT_EQ(CountMatches(t, std::regex(R"(TCH PROBE 0\.0 REF\. PLANE Q[1-5] [XYZ][+-])")), kTouches);
      EXPECT_EQ(CountMatches(t, std::regex(R"(TCH PROBE 0\.1 X[-+0-9.]+ Y[-+0-9.]+ Z[-+0-9.]+)")), kTouches);
      EXPECT_EQ(CountMatches(t, std::regex(R"(PLANE Q1 Z-)")), 36);  // the touch from above
      break;
  }
  EXPECT_NE(t.find("POSITION 1/36: B0 C0,"), std::string::npos);
  EXPECT_NE(t.find("POSITION 36/36: B-30 C330,"), std::string::npos);
  EXPECT_TRUE(std::regex_search(t, std::regex("INSTRUMENT: datum ball", std::regex::icase)));
}

INSTANTIATE_TEST_SUITE_P(AllDialects, DatumBallDialect,
                         ::testing::Values(Dialect::kLinuxCnc, Dialect::kFanuc, Dialect::kSinumerik, Dialect::kHeidenhain),
                         [](const auto& info) { return std::string(DialectName(info.param)); });

// The IR's touches: contact at R + r from the nominal centre along the probing direction, start
// `approach` before it, target `overtravel` past it.
TEST(DatumBallIr, TouchesAreOnTheSphereOfBallPlusStylusRadius) {
  const BallCase bc = SeedBallCase();
  const DatumBallProbeOptions probe;
  auto ir = BuildDatumBallIr(bc.plan, bc.machine, probe, BallOptions(Dialect::kLinuxCnc));
  ASSERT_TRUE(ir.ok()) << ir.status().ToString();
  const double rr = 0.5 * (bc.plan.ball_diameter_mm + probe.stylus_diameter_mm);
  const kinematics::ErrorState zero(bc.machine);
  int touches = 0;
  for (const Instr& in : ir->instrs) {
    if (in.kind != InstrKind::kProbe) continue;
    ++touches;
    kinematics::AxisState rotary;
    rotary.b_rad = in.end.b_rad, rotary.c_rad = in.end.c_rad;
    auto c = kinematics::BallCentreCommand(bc.machine, zero, rotary, bc.plan.ball_part_mm);
    ASSERT_TRUE(c.ok());
    const Eigen::Vector3d start(in.start.x_mm, in.start.y_mm, in.start.z_mm), end(in.end.x_mm, in.end.y_mm, in.end.z_mm);
    EXPECT_NEAR((in.probe.contact_mm - *c).norm(), rr, 1e-9);
    EXPECT_NEAR((start - *c).norm(), rr + probe.approach_mm, 1e-9);
    EXPECT_NEAR((end - *c).norm(), rr - probe.overtravel_mm, 1e-9);
    EXPECT_NEAR((end - start).normalized().dot(in.probe.direction), 1.0, 1e-12);
    EXPECT_TRUE(RotaryAxesEqual(in.start, in.end));
  }
  EXPECT_EQ(touches, kTouches);
}

// LinuxCNC's interpreter runs the program; every STRAIGHT_PROBE reaches the IR's target (rs274 has
// no probe: the move runs to its end) on a line through the nominal contact, at the plan's rotary
// position; no rapid brings the stylus closer to the ball than the approach gap, including while
// the table indexes (the ball's centre followed every degree).
TEST(DatumBallRs274, ProbeMovesReachTheExpectedPointsAndRapidsClearTheBall) {
  TPCAL_REQUIRE_RS274(rs274);
  const BallCase bc = SeedBallCase();
  const DatumBallProbeOptions probe;
  const GcodeOptions o = BallOptions(Dialect::kLinuxCnc);
  auto p = PostDatumBallProgram(bc.plan, bc.machine, probe, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  const testing::Rs274Run run = testing::RunRs274(rs274, testing::OutputDir(), *p);
  ASSERT_EQ(Rs274Errors(run.exit_status, run.out, run.err), "");
  auto listing = ParseRs274Listing(run.out);
  ASSERT_TRUE(listing.ok()) << listing.status().ToString();
  ASSERT_EQ(listing->tool_length_offsets_mm.size(), 2u);  // reset, then the probe's G43 H1
  EXPECT_NEAR(listing->tool_length_offsets_mm.back(), o.default_tool_length_mm, 1e-6);  // 8 inch decimals

  std::vector<const Instr*> ir_probes;
  for (const Instr& in : p->ir.instrs)
    if (in.kind == InstrKind::kProbe) ir_probes.push_back(&in);
  ASSERT_EQ(listing->probes.size(), ir_probes.size());
  ASSERT_EQ(static_cast<int>(ir_probes.size()), kTouches);

  const kinematics::ErrorState zero(bc.machine);
  const double rr = 0.5 * (bc.plan.ball_diameter_mm + probe.stylus_diameter_mm);
  auto centre_at = [&](double b_deg, double c_deg) {
    kinematics::AxisState s;
    s.b_rad = DegToRad(b_deg), s.c_rad = DegToRad(c_deg);
    auto c = kinematics::BallCentreCommand(bc.machine, zero, s, bc.plan.ball_part_mm);
    EXPECT_TRUE(c.ok());
    return c.ok() ? *c : Eigen::Vector3d(Eigen::Vector3d::Constant(1e9));
  };
  std::array<double, 6> cur{};
  std::size_t k = 0;
  double min_rapid_gap_mm = 1e9;
  bool retract_pending = false;  // the rapid after a touch goes back out along the probing line
  Eigen::Vector3d touch_start = Eigen::Vector3d::Zero();
  for (const PathMove& m : listing->path.moves) {
    const Eigen::Vector3d start(cur[0], cur[1], cur[2]), end(m.end[0], m.end[1], m.end[2]);
    if (m.probe) {
      ASSERT_LT(k, ir_probes.size());
      const Instr& in = *ir_probes[k];
      EXPECT_NEAR(end.x(), in.end.x_mm, kNcTol_mm);
      EXPECT_NEAR(end.y(), in.end.y_mm, kNcTol_mm);
      EXPECT_NEAR(end.z(), in.end.z_mm, kNcTol_mm);
      const std::size_t pos = static_cast<std::size_t>(in.op) - 1;
      EXPECT_NEAR(m.end[4], RadToDeg(bc.plan.positions[pos].b_rad), kNcTol_mm);
      EXPECT_NEAR(m.end[5], RadToDeg(bc.plan.positions[pos].c_rad), kNcTol_mm);
      const Eigen::Vector3d c = centre_at(m.end[4], m.end[5]);
      const Eigen::Vector3d contact = c - rr * in.probe.direction;  // the stylus centre at the touch
      const Eigen::Vector3d u = (end - start).normalized();
      const double along = (contact - start).dot(u);
      EXPECT_LT((contact - start - along * u).norm(), 2 * kNcTol_mm) << "touch " << k;
      EXPECT_NEAR(along, probe.approach_mm, 2 * kNcTol_mm) << "touch " << k;
      EXPECT_NEAR((end - start).norm() - along, probe.overtravel_mm, 2 * kNcTol_mm) << "touch " << k;
      retract_pending = true;
      touch_start = start;
      ++k;
    } else if (m.kind == PathMoveKind::kRapid && retract_pending) {
      EXPECT_LT((end - touch_start).norm(), kNcTol_mm) << "retract after touch " << k;
      retract_pending = false;
    } else if (m.kind == PathMoveKind::kRapid) {
      const double rot = std::max(std::abs(m.end[4] - cur[4]), std::abs(m.end[5] - cur[5]));
      const double lin = std::max({std::abs(m.end[0] - cur[0]), std::abs(m.end[1] - cur[1]), std::abs(m.end[2] - cur[2])});
      const int n = std::max(1, static_cast<int>(std::ceil(std::max(rot, lin / 0.5))));
      for (int j = 0; j <= n; ++j) {
        const double f = static_cast<double>(j) / n;
        std::array<double, 6> s;
        for (int i = 0; i < 6; ++i) s[i] = cur[i] + f * (m.end[i] - cur[i]);
        const Eigen::Vector3d stylus(s[0], s[1], s[2]);
        min_rapid_gap_mm = std::min(min_rapid_gap_mm, (stylus - centre_at(s[4], s[5])).norm() - rr);
      }
    } else {
      ADD_FAILURE() << "unexpected move " << PathMoveKindName(m.kind) << " " << m.label;
    }
    cur = m.end;
  }
  EXPECT_EQ(k, listing->probes.size());
  // The closest rapid is the approach to a touch's start point.
  EXPECT_NEAR(min_rapid_gap_mm, probe.approach_mm, kNcTol_mm);
}

// A machine whose Z stroke ends below the safe Z: the error names the block.
TEST(DatumBallStrokes, SafeZAboveTheZStrokeIsRefusedNamingTheBlock) {
  BallCase bc = SeedBallCase();
  for (kinematics::AxisLink& l : bc.machine.links)
    if (l.axis == kinematics::Axis::kZ) l.max_position = 150.0;
  auto p = PostDatumBallProgram(bc.plan, bc.machine, {}, BallOptions(Dialect::kFanuc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().ToString().find("DATUM_BALL.nc"), std::string::npos) << p.status().ToString();
  EXPECT_TRUE(std::regex_search(p.status().ToString(), std::regex("N[0-9]+: rapid target outside the machine's travel")))
      << p.status().ToString();
}

}  // namespace
}  // namespace tpcal::gcode
