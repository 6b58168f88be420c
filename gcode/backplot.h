// Backplot of a program as an SVG drawing: the tool reference point in the PART frame (through
// the nominal kinematics, so indexed holes and A = -90 turning appear where they are on the
// piece), in a top view (part X right, Y up) and a side view (part X right, Z up). Rapids dashed,
// feeds solid; one colour per operation with a legend; XY arcs at A = 0 drawn as SVG arcs,
// other arcs and simultaneous rotary moves as polylines (options.arc_segment_deg); a scale bar
// in mm per view. Table-turning moves are drawn at C = 0 (the table spins); the top view adds
// the circle each turning feed's nose centre sweeps and a circle of the reamer radius per hole.
#pragma once

#include <string>

#include "gcode/ir.h"
#include "gcode/options.h"

namespace tpcal::gcode {

struct BackplotStats {
  int polylines = 0;   // path elements drawn
  int svg_arcs = 0;    // of which SVG arc commands
  int marks = 0;       // top-view circles: holes (tool radius) and turned faces (nose-centre circle)
  double rapid_length_mm = 0.0;  // part-frame lengths (tool reference point)
  double feed_length_mm = 0.0;
};

// A self-contained SVG document. `title` heads the drawing (piece and dialect).
std::string BackplotSvg(const IrProgram& prog, const BackplotOptions& options, const std::string& title,
                        BackplotStats* stats = nullptr);

}  // namespace tpcal::gcode
