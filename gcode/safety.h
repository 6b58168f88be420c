// Checks run on a posted program before it is handed out: axis strokes of the machine model,
// no rapid move into the stock envelope, tools that fit their features. A violation is an error
// naming the block (N number, or the Heidenhain line number) and what was violated.
#pragma once

#include <string>

#include "core/status.h"
#include "gcode/ir.h"
#include "gcode/options.h"
#include "gcode/post.h"
#include "gcode/stock.h"
#include "testpieces/test_piece.h"

namespace tpcal::gcode {

struct SafetyReport {
  int instructions_checked = 0;
  int rapids_checked = 0;
  int rapid_samples = 0;
  double min_rapid_clearance_mm = 0.0;  // smallest distance of a rapid's tool to the envelope
  std::string min_rapid_block;          // where
  int tool_fits_checked = 0;
};

// Tool model for the rapid check (part frame): milling tools are the cylinder of their
// diameter from the tip along the tool axis over the flute length (end disc and body sampled);
// a turning insert is the sphere of its nose radius about the nose centre. Rapids are sampled
// along the straight line in axis space (the linear interpolation LinuxCNC performs; a control
// with non-interpolated rapids must keep its dog-leg inside that clearance), every
// rapid_sample_mm of the longest linear axis and every degree of rotary motion.
//
// Tool fit: a reamer's diameter equals its hole's (tool_fit_tol_mm); a milling tool on a concave
// cylinder (groove outer wall, bore) has a radius below the cylinder's; the end mill of the seed
// 002 groove has a radius <= groove width / 2.
//
// Errors (kInvalidArgument): "<block>: <what>" for the first violation found.
Result<SafetyReport> CheckProgram(const testpieces::TestPiece& piece, const IrProgram& prog, const PostedText& posted,
                                  const StockEnvelope& stock, const SafetyOptions& options);

}  // namespace tpcal::gcode
