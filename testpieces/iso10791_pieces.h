// Parameters of the ISO 10791-7 test pieces: M1 (contouring, sizes 160 and 320), M2 (face
// milling) and the cone frustum (NAS 979 / ISO 10791-7 five-axis piece, simultaneous flank
// milling on an A/C table). The standard's drawings are not public: every dimension here is our
// documented choice in the spirit of the standard (testpieces/README.md, "ISO 10791-7 pieces").
//
// Part frame of all three: origin at the centre of the piece's bottom face (on the table), +Z up,
// sides along X and Y. They are cut at A = C = 0 (M1, M2) or with A, C interpolated (cone).
#pragma once

#include <string>

#include "core/status.h"

namespace tpcal::testpieces {

// M1 contouring piece. Layers from the bottom: base plate (stock), square, diamond (square
// turned 45 deg), circle boss, slope quadrilateral with faces at 3 and 6 deg to X; a central
// bore through the layers. Features: FLOOR (base top, end of the square-contour tool: primary
// datum), SQ_XP, SQ_YP, SQ_XN, SQ_YN (square sides; SQ_YN is the secondary datum line),
// DI_1..DI_4 (diamond sides, normals at 45, 135, 225, 315 deg), CIRCLE, SL3 (the -Y slope face,
// 3 deg), SL6 (the +Y slope face, 6 deg), SLX_P, SLX_N (slope layer ends), BORE (tertiary datum).
struct ContourPieceParams {
  std::string name = "ISO 10791-7 M1 (320)";
  double size_mm = 320.0;            // L: base plate L x L
  double base_thickness_mm = 40.0;   // FLOOR height
  double square_side_mm = 280.0;
  double square_height_mm = 20.0;
  double diamond_side_mm = 192.0;
  double diamond_height_mm = 15.0;
  double circle_diameter_mm = 160.0;
  double circle_height_mm = 15.0;
  double slope_half_length_mm = 50.0;  // SLX faces at x = +-this
  double slope_offset_mm = 40.0;       // SL3 through (0, -offset), SL6 through (0, +offset)
  double slope_small_angle_deg = 3.0;  // SL3 direction (cos a, sin a)
  double slope_large_angle_deg = 6.0;  // SL6 direction (cos a, -sin a)
  double slope_height_mm = 10.0;
  double bore_diameter_mm = 50.0;      // through all layers down to the FLOOR height
  double end_mill_diameter_mm = 32.0;
  int end_mill_teeth = 4;
  double cutting_speed_m_per_min = 200.0;
  double feed_per_tooth_mm = 0.05;
  double probe_height_fraction = 0.5;  // side faces probed at this fraction of the layer height
  double safe_clearance_mm = 25.0;     // rapid (retract) height above the top of the piece

  // Defaults of size 320 scaled by size / 320 (sizes 160 and 320 are the standard's).
  static ContourPieceParams ForSize(double size_mm);
  Status Validate() const;
  double floor_z_mm() const { return base_thickness_mm; }
  double top_z_mm() const {
    return base_thickness_mm + square_height_mm + diamond_height_mm + circle_height_mm + slope_height_mm;
  }
};

// M2 face-milling piece: a block whose top face is finished by `passes` parallel passes of a
// face mill along X with `overlap_fraction` of the cutter diameter between neighbours. Features
// FACE_P1 .. FACE_Pn: the part of the top face whose last cut was pass k.
struct FaceMillingPieceParams {
  std::string name = "ISO 10791-7 M2";
  double face_mill_diameter_mm = 50.0;
  int face_mill_teeth = 5;
  int passes = 2;
  double overlap_fraction = 0.2;     // of the cutter diameter
  double length_mm = 160.0;          // along X
  double height_mm = 50.0;           // block height (top face at z = height)
  double edge_clearance_mm = 5.0;    // the outer passes overhang the block sides by this
  double cutting_speed_m_per_min = 300.0;
  double feed_per_tooth_mm = 0.08;
  double run_out_mm = 5.0;           // the cutter clears the block ends by this at start / end
  double safe_clearance_mm = 25.0;   // rapid (retract) height above the top face

  Status Validate() const;
  // Width of the block along Y: passes * D - (passes - 1) * overlap * D - 2 * edge clearance.
  double width_mm() const;
  double PassCenterY(int k) const;   // k = 0 .. passes - 1, from -Y to +Y
};

// Cone frustum (NAS 979 / ISO 10791-7): a cone whose axis is tilted `axis_tilt_deg` from +Z
// toward +X, standing on a base plate, its flank finished in one simultaneous five-axis pass of
// an end mill whose axis follows the generatrix. Features CONE_1 .. CONE_k: probing circles at
// the cone heights (in the cone's own frame), the `k` set by the probing density.
// Enrichment (`second_cone_offset_mm` > 0): a second, identical cone this far along +X from the
// first, cut by its own flank pass (features CONE2_1 .. CONE2_k). Along one pass X, Y and C move
// as functions of each other, so a function of X (straightness) and a function of C (rotary error
// motion, angular positioning) differ only by their assumed shapes; on the offset cone X(C) is
// another function, which separates them.
struct ConeFrustumParams {
  std::string name = "NAS 979 cone frustum";
  double base_size_mm = 160.0;       // square plate, stock
  double base_thickness_mm = 20.0;
  double bottom_diameter_mm = 80.0;  // on the base top, measured normal to the cone axis
  double half_angle_deg = 15.0;
  double axis_tilt_deg = 10.0;
  double height_mm = 40.0;           // along the cone axis
  double end_mill_diameter_mm = 16.0;
  int end_mill_teeth = 3;
  double cutting_speed_m_per_min = 200.0;
  double feed_per_tooth_mm = 0.04;
  double tip_clearance_mm = 1.0;     // tool end stays this far above the base top
  int path_steps = 720;              // linear segments of the five-axis pass (0.5 deg)
  double probe_band_margin_mm = 2.0; // probing circles kept this far inside the machined band
  // Rapid (retract) height above the cone top: the tilted tool must clear the cone at every A/C.
  double safe_clearance_mm = 60.0;
  double second_cone_offset_mm = 0.0;  // 0: one cone (NAS 979); > 0: see above
  // A third identical cone this far along +Y (features CONE3_1 .. CONE3_k; needs the second):
  // on the +X cone a first-harmonic angular positioning error of C turns up as a field whose
  // X^2 and Y^2 parts a quadratic straightness of X and Y also makes; on a cone a quarter turn
  // away the two fields fall on the pass with other phases.
  double third_cone_offset_mm = 0.0;   // 0: none

  Status Validate() const;
};

}  // namespace tpcal::testpieces
