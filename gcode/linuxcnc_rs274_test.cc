// Proof of the LinuxCNC programs by LinuxCNC's own interpreter: every test piece is posted in
// the LinuxCNC dialect, run through `rs274 -g PROGRAM.ngc -t PROGRAM.tbl`, and its canonical
// output (STRAIGHT_TRAVERSE / STRAIGHT_FEED / ARC_FEED, mm, work offsets applied, tool length
// not) is mapped through the nominal kinematics into the part frame and checked against the
// nominal geometry of every feature.
//
// Tolerance: kGeomTol_mm = 1 um, the requirement. The program is posted with 4 decimals and
// rs274 prints 4 decimals, so rounding alone is <= 0.05 um per coordinate; the measured
// deviations are printed (they are ~0.1 um).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <map>
#include <set>

#include "core/units.h"
#include "gcode/internal/test_support.h"
#include "gcode/options_yaml.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::gcode {
namespace {

using testing::PieceCase;

constexpr double kGeomTol_mm = 1e-3;      // requirement: nominal geometry within 1 um
constexpr double kAxisTol = 1e-6;         // unit-vector components (tool axis vs cone normal)

struct Proof {
  testpieces::TestPiece piece;
  PostedProgram posted;
  Rs274Listing listing;
  std::string error;  // rs274 errors or setup failure
};

const Proof& ProofOf(const PieceCase& pc, const std::string& rs274) {
  static std::map<std::string, Proof> cache;
  auto it = cache.find(pc.id);
  if (it != cache.end()) return it->second;
  Proof& p = cache[pc.id];
  auto piece = testing::MakePiece(pc);
  if (!piece.ok()) {
    p.error = "test piece: " + piece.status().ToString();
    return p;
  }
  p.piece = *piece;
  auto posted = PostProgram(p.piece, testing::GoldenOptions(Dialect::kLinuxCnc, pc.id));
  if (!posted.ok()) {
    p.error = "post: " + posted.status().ToString();
    return p;
  }
  p.posted = *posted;
  const auto dir = testing::OutputDir();
  const testing::Rs274Run run = testing::RunRs274(rs274, dir, p.posted);
  p.error = Rs274Errors(run.exit_status, run.out, run.err);
  if (!p.error.empty()) return p;
  auto listing = ParseRs274Listing(run.out);
  if (!listing.ok()) {
    p.error = listing.status().ToString();
    return p;
  }
  p.listing = *listing;
  testing::WriteFile(dir / (p.posted.program_file + ".svg"), p.posted.backplot_svg);
  return p;
}

kinematics::AxisState StateOf(const PathMove& m) {
  kinematics::AxisState s;
  s.x_mm = m.end[0];
  s.y_mm = m.end[1];
  s.z_mm = m.end[2];
  s.a_rad = DegToRad(m.end[3]);
  s.b_rad = DegToRad(m.end[4]);
  s.c_rad = DegToRad(m.end[5]);
  return s;
}

Eigen::Vector3d Tip(const Proof& p, const PathMove& m) {
  return kinematics::NominalToolPointInPart(p.piece.machine, StateOf(m), Eigen::Vector3d::Zero());
}

int InstrOf(const IrProgram& ir, const testpieces::CutRef& ref) {
  for (std::size_t i = 0; i < ir.instrs.size(); ++i) {
    const Instr& in = ir.instrs[i];
    if (in.op == ref.op && in.pass == ref.pass && in.move == ref.move) return static_cast<int>(i);
  }
  return -1;
}

// Indices into listing.path.moves of the canonical moves an IR instruction produced.
std::vector<int> MovesOf(const Proof& p, int instr) {
  std::vector<int> out;
  if (instr < 0) return out;
  const auto& labels = p.posted.posted.instr_labels[instr];
  const std::set<std::string> set(labels.begin(), labels.end());
  for (std::size_t k = 0; k < p.listing.path.moves.size(); ++k) {
    if (set.count(p.listing.path.moves[k].label)) out.push_back(static_cast<int>(k));
  }
  return out;
}

double Rho(const Eigen::Vector3d& v) { return std::hypot(v.x(), v.y()); }

// Largest deviation found per check, printed for the report.
struct Worst {
  std::map<std::string, double> um;
  void Add(const std::string& what, double dev_mm) { um[what] = std::max(um[what], std::abs(dev_mm) * 1000.0); }
  void Print(const std::string& id) const {
    for (const auto& [k, v] : um) std::cout << "[rs274 " << id << "] max |" << k << "| = " << v << " um\n";
  }
};

void CheckTurned(const Proof& p, const testpieces::NominalFeature& f, const testpieces::TurnedCut& cut, Worst* w) {
  const int instr = InstrOf(p.posted.ir, cut.ref);
  const std::vector<int> moves = MovesOf(p, instr);
  ASSERT_FALSE(moves.empty()) << f.name << ": no canonical feed for its turning move";
  ASSERT_GT(moves.front(), 0);
  const Eigen::Vector3d start = Tip(p, p.listing.path.moves[moves.front() - 1]);
  const Eigen::Vector3d end = Tip(p, p.listing.path.moves[moves.back()]);
  const double rn = cut.nose_radius_mm;
  if (!cut.radial_feed) {  // side face S_i: axial feed at nose-centre radius r + rn down to B_i + rn
    for (const Eigen::Vector3d& q : {start, end}) {
      EXPECT_NEAR(Rho(q), f.radius_mm + rn, kGeomTol_mm) << f.name;
      w->Add("side face nose radius - (r + rn)", Rho(q) - (f.radius_mm + rn));
    }
    EXPECT_NEAR(end.z(), f.h_min_mm + rn, kGeomTol_mm) << f.name << ": cutting end of the axial feed";
    w->Add("side face end height - (shoulder + rn)", end.z() - (f.h_min_mm + rn));
    EXPECT_GT(start.z(), end.z()) << f.name << ": feeds toward the shoulder";
  } else {  // bottom face B_i: radial feed at height shoulder + rn down to radius r + rn
    for (const Eigen::Vector3d& q : {start, end}) {
      EXPECT_NEAR(q.z(), f.origin_mm.z() + rn, kGeomTol_mm) << f.name;
      w->Add("bottom face nose height - (z + rn)", q.z() - (f.origin_mm.z() + rn));
    }
    EXPECT_NEAR(Rho(end), f.r_min_mm + rn, kGeomTol_mm) << f.name << ": cutting end of the radial feed";
    w->Add("bottom face end radius - (r + rn)", Rho(end) - (f.r_min_mm + rn));
    EXPECT_GT(Rho(start), Rho(end));
  }
  // Feed per rev: every segment's feed rate over its table speed is the piece's mm/rev, and the
  // speed follows v = 2 pi r n (clamped) at the segment's mid radius.
  const Instr& in = p.posted.ir.instrs[instr];
  const std::set<std::string> labels(p.posted.posted.instr_labels[instr].begin(), p.posted.posted.instr_labels[instr].end());
  double feed = 0, rpm = 0;
  int segments = 0;
  const PathMove* prev = &p.listing.path.moves[moves.front() - 1];
  std::size_t move_k = 0;
  for (const auto& [label, call] : p.listing.calls) {
    if (call.rfind("SET_FEED_RATE(", 0) == 0) feed = std::stod(call.substr(14));
    if (call.rfind("SET_AUX_OUTPUT_VALUE(", 0) == 0 || call.rfind("SET_MOTION_OUTPUT_VALUE(", 0) == 0) {
      rpm = std::abs(std::stod(call.substr(call.find(',') + 1)));
    }
    if (call.rfind("STRAIGHT_FEED(", 0) == 0 && labels.count(label)) {
      ++segments;
      ASSERT_GT(rpm, 0) << f.name << ": table not turning during the feed";
      EXPECT_NEAR(feed / rpm, in.feed_mm_per_rev, 1e-6) << f.name << " at " << label;
      const PathMove& m = p.listing.path.moves[moves[move_k++]];
      const double r_mid = 0.5 * (Rho(Tip(p, *prev)) + Rho(Tip(p, m))) - (cut.radial_feed ? 0.0 : rn);
      const TableSpin& spin = [&]() -> const TableSpin& {
        for (int k = instr; k >= 0; --k) {
          if (p.posted.ir.instrs[k].kind == InstrKind::kTableSpinStart) return p.posted.ir.instrs[k].spin;
        }
        return p.posted.ir.instrs[instr].spin;
      }();
      EXPECT_LE(rpm, spin.max_rpm + 0.5);
      double n = spin.surface_speed_m_per_min * 1000.0 / (2 * kPi * r_mid);
      if (spin.max_rpm > 0) n = std::min(n, spin.max_rpm);
      // Segments of at most css_step_mm radius change: the speed stays within that step's range.
      const double dn = spin.surface_speed_m_per_min * 1000.0 / (2 * kPi) *
                        (1.0 / (r_mid - 1.0) - 1.0 / (r_mid + 1.0));
      EXPECT_NEAR(rpm, n, dn + 1.0) << f.name << " at " << label;
      prev = &m;
    }
  }
  EXPECT_EQ(segments, static_cast<int>(moves.size()));
}

void CheckMill(const Proof& p, const testpieces::NominalFeature& f, const testpieces::PathMillCut& cut, Worst* w) {
  for (const testpieces::PathElement& e : cut.elements) {
    const int instr = InstrOf(p.posted.ir, e.ref);
    const std::vector<int> moves = MovesOf(p, instr);
    ASSERT_EQ(moves.size(), 1u) << f.name << ": one canonical move per path element";
    const PathMove& m = p.listing.path.moves[moves[0]];
    ASSERT_GT(moves[0], 0);
    const Eigen::Vector3d start = Tip(p, p.listing.path.moves[moves[0] - 1]);
    const Eigen::Vector3d end = Tip(p, m);
    if (e.arc) {
      ASSERT_EQ(m.kind, PathMoveKind::kArc) << f.name;
      EXPECT_EQ(m.rotation, e.clockwise ? -1 : 1) << f.name;
      kinematics::AxisState c = StateOf(m);
      c.x_mm = m.center1_mm;
      c.y_mm = m.center2_mm;
      const Eigen::Vector3d centre = kinematics::NominalToolPointInPart(p.piece.machine, c, Eigen::Vector3d::Zero());
      EXPECT_LT((centre - e.center_mm).norm(), kGeomTol_mm) << f.name << ": arc centre";
      w->Add("arc centre", (centre - e.center_mm).norm());
      for (const Eigen::Vector3d& q : {start, end}) {
        EXPECT_NEAR((q - centre).norm(), e.radius_mm, kGeomTol_mm) << f.name << ": tool path radius";
        w->Add("arc radius", (q - centre).norm() - e.radius_mm);
      }
      if (std::abs(e.angle_rad - 2 * kPi) < 1e-9) {
        EXPECT_LT((start - end).norm(), kGeomTol_mm) << f.name << ": full circle";
      }
      // The face: tool path radius + tool radius on a concave cylinder, - on a convex one.
      if (!cut.end_face && f.type == testpieces::SurfaceType::kCylinder) {
        const double face = f.internal ? e.radius_mm + cut.tool_radius_mm : e.radius_mm - cut.tool_radius_mm;
        EXPECT_NEAR(face, f.radius_mm, kGeomTol_mm) << f.name;
        EXPECT_LT(std::hypot(centre.x() - f.origin_mm.x(), centre.y() - f.origin_mm.y()), kGeomTol_mm) << f.name;
      }
    } else {
      ASSERT_EQ(m.kind, PathMoveKind::kFeed) << f.name;
      EXPECT_LT((start - e.start_tip_mm).norm(), kGeomTol_mm) << f.name;
      EXPECT_LT((end - e.end_tip_mm).norm(), kGeomTol_mm) << f.name;
      w->Add("line end", (end - e.end_tip_mm).norm());
      if (!cut.end_face && f.type == testpieces::SurfaceType::kPlane) {
        for (const Eigen::Vector3d& q : {start, end}) {
          const double d = (q - f.origin_mm).dot(f.axis);
          EXPECT_NEAR(d, cut.tool_radius_mm, kGeomTol_mm) << f.name << ": tool axis at the tool radius from the face";
          w->Add("side face offset - tool radius", d - cut.tool_radius_mm);
        }
      }
    }
    if (cut.end_face) {  // floor: the tool tip at the face height
      const double z0 = f.origin_mm.z();
      for (const Eigen::Vector3d& q : {start, end}) {
        EXPECT_NEAR(q.z(), z0, kGeomTol_mm) << f.name << ": tool end on the floor";
        w->Add("floor height", q.z() - z0);
      }
    }
  }
}

void CheckPlunge(const Proof& p, const testpieces::NominalFeature& f, const testpieces::PlungeCut& cut, Worst* w) {
  const int instr = InstrOf(p.posted.ir, cut.ref);
  ASSERT_GE(instr, 0);
  EXPECT_EQ(p.posted.ir.instrs[instr].kind, InstrKind::kDrillCycle) << f.name << ": reamed by a G85 cycle";
  const std::vector<int> moves = MovesOf(p, instr);
  int bottom = -1;
  for (int k : moves) {
    if (p.listing.path.moves[k].kind == PathMoveKind::kFeed) {
      bottom = k;
      break;
    }
  }
  ASSERT_GE(bottom, 0) << f.name;
  const Eigen::Vector3d tip = Tip(p, p.listing.path.moves[bottom]);
  const Eigen::Vector3d expected = cut.entry_mm - cut.depth_mm * cut.axis;
  EXPECT_LT((tip - expected).norm(), kGeomTol_mm) << f.name << ": hole bottom";
  const double pos = std::hypot(tip.x() - f.origin_mm.x(), tip.y() - f.origin_mm.y());
  EXPECT_LT(pos, kGeomTol_mm) << f.name << ": hole position";
  w->Add("hole position", pos);
  w->Add("hole bottom", (tip - expected).norm());
  EXPECT_NEAR(cut.tool_radius_mm, f.radius_mm, 1e-9) << f.name << ": reamer diameter = hole";
}

void CheckFlank(const Proof& p, const testpieces::NominalFeature& cone, const testpieces::FlankMillCut& cut, Worst* w) {
  int feeds = 0;
  double mid_dev = 0;
  const PathMove* prev = nullptr;
  const double up = 20.0;  // a second point up the tool axis (mm): the whole flank line is tangent
  for (std::size_t i = 0; i < p.posted.ir.instrs.size(); ++i) {
    const Instr& in = p.posted.ir.instrs[i];
    if (in.op != cut.ref.op || in.pass != cut.ref.pass || in.feed_mode != FeedMode::kInverseTime) continue;
    const std::vector<int> moves = MovesOf(p, static_cast<int>(i));
    ASSERT_EQ(moves.size(), 1u);
    const PathMove& m = p.listing.path.moves[moves[0]];
    const kinematics::AxisState s = StateOf(m);
    const Eigen::Vector3d tip = Tip(p, m);
    const Eigen::Vector3d axis = kinematics::NominalToolAxisInPart(p.piece.machine, s);
    for (double h : {0.0, up}) {
      auto proj = testpieces::ProjectOnto(cone, tip + h * axis);
      ASSERT_TRUE(proj.ok());
      EXPECT_NEAR(proj->signed_distance_mm, cut.tool_radius_mm, kGeomTol_mm) << "block " << m.label << " h " << h;
      w->Add("cone: tool axis distance to the cone - tool radius", proj->signed_distance_mm - cut.tool_radius_mm);
      if (h == 0.0) {
        EXPECT_NEAR(axis.dot(proj->normal), 0.0, kAxisTol) << "block " << m.label << ": axis along the generatrix";
      }
    }
    // Joint-space interpolation between two blocks (what a control without TCP does): report
    // the deviation of the mid-point from the offset surface.
    if (prev) {
      kinematics::AxisState a = StateOf(*prev);
      kinematics::AxisState mid = a;
      mid.x_mm = 0.5 * (a.x_mm + s.x_mm);
      mid.y_mm = 0.5 * (a.y_mm + s.y_mm);
      mid.z_mm = 0.5 * (a.z_mm + s.z_mm);
      mid.a_rad = 0.5 * (a.a_rad + s.a_rad);
      mid.c_rad = 0.5 * (a.c_rad + s.c_rad);
      const Eigen::Vector3d t = kinematics::NominalToolPointInPart(p.piece.machine, mid, Eigen::Vector3d::Zero());
      auto proj = testpieces::ProjectOnto(cone, t);
      ASSERT_TRUE(proj.ok());
      mid_dev = std::max(mid_dev, std::abs(proj->signed_distance_mm - cut.tool_radius_mm));
    }
    prev = &m;
    ++feeds;
  }
  EXPECT_EQ(feeds, cut.steps);
  std::cout << "[rs274 cone] " << feeds << " five-axis blocks; joint-interpolation mid-block deviation from the "
               "offset cone (information, not an error of the program): max " << mid_dev * 1000.0 << " um\n";
}

class Rs274Proof : public ::testing::TestWithParam<PieceCase> {};

TEST_P(Rs274Proof, InterpreterRunsCleanAndReproducesTheIr) {
  TPCAL_REQUIRE_RS274(rs274);
  const Proof& p = ProofOf(GetParam(), rs274);
  ASSERT_TRUE(p.error.empty()) << p.error;
  EXPECT_TRUE(p.listing.program_end);
  // Every canonical move equals the IR's path (1 um, 1e-4 deg).
  const auto expected = ToPartPoints(ExpectedPath(p.posted.ir), p.piece.machine);
  const auto actual = ToPartPoints(p.listing.path, p.piece.machine);
  auto cmp = ComparePaths(expected, actual, kGeomTol_mm, 1e-4);
  ASSERT_TRUE(cmp.ok()) << cmp.status().ToString();
  std::cout << "[rs274 " << GetParam().id << "] " << p.listing.path.moves.size() << " canonical moves, "
            << cmp->points << " path points = IR within " << cmp->max_tip_deviation_mm * 1000.0 << " um, "
            << cmp->max_rotary_deviation_deg << " deg\n";
  // The tool table in inches gives the tool lengths in mm (G43 after each change).
  ASSERT_EQ(p.listing.path.tool_changes, static_cast<int>(p.posted.ir.tools.size()));
  std::vector<double> lengths;
  for (double z : p.listing.tool_length_offsets_mm) {
    if (z != 0.0) lengths.push_back(z);
  }
  ASSERT_EQ(lengths.size(), p.posted.ir.tools.size());
  for (std::size_t k = 0; k < lengths.size(); ++k) {
    EXPECT_NEAR(lengths[k], p.posted.ir.tools[k].length_mm, 1e-6) << "T" << p.posted.ir.tools[k].number;
  }
}

TEST_P(Rs274Proof, ToolPathReproducesTheNominalGeometry) {
  TPCAL_REQUIRE_RS274(rs274);
  const Proof& p = ProofOf(GetParam(), rs274);
  ASSERT_TRUE(p.error.empty()) << p.error;
  Worst w;
  int checked = 0;
  bool flank_done = false;
  for (std::size_t k = 0; k < p.piece.features.size(); ++k) {
    const testpieces::NominalFeature& f = p.piece.features[k];
    SCOPED_TRACE(f.name);
    const testpieces::CutModel& model = p.piece.cuts[k].model;
    if (const auto* t = std::get_if<testpieces::TurnedCut>(&model)) {
      CheckTurned(p, f, *t, &w);
    } else if (const auto* m = std::get_if<testpieces::PathMillCut>(&model)) {
      CheckMill(p, f, *m, &w);
    } else if (const auto* h = std::get_if<testpieces::PlungeCut>(&model)) {
      CheckPlunge(p, f, *h, &w);
    } else if (const auto* c = std::get_if<testpieces::FlankMillCut>(&model)) {
      if (flank_done) continue;
      CheckFlank(p, f, *c, &w);
      flank_done = true;
    }
    ++checked;
  }
  EXPECT_GT(checked, 0);
  std::cout << "[rs274 " << GetParam().id << "] " << checked << " features checked\n";
  w.Print(GetParam().id);
}

INSTANTIATE_TEST_SUITE_P(AllPieces, Rs274Proof, ::testing::ValuesIn(testing::AllPieces()),
                         [](const auto& info) { return info.param.id; });

// The proofs above run the default options; the other LinuxCNC option choices must run clean in
// rs274 too and give the IR's path: the sample post file, constant rpm instead of segmented
// constant cutting speed, no block numbers (block_step 0), coarse CSS segments with mist.
TEST(Rs274Variants, OptionChoicesRunCleanAndGiveTheIrPath) {
  TPCAL_REQUIRE_RS274(rs274);
  auto piece = testing::MakePiece({"turning", "ac_table"});
  ASSERT_TRUE(piece.ok()) << piece.status().ToString();
  auto sample = LoadGcodeOptions(std::string(TPCAL_SOURCE_DIR) + "/samples/gcode/linuxcnc.yaml");
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  std::vector<std::pair<std::string, GcodeOptions>> variants;
  variants.emplace_back("sample", *sample);
  GcodeOptions base = testing::GoldenOptions(Dialect::kLinuxCnc, "turning");
  GcodeOptions o = base;
  o.c_spindle.css = false;
  variants.emplace_back("constant_rpm", o);
  o = base;
  o.block_step = 0;
  variants.emplace_back("no_block_numbers", o);
  o = base;
  o.c_spindle.css_step_mm = 10.0;
  o.coolant = Coolant::kMist;
  variants.emplace_back("coarse_css_mist", o);
  for (auto& [name, opts] : variants) {
    SCOPED_TRACE(name);
    auto posted = PostProgram(*piece, opts);
    ASSERT_TRUE(posted.ok()) << posted.status().ToString();
    const auto run = testing::RunRs274(rs274, testing::OutputDir() / name, *posted);
    ASSERT_EQ(Rs274Errors(run.exit_status, run.out, run.err), "");
    auto listing = ParseRs274Listing(run.out);
    ASSERT_TRUE(listing.ok()) << listing.status().ToString();
    const auto expected = ToPartPoints(ExpectedPath(posted->ir), piece->machine);
    const auto actual = ToPartPoints(listing->path, piece->machine);
    auto cmp = ComparePaths(expected, actual, kGeomTol_mm, 1e-4);
    ASSERT_TRUE(cmp.ok()) << cmp.status().ToString();
    std::cout << "[rs274 variant " << name << "] " << cmp->points << " points = IR within "
              << cmp->max_tip_deviation_mm * 1000.0 << " um\n";
  }
}

// The listing's arc conventions, checked against the interpreter itself: one G2 arc per plane
// with known end points and centres. rs274 prints ARC_FEED in the active plane's axis order:
// XY as (X, Y), XZ as (Z, X), YZ as (Y, Z); ParseRs274Listing must put every end point back
// on X, Y, Z and keep the centre in plane order.
TEST(Rs274Listing, ArcPlanesAsTheInterpreterPrintsThem) {
  TPCAL_REQUIRE_RS274(rs274);
  const auto dir = testing::TestDir(testing::OutputDir());
  testing::WriteFile(dir / "arcs.ngc",
                     "%\nG21 G90 G94 F100\nG0 X0 Y0 Z0\n"
                     "G17 G2 X10 Y10 I10 J0\n"   // centre (X10, Y0)
                     "G18 G2 X20 Z10 I10 K0\n"   // centre (X20, Z0)
                     "G19 G2 Y20 Z20 J10 K0\n"   // centre (Y20, Z10)
                     "M30\n%\n");
  testing::WriteFile(dir / "arcs.tbl", "T1 P1 Z1 D0.1\n");
  const std::string cmd = "cd '" + dir.string() + "' && HOME='" + dir.string() + "' '" + rs274 +
                          "' -g arcs.ngc -t arcs.tbl > arcs.out 2> arcs.err < /dev/null";
  const int rc = std::system(cmd.c_str());
  const std::string out = testing::ReadFile(dir / "arcs.out");
  ASSERT_EQ(Rs274Errors(WEXITSTATUS(rc), out, testing::ReadFile(dir / "arcs.err")), "");
  auto listing = ParseRs274Listing(out);
  ASSERT_TRUE(listing.ok()) << listing.status().ToString();
  std::vector<PathMove> arcs;
  for (const PathMove& m : listing->path.moves) {
    if (m.kind == PathMoveKind::kArc) arcs.push_back(m);
  }
  ASSERT_EQ(arcs.size(), 3u);
  const std::array<std::array<double, 3>, 3> ends = {{{10, 10, 0}, {20, 10, 10}, {20, 20, 20}}};
  const std::array<std::array<double, 2>, 3> centres = {{{10, 0}, {0, 20}, {20, 10}}};  // plane order
  const std::array<int, 3> planes = {17, 18, 19};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("G" + std::to_string(planes[k]));
    EXPECT_EQ(arcs[k].plane, planes[k]);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(arcs[k].end[i], ends[k][i], 1e-9) << "axis " << i;
    EXPECT_NEAR(arcs[k].center1_mm, centres[k][0], 1e-9);
    EXPECT_NEAR(arcs[k].center2_mm, centres[k][1], 1e-9);
  }
}

TEST(Rs274Listing, ReportsInterpreterErrorsEvenWithContinueMode) {
  TPCAL_REQUIRE_RS274(rs274);
  const auto dir = testing::TestDir(testing::OutputDir());
  testing::WriteFile(dir / "bad.ngc", "%\nN10 G21 G90\nN20 G1 X10\nN30 M30\n%\n");  // G1 without F
  testing::WriteFile(dir / "bad.tbl", "T1 P1 Z1 D0.1\n");
  for (const std::string mode : {"", "-n 0 "}) {
    const std::string cmd = "cd '" + dir.string() + "' && HOME='" + dir.string() + "' '" + rs274 + "' " + mode +
                            "-g bad.ngc -t bad.tbl > bad.out 2> bad.err < /dev/null";
    const int rc = std::system(cmd.c_str());
    const std::string err = Rs274Errors(WEXITSTATUS(rc), testing::ReadFile(dir / "bad.out"), testing::ReadFile(dir / "bad.err"));
    EXPECT_NE(err.find("zero feed rate"), std::string::npos) << "mode '" << mode << "': " << err;
  }
}

}  // namespace
}  // namespace tpcal::gcode
