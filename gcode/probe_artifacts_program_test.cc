// The probe-artifacts probing program (gcode/probe_artifacts_program.h) on the nominal A/C table
// with seed 000's plan (A 0, -30, -60, -90 deg x C every 60 deg, three 30 x 30 x 60 columns).
//
// Truth: the nominal geometry recomputed here from the boxes (kinematics::FaceOf, the face centre
// and outward normal) and the nominal machine_from_table at the A, C the program commands: the
// stylus-ball centre touches a face at contact + r n (r = 3 mm). Tolerances: exact IR geometry
// kArtIrTol_mm = 1e-9 (sums of vectors within 1000 mm); the program and rs274's listing both carry
// 4 decimals (0.05 um rounding each): kArtNcTol_mm = 1e-4, two of them on a distance along a line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "core/units.h"
#include "gcode/dialect_check.h"
#include "gcode/internal/test_support.h"
#include "gcode/probe_artifacts_program.h"

namespace tpcal::gcode {
namespace {

constexpr double kArtIrTol_mm = 1e-9;
constexpr double kArtNcTol_mm = 1e-4;

struct ArtifactCase {
  kinematics::MachineModel machine;
  testpieces::ProbeArtifactsPlan plan;
};

ArtifactCase SeedArtifactCase(const testpieces::ProbeArtifactsPlanOptions& o = {}) {
  ArtifactCase c;
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  c.machine = *m;
  auto plan = testpieces::MakeProbeArtifactsPlan(c.machine, kinematics::Seed000Artifacts(), o);
  EXPECT_TRUE(plan.ok()) << plan.status().ToString();
  if (plan.ok()) c.plan = *plan;
  return c;
}

GcodeOptions ArtifactOptions(Dialect d) {
  GcodeOptions o = GcodeOptions::ForDialect(d);
  o.program_name = "PROBE_ARTIFACTS";
  o.date = "2025-01-01";
  return o;
}

int CountArtifactMatches(const std::string& text, const std::regex& re) {
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

// Stylus-ball centre at the touch (machine frame), computed from the box, not from the plan.
struct ArtifactTruth {
  Eigen::Vector3d centre_mm;  // contact + r n
  Eigen::Vector3d normal;     // outward, machine frame
};

ArtifactTruth ArtifactTruthOf(const kinematics::MachineModel& m, const testpieces::ProbeArtifactsPlan& plan,
                      const testpieces::PlannedTouch& t, double a_deg, double c_deg) {
  kinematics::AxisState s;
  s.a_rad = DegToRad(a_deg), s.c_rad = DegToRad(c_deg);
  const Rigid3 machine_from_table = kinematics::NominalMachineFromTable(m, s);
  const kinematics::FaceGeometry g = kinematics::FaceOf(plan.artifacts.boxes[t.artifact], t.face);
  const Eigen::Vector3d n = machine_from_table.linear() * g.normal;
  return {machine_from_table * g.centre_mm + plan.probe_radius_mm * n, n};
}

// Distance (mm) from a part-frame point to a box (0 inside).
double ArtifactDistanceToBox(const Eigen::Vector3d& p_part, const kinematics::ArtifactBox& b) {
  const double rot = DegToRad(b.rotation_deg);
  const Eigen::Vector3d d = p_part - b.base_centre_mm;
  const Eigen::Vector3d l(std::cos(rot) * d.x() + std::sin(rot) * d.y(), -std::sin(rot) * d.x() + std::cos(rot) * d.y(),
                          d.z() - 0.5 * b.size_mm.z());
  const Eigen::Vector3d out = (l.cwiseAbs() - 0.5 * b.size_mm).cwiseMax(0.0);
  return out.norm();
}

class ProbeArtifactsDialect : public ::testing::TestWithParam<Dialect> {};

// The G-code dialects post seed 000's plan with one probing block per planned touch (oblique
// approaches included) and pass their whitelist.
TEST_P(ProbeArtifactsDialect, PostsOneProbingBlockPerPlannedTouch) {
  const ArtifactCase ac = SeedArtifactCase();
  const GcodeOptions o = ArtifactOptions(GetParam());
  auto p = PostProbeArtifactsProgram(ac.plan, ac.machine, {}, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_TRUE(CheckDialectSyntax(p->program_text, o).ok());
  const std::string& t = p->program_text;
  const int touches = static_cast<int>(ac.plan.touches.size());
  switch (GetParam()) {
    case Dialect::kLinuxCnc: EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(\bG38\.2 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\b)")), touches); break;
    case Dialect::kFanuc: EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(\bG31 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\.)")), touches); break;
    case Dialect::kSinumerik: EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(\bMEAS=1 G1 X[-0-9.]+ Y[-0-9.]+ Z[-0-9.]+ F200\b)")), touches); break;
    case Dialect::kHeidenhain: break;
  }
  EXPECT_TRUE(std::regex_search(t, std::regex("POSE 1/24: A0 C0, 15 touches, 0 skipped, Q1\\.\\.: 1\\+X 1-X 1\\+Y 1-Y 1\\+Z 2\\+X .* 3\\+Z", std::regex::icase)));
  EXPECT_TRUE(std::regex_search(t, std::regex("POSE 24/24: A-90 C300,", std::regex::icase)));
  EXPECT_TRUE(std::regex_search(t, std::regex("INSTRUMENT: probe artifacts", std::regex::icase)));
}

INSTANTIATE_TEST_SUITE_P(GDialects, ProbeArtifactsDialect,
                         ::testing::Values(Dialect::kLinuxCnc, Dialect::kFanuc, Dialect::kSinumerik),
                         [](const auto& info) { return std::string(DialectName(info.param)); });

// Heidenhain posts a touch along one machine axis with cycle 0 (REF. PLANE, result Q<n>) and any
// other with cycle 4 (MEASURING IN 3-D, results Q(30 + 3 (n - 1)) .. +2). The default plan (C every
// 60 deg, A tilted) posts with one cycle-4 block group per oblique approach and one cycle-0 group
// per axis-parallel one, counted here from the plan's approaches; each cycle 4 probes along its
// approach over approach + overtravel (7 mm).
TEST(ProbeArtifactsHeidenhain, DefaultPlanPostsObliqueTouchesWithCycle4AndAxisParallelOnesWithCycle0) {
  const GcodeOptions o = ArtifactOptions(Dialect::kHeidenhain);
  const ArtifactCase ac = SeedArtifactCase();
  const ProbeArtifactsProbeOptions probe;
  int oblique = 0, parallel = 0;
  std::vector<const testpieces::PlannedTouch*> oblique_touches;
  for (const testpieces::PlannedTouch& t : ac.plan.touches) {
    const bool axis_parallel = std::abs(t.approach.cwiseAbs().maxCoeff() - 1.0) <= 1e-12;
    (axis_parallel ? parallel : oblique) += 1;
    if (!axis_parallel) oblique_touches.push_back(&t);
  }
  ASSERT_GT(oblique, 0);
  ASSERT_GT(parallel, 0);  // e.g. the tops at A 0
  auto p = PostProbeArtifactsProgram(ac.plan, ac.machine, probe, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_TRUE(CheckDialectSyntax(p->program_text, o).ok());
  const std::string& t = p->program_text;
  EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(\n\d+ TCH PROBE 4\.0 MEASURING IN 3-D\n)")), oblique);
  EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(TCH PROBE 4\.3 ABST\+7 F200 MB7 BASE0\n)")), oblique);
  EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(TCH PROBE 0\.0 REF\. PLANE Q[0-9]+ [XYZ][+-]\n)")), parallel);
  EXPECT_EQ(CountArtifactMatches(t, std::regex(R"(TCH PROBE 0\.1 X[-+0-9.]+ Y[-+0-9.]+ Z[-+0-9.]+\n)")), parallel);

  // Each cycle 4 in plan order: its result parameter from the touch's number within the pose, its
  // direction vector along the approach, 7 mm long (4 decimals per component).
  std::vector<int> numbers;  // the touch number within its pose of each oblique touch
  for (std::size_t k = 0, n = 0; k < ac.plan.touches.size(); ++k) {
    const testpieces::PlannedTouch& tk = ac.plan.touches[k];
    const bool new_pose = k == 0 || ac.plan.touches[k - 1].rotary.a_rad != tk.rotary.a_rad ||
                          ac.plan.touches[k - 1].rotary.c_rad != tk.rotary.c_rad;
    n = new_pose ? 1 : n + 1;
    if (std::abs(tk.approach.cwiseAbs().maxCoeff() - 1.0) > 1e-12) numbers.push_back(static_cast<int>(n));
  }
  const std::regex cycle4(R"(TCH PROBE 4\.1 Q([0-9]+)\n\d+ TCH PROBE 4\.2 IX([-+0-9.]+) IY([-+0-9.]+) IZ([-+0-9.]+)\n)");
  std::size_t i = 0;
  for (auto it = std::sregex_iterator(t.begin(), t.end(), cycle4); it != std::sregex_iterator(); ++it, ++i) {
    ASSERT_LT(i, oblique_touches.size());
    EXPECT_EQ(std::stoi((*it)[1]), 30 + 3 * (numbers[i] - 1)) << "cycle 4 #" << i;
    const Eigen::Vector3d v(std::stod((*it)[2]), std::stod((*it)[3]), std::stod((*it)[4]));
    const Eigen::Vector3d expected = (probe.approach_mm + probe.overtravel_mm) * oblique_touches[i]->approach;
    EXPECT_LT((v - expected).norm(), 2 * kArtNcTol_mm) << "cycle 4 #" << i;
  }
  EXPECT_EQ(i, oblique_touches.size());

  // The whitelist takes cycle 4's four blocks in order only.
  std::string swapped = t;
  swapped.replace(swapped.find("TCH PROBE 4.1 Q"), 15, "TCH PROBE 4.2 Q");
  auto bad = CheckDialectSyntax(swapped, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().ToString().find("expected TCH PROBE 4.1"), std::string::npos) << bad.status().ToString();
}

// Cycle 4's three result parameters of touch n stay within Q30..Q99: touch 24 of a pose is refused.
TEST(ProbeArtifactsHeidenhain, Cycle4ResultsBeyondQ99AreRefused) {
  const ArtifactCase ac = SeedArtifactCase();
  const GcodeOptions o = ArtifactOptions(Dialect::kHeidenhain);
  auto ir = BuildProbeArtifactsIr(ac.plan, ac.machine, {}, o);
  ASSERT_TRUE(ir.ok()) << ir.status().ToString();
  Instr* oblique = nullptr;
  for (Instr& in : ir->instrs)
    if (in.kind == InstrKind::kProbe && std::abs(in.probe.direction.cwiseAbs().maxCoeff() - 1.0) > 1e-12) {
      oblique = &in;
      break;
    }
  ASSERT_NE(oblique, nullptr);
  oblique->probe.result = 23;  // Q96..Q98
  ASSERT_TRUE(PostIr(*ir, o).ok());
  oblique->probe.result = 24;  // Q99..Q101
  auto refused = PostIr(*ir, o);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().ToString().find("Q99"), std::string::npos) << refused.status().ToString();
}

// Upright columns with C every 90 deg (every approach along X, Y or -Z) post as before: one
// REF. PLANE per touch, Q1..Q15 per pose, no cycle 4.
TEST(ProbeArtifactsHeidenhain, AxisAlignedPlansPostWithCycle0Only) {
  const GcodeOptions o = ArtifactOptions(Dialect::kHeidenhain);
  const ArtifactCase aligned = SeedArtifactCase({.a_deg = {0.0}, .c_step_deg = 90.0});
  ASSERT_EQ(aligned.plan.touches.size(), 4u * 15u);
  auto p = PostProbeArtifactsProgram(aligned.plan, aligned.machine, {}, o);
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  ASSERT_TRUE(CheckDialectSyntax(p->program_text, o).ok());
  EXPECT_EQ(CountArtifactMatches(p->program_text, std::regex(R"(TCH PROBE 0\.0 REF\. PLANE Q[0-9]+ [XYZ][+-])")), 60);
  EXPECT_EQ(CountArtifactMatches(p->program_text, std::regex(R"(TCH PROBE 0\.1 X[-+0-9.]+ Y[-+0-9.]+ Z[-+0-9.]+)")), 60);
  EXPECT_EQ(CountArtifactMatches(p->program_text, std::regex(R"(PLANE Q15 Z-)")), 4);  // box 3's top, last
  EXPECT_EQ(CountArtifactMatches(p->program_text, std::regex(R"(TCH PROBE 4\.)")), 0);
}

// The IR's touches: the ball centre at contact + r n, the start `approach` further out, the
// target `overtravel` past the contact, probing along -n at the plan's pose; each touch comes
// straight down from the safe Z to its start; the safe Z clears every box corner + r by the
// safe clearance at every pose.
TEST(ProbeArtifactsIr, TouchesStartOffTheFaceAndComeStraightDownFromSafeZ) {
  const ArtifactCase ac = SeedArtifactCase();
  const ProbeArtifactsProbeOptions probe;
  auto ir = BuildProbeArtifactsIr(ac.plan, ac.machine, probe, ArtifactOptions(Dialect::kLinuxCnc));
  ASSERT_TRUE(ir.ok()) << ir.status().ToString();
  const double r = ac.plan.probe_radius_mm;
  std::size_t k = 0;
  int result = 0;
  for (std::size_t i = 0; i < ir->instrs.size(); ++i) {
    const Instr& in = ir->instrs[i];
    if (in.kind != InstrKind::kProbe) continue;
    ASSERT_LT(k, ac.plan.touches.size());
    const testpieces::PlannedTouch& t = ac.plan.touches[k];
    const ArtifactTruth truth = ArtifactTruthOf(ac.machine, ac.plan, t, RadToDeg(in.end.a_rad), RadToDeg(in.end.c_rad));
    const Eigen::Vector3d start(in.start.x_mm, in.start.y_mm, in.start.z_mm), end(in.end.x_mm, in.end.y_mm, in.end.z_mm);
    EXPECT_EQ(in.end.a_rad, t.rotary.a_rad);
    EXPECT_EQ(in.end.c_rad, t.rotary.c_rad);
    EXPECT_LT((in.probe.contact_mm - truth.centre_mm).norm(), kArtIrTol_mm);
    EXPECT_LT((start - (truth.centre_mm + probe.approach_mm * truth.normal)).norm(), kArtIrTol_mm);
    EXPECT_LT((end - (truth.centre_mm - probe.overtravel_mm * truth.normal)).norm(), kArtIrTol_mm);
    EXPECT_LT((in.probe.direction + truth.normal).norm(), kArtIrTol_mm);
    const bool new_pose = k == 0 || ac.plan.touches[k - 1].rotary.a_rad != t.rotary.a_rad ||
                          ac.plan.touches[k - 1].rotary.c_rad != t.rotary.c_rad;
    result = new_pose ? 1 : result + 1;  // Q<n>: the touch's number within its pose
    EXPECT_EQ(in.probe.result, result);
    // The two rapids before: X Y at safe Z, then Z alone down to the start.
    const Instr& down = ir->instrs[i - 1];
    const Instr& over = ir->instrs[i - 2];
    ASSERT_EQ(down.kind, InstrKind::kRapid);
    ASSERT_EQ(over.kind, InstrKind::kRapid);
    EXPECT_NEAR(down.start.z_mm, ir->safe_z_mm, kArtIrTol_mm);
    EXPECT_NEAR(down.start.x_mm, start.x(), kArtIrTol_mm);
    EXPECT_NEAR(down.start.y_mm, start.y(), kArtIrTol_mm);
    EXPECT_NEAR(over.start.z_mm, ir->safe_z_mm, kArtIrTol_mm);
    ++k;
  }
  EXPECT_EQ(k, ac.plan.touches.size());
  for (const kinematics::AxisState& pose : ac.plan.poses) {
    const Rigid3 machine_from_table = kinematics::NominalMachineFromTable(ac.machine, pose);
    for (const kinematics::ArtifactBox& b : ac.plan.artifacts.boxes)
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d p = b.base_centre_mm + Eigen::Vector3d((corner & 1 ? 0.5 : -0.5) * b.size_mm.x(),
                                                                     (corner & 2 ? 0.5 : -0.5) * b.size_mm.y(),
                                                                     (corner & 4 ? 1.0 : 0.0) * b.size_mm.z());
        EXPECT_GE(ir->safe_z_mm, (machine_from_table * p).z() + r + probe.safe_clearance_mm - kArtIrTol_mm);
      }
  }
}

// LinuxCNC's interpreter runs the program; every STRAIGHT_PROBE reaches the IR's target (rs274 has
// no probe: the move runs to its end) on the line through the nominal ball centre at the touch
// (recomputed from the box at the A, C rs274 reports, which are the plan's), `approach` after the
// start and `overtravel` before the target; no rapid (the index sweeps included, every degree and
// every 0.5 mm) brings the stylus ball closer to any box than the approach gap.
TEST(ProbeArtifactsRs274, ProbeMovesRunOnTheirContactLinesAndRapidsClearTheBoxes) {
  TPCAL_REQUIRE_RS274(rs274);
  const ArtifactCase ac = SeedArtifactCase();
  const ProbeArtifactsProbeOptions probe;
  const GcodeOptions o = ArtifactOptions(Dialect::kLinuxCnc);
  auto p = PostProbeArtifactsProgram(ac.plan, ac.machine, probe, o);
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
  ASSERT_EQ(ir_probes.size(), ac.plan.touches.size());

  const double r = ac.plan.probe_radius_mm;
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
      const testpieces::PlannedTouch& t = ac.plan.touches[k];
      EXPECT_NEAR(end.x(), in.end.x_mm, kArtNcTol_mm);
      EXPECT_NEAR(end.y(), in.end.y_mm, kArtNcTol_mm);
      EXPECT_NEAR(end.z(), in.end.z_mm, kArtNcTol_mm);
      EXPECT_NEAR(m.end[3], RadToDeg(t.rotary.a_rad), kArtNcTol_mm);
      EXPECT_NEAR(m.end[5], RadToDeg(t.rotary.c_rad), kArtNcTol_mm);
      const ArtifactTruth truth = ArtifactTruthOf(ac.machine, ac.plan, t, m.end[3], m.end[5]);
      const Eigen::Vector3d u = (end - start).normalized();
      const double along = (truth.centre_mm - start).dot(u);
      EXPECT_LT((truth.centre_mm - start - along * u).norm(), 2 * kArtNcTol_mm) << "touch " << k;
      EXPECT_NEAR(along, probe.approach_mm, 2 * kArtNcTol_mm) << "touch " << k;
      EXPECT_NEAR((end - start).norm() - along, probe.overtravel_mm, 2 * kArtNcTol_mm) << "touch " << k;
      EXPECT_NEAR(u.dot(truth.normal), -1.0, 1e-4) << "touch " << k;  // 0.1 um over 7 mm
      retract_pending = true;
      touch_start = start;
      ++k;
    } else if (m.kind == PathMoveKind::kRapid && retract_pending) {
      EXPECT_LT((end - touch_start).norm(), kArtNcTol_mm) << "retract after touch " << k;
      retract_pending = false;
    } else if (m.kind == PathMoveKind::kRapid) {
      const double rot = std::max(std::abs(m.end[3] - cur[3]), std::abs(m.end[5] - cur[5]));
      const double lin = std::max({std::abs(m.end[0] - cur[0]), std::abs(m.end[1] - cur[1]), std::abs(m.end[2] - cur[2])});
      const int n = std::max(1, static_cast<int>(std::ceil(std::max(rot, lin / 0.5))));
      for (int j = 0; j <= n; ++j) {
        const double f = static_cast<double>(j) / n;
        std::array<double, 6> s;
        for (int i = 0; i < 6; ++i) s[i] = cur[i] + f * (m.end[i] - cur[i]);
        kinematics::AxisState rot_s;
        rot_s.a_rad = DegToRad(s[3]), rot_s.c_rad = DegToRad(s[5]);
        const Eigen::Vector3d ball_part = kinematics::NominalMachineFromTable(ac.machine, rot_s).inverse() *
                                          Eigen::Vector3d(s[0], s[1], s[2]);
        for (const kinematics::ArtifactBox& b : ac.plan.artifacts.boxes)
          min_rapid_gap_mm = std::min(min_rapid_gap_mm, ArtifactDistanceToBox(ball_part, b) - r);
      }
    } else {
      ADD_FAILURE() << "unexpected move " << PathMoveKindName(m.kind) << " " << m.label;
    }
    cur = m.end;
  }
  EXPECT_EQ(k, listing->probes.size());
  // The closest rapid is the approach to a touch's start point.
  EXPECT_NEAR(min_rapid_gap_mm, probe.approach_mm, 2 * kArtNcTol_mm);
}

// A machine whose Z stroke ends below the safe Z: the error names the block.
TEST(ProbeArtifactsStrokes, SafeZAboveTheZStrokeIsRefusedNamingTheBlock) {
  ArtifactCase ac = SeedArtifactCase();
  for (kinematics::AxisLink& l : ac.machine.links)
    if (l.axis == kinematics::Axis::kZ) l.max_position = 100.0;
  auto p = PostProbeArtifactsProgram(ac.plan, ac.machine, {}, ArtifactOptions(Dialect::kFanuc));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().ToString().find("PROBE_ARTIFACTS.nc"), std::string::npos) << p.status().ToString();
  EXPECT_TRUE(std::regex_search(p.status().ToString(), std::regex("N[0-9]+: rapid target outside the machine's travel")))
      << p.status().ToString();
}

TEST(ProbeArtifactsOptions, BadOptionsAndEmptyPlansAreNamed) {
  const ArtifactCase ac = SeedArtifactCase();
  const GcodeOptions o = ArtifactOptions(Dialect::kLinuxCnc);
  EXPECT_FALSE(BuildProbeArtifactsIr(ac.plan, ac.machine, {.approach_mm = 0.0}, o).ok());
  EXPECT_FALSE(BuildProbeArtifactsIr(ac.plan, ac.machine, {.overtravel_mm = -1.0}, o).ok());
  EXPECT_FALSE(BuildProbeArtifactsIr(ac.plan, ac.machine, {.probe_tool_number = 0}, o).ok());
  testpieces::ProbeArtifactsPlan empty = ac.plan;
  empty.touches.clear();
  auto e = BuildProbeArtifactsIr(empty, ac.machine, {}, o);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.status().message().find("no touch"), std::string::npos);
  testpieces::ProbeArtifactsPlan bad = ac.plan;
  bad.touches[0].artifact = 7;
  EXPECT_FALSE(BuildProbeArtifactsIr(bad, ac.machine, {}, o).ok());
  testpieces::ProbeArtifactsPlan stray = ac.plan;
  stray.touches[0].rotary.c_rad += DegToRad(1.0);
  auto s = BuildProbeArtifactsIr(stray, ac.machine, {}, o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("not one of the plan's poses"), std::string::npos) << s.status().ToString();
}

}  // namespace
}  // namespace tpcal::gcode
