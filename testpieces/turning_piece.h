// The turning test piece of seed 002 (Ibaraki, Yoshida, Asano) for a five-axis machine with an
// A/C swiveling table, parametrised. Defaults are the paper's; what the paper leaves open is
// chosen and documented in testpieces/README.md ("Turning test piece").
//
// Part frame: origin at the nominal A/C intersection, +Z along the C axis (up at A = 0), +X
// toward hole H1 (machine +X at A = C = 0). Heights are "from the A axis" as in the paper.
// Shape: a stepped cylinder widening downward. From the top: the top face (groove S_R / B_R
// and holes H1..Hn), sections S1, S2, S3 (r1 < r2 < r3), a tall section S4, then S5, S6 and a
// base flange. Each S_i is a cylinder above its shoulder B_i (an annulus facing +Z from r_i out
// to the next section's radius).
//
// Machining (seed 002 section 2.1), one operation per step:
//   1 groove: B_R floor pass, then S_R wall pass (climb, CCW), A = C = 0, X-Y circular
//     interpolation about the MCS origin [+ optional inner wall S_RI, CW climb];
//   2 holes: reamer at machine (pitch radius, 0), C indexed by 360/n deg, A = 0;
//   3 S1/B1, 4 S4/B4: A = 0, tool at +X (Y = 0): B by -X radial feed, S by -Z axial feed;
//   5 S2/B2, 6 S5/B5: A = 0, tool at +Y (X = 0): B by -Y feed, S by -Z feed;
//   7 S3/B3, 8 S6/B6: A = -90 deg (part +Z along machine -Y), tool above (X = 0): B by -Z feed,
//     S by +Y feed.
#pragma once

#include <array>
#include <string>

#include "core/status.h"

namespace tpcal::testpieces {

// One turned step i: side face S_i (cylinder of radius radius_mm from shoulder_z_mm up to the
// next shoulder above) and bottom face B_i (annulus at shoulder_z_mm from radius_mm out to the
// next step's radius).
struct TurnedStep {
  double radius_mm = 0.0;       // r_i
  double shoulder_z_mm = 0.0;   // height of B_i
  double probe_z_mm = 0.0;      // height of the S_i probing circle (the paper's z_i)
};

struct TurningPieceParams {
  std::string name = "seed 002 turning test piece";

  // Reference groove (S_R outer wall facing the axis, B_R floor), tool: radius end mill.
  double groove_bottom_z_mm = 405.702;   // z_R, height of B_R (paper section 4.1)
  double groove_depth_mm = 5.0;          // top face at z_R + depth
  double groove_outer_radius_mm = 119.0; // radius of S_R
  double groove_inner_radius_mm = 109.0; // radius of the groove's inner wall (S_RI)
  double groove_wall_probe_height_mm = 2.5;  // S_R probing circle above B_R
  double groove_floor_probe_radius_mm = 114.0;  // B_R probing circle radius
  double groove_finish_stock_mm = 0.2;   // wall stock left by the floor pass for the wall pass
  double groove_wall_lift_mm = 0.1;      // the wall pass runs this far above B_R (no floor recut)
  // Enrichment: also finish the inner wall S_RI (radius groove_inner_radius_mm) by a CW climb
  // pass, giving a second reference circle cut in the opposite interpolation direction.
  bool groove_inner_wall_pass = false;
  // Direction of the S_R wall pass: true = CCW (G3, climb with M03 on an outer wall, the
  // paper's down cut); false = CW (G2, up cut).
  bool groove_outer_wall_ccw = true;

  // Holes H1..Hn (reamed, blind), axes parallel to part Z.
  int hole_count = 16;
  double hole_pitch_radius_mm = 140.0;   // H1 at machine (X, Y) = (140, 0) at A = C = 0
  double hole_depth_mm = 15.0;           // from the top face
  double hole_probe_depth_mm = 7.5;      // probing circle below the top face (z_h = top - this)

  // Steps S1..S6 / B1..B6 (index 0 = step 1). Radii 160, 165, 170 and heights 400.702,
  // 380.702, 160.702, 140.702 are the paper's; the rest is chosen (README).
  std::array<TurnedStep, 6> steps = {{
      {160.0, 395.702, 400.702},
      {165.0, 385.702, 390.702},
      {170.0, 375.702, 380.702},
      {175.0, 155.702, 160.702},
      {180.0, 145.702, 150.702},
      {185.0, 135.702, 140.702},
  }};
  double base_radius_mm = 195.0;         // flange below B6 (outer edge of B6); stock
  double base_bottom_z_mm = 115.702;     // part bottom on the fixture
  double bore_radius_mm = 100.0;         // pre-machined central bore from the bottom; 0: none
  double bore_top_z_mm = 380.702;

  // B_i probing circle: fraction of the annulus (0 = r_i, 1 = outer edge).
  double bottom_probe_fraction = 0.6;

  // Tools and cutting data (seed 002 section 4.1 and Table 3).
  double end_mill_diameter_mm = 8.0;
  double end_mill_corner_radius_mm = 0.5;   // not given in the paper: chosen
  int end_mill_teeth = 4;
  double floor_cutting_speed_m_per_min = 62.8;
  double floor_feed_per_tooth_mm = 0.025;
  double wall_cutting_speed_m_per_min = 100.0;
  double wall_feed_per_tooth_mm = 0.019;
  double reamer_diameter_mm = 10.7;
  int reamer_teeth = 4;
  double reamer_cutting_speed_m_per_min = 13.5;
  double reamer_feed_per_tooth_mm = 0.006;
  double insert_nose_radius_mm = 0.8;
  double insert_included_angle_deg = 80.0;
  double turning_cutting_speed_m_per_min = 250.0;
  double turning_feed_mm_per_rev = 0.2;
  double turning_depth_of_cut_mm = 0.8;     // finishing stock on every turned face
  double turning_max_table_rpm = 500.0;
  double turning_tool_reach_mm = 300.0;     // holder reach below the spindle (A = 0 faces)
  double turning_shank_width_mm = 25.0;     // holder width along part Z (A = -90 faces)
  double approach_clearance_mm = 2.0;       // feed moves start this far from the stock
  // Rapid (retract) height of machine Z above the part in both setups (A = 0: above the top
  // face; A = -90: above the flange radius).
  double safe_clearance_mm = 25.0;

  // Checks values, ordering, and machinability: the reamer fits the hole, the groove is wider
  // than the end mill and clear of the holes, every A = 0 turned face is reachable from above
  // (all stock above it at a smaller radius), every A = -90 face has room for the shank, the
  // holes end above the bore. kInvalidArgument naming the parameter (YAML key).
  Status Validate() const;

  double top_z_mm() const { return groove_bottom_z_mm + groove_depth_mm; }
  double hole_probe_z_mm() const { return top_z_mm() - hole_probe_depth_mm; }  // z_h
  // Outer radius of B_i (the next lower section's radius, or the base flange for B6).
  double BottomOuterRadius(int step_index) const;
};

}  // namespace tpcal::testpieces
