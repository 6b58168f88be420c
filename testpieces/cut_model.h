// Cut-state association: how each feature's surface was generated, so that any part-frame point
// of the feature (a plan point, or a measured point after datum alignment) maps back to the
// machine state that cut it: the kinematics::CutPoint {axis commands with t_s and op, the contact
// point in the tool frame, the nominal point p0 and outward normal n0, the sweep tangents}.
// Identification, diagnosis and the simulator all go through CutPointAt (test_piece.h).
//
// All geometry is in the PART frame (mm, unit vectors); axis states come from the nominal inverse
// kinematics of the planning machine (kinematics/inverse_kinematics.h), so the CutPoint is
// consistent with kinematics/simulate.h: nominal S(0, 0) == p0 (tested to 1e-9 mm).
#pragma once

#include <Eigen/Core>
#include <variant>
#include <vector>

#include "kinematics/axis_state.h"

namespace tpcal::testpieces {

// Where a cut happens in the program: operation number (1-based, contract `op`), pass and move
// indices (0-based) inside it.
struct CutRef {
  int op = 0;
  int pass = 0;
  int move = 0;
};

// A turned face (seed 002 S_i, B_i): the C table spins while the tool feeds along a straight
// line at fixed A. The surface coordinate of a point is its height h along the part Z (axial
// feed: side faces) or its radius from the part Z axis (radial feed: bottom faces); it maps
// linearly onto the feed move. C at the cut = azimuth - tool_azimuth.
struct TurnedCut {
  CutRef ref;
  double a_rad = 0.0;             // A command during the cut
  double tool_azimuth_rad = 0.0;  // part azimuth of the tool at C = 0 (A = 0, tool at +X: 0;
                                  // tool at +Y: pi/2; A = -90, tool above at +Z: pi/2)
  double nose_radius_mm = 0.0;
  bool radial_feed = false;       // true: bottom face (feed toward the axis)
  double coord_start_mm = 0.0;    // h or radius of the CONTACT at the start of the feed move
  double coord_end_mm = 0.0;      // ... and at its end
};

// One element of a milled path at fixed rotary axes: the tool tip runs on a straight line or a
// circular arc (in the plane normal to the tool axis).
struct PathElement {
  CutRef ref;
  bool arc = false;
  Eigen::Vector3d start_tip_mm = Eigen::Vector3d::Zero();  // line: tool tip at the start
  Eigen::Vector3d end_tip_mm = Eigen::Vector3d::Zero();    // line: ... at the end
  Eigen::Vector3d center_mm = Eigen::Vector3d::Zero();     // arc: centre at tip height
  Eigen::Vector3d start_dir = Eigen::Vector3d::UnitX();    // arc: unit, centre -> tip at start
  double radius_mm = 0.0;                                  // arc: tool-centre path radius
  double angle_rad = 0.0;                                  // arc: swept angle (<= 2 pi)
  bool clockwise = false;                                  // arc: about the tool axis
};

// A face milled with the side (walls) or the end (floors, face milling) of a rotating tool at
// fixed rotary axes (groove S_R / B_R, M1 contours, bore, M2 passes). A point is associated with
// the element (and the tool position on it) that left it: side: the tool axis at the point's
// foot, |distance - tool radius| smallest; end: among the elements whose flat end covers the
// point, the one that passed last.
struct PathMillCut {
  kinematics::AxisState rotary;   // A, B, C during the cut (linear fields unused)
  Eigen::Vector3d tool_axis = Eigen::Vector3d::UnitZ();  // part frame, unit, toward the spindle
  double tool_radius_mm = 0.0;
  double corner_radius_mm = 0.0;  // flat end radius = tool radius - corner radius
  bool end_face = false;          // true: cut by the tool end (floor); false: by its side
  std::vector<PathElement> elements;
};

// A hole finished by a tool plunging along its axis (reamer) at fixed rotary axes.
struct PlungeCut {
  CutRef ref;
  kinematics::AxisState rotary;
  Eigen::Vector3d entry_mm = Eigen::Vector3d::Zero();  // hole axis at the entry face, part frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();     // unit, out of the hole (toward spindle)
  double depth_mm = 0.0;                               // plunge depth of the tool tip
  double tool_radius_mm = 0.0;
};

// Simultaneous five-axis flank milling of a cone: the tool axis lies along the generatrix, the
// tool side touches the cone along it; the tip sits at cone height h_tip. The pass turns once
// around the cone from theta_start (about the cone axis from the feature's ref_dir), moves
// ref.move .. ref.move + steps - 1 being the discretised path (equal theta steps).
struct FlankMillCut {
  CutRef ref;
  int steps = 0;
  double theta_start_rad = 0.0;
  bool counter_clockwise = true;  // about the cone axis
  double tool_radius_mm = 0.0;
  double h_tip_mm = 0.0;
  bool negative_tilt = true;      // rotary solution branch: the A (or B) <= 0 one
};

using CutModel = std::variant<TurnedCut, PathMillCut, PlungeCut, FlankMillCut>;

struct FeatureCut {
  std::string feature;
  CutModel model;
};

}  // namespace tpcal::testpieces
