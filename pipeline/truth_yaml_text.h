// Text pieces of the stated-truth YAML that `tpcal simulate` writes (schema
// tpcal.simulation_truth/1, docs/formats/simulation_truth.md), shared by the test-piece and the
// datum-ball simulations.
#pragma once

#include <string>

namespace tpcal::pipeline {

// A number to 17 significant digits (reads back to the same double); no "-0".
std::string TruthNum(double v);
// A YAML flow string, always double-quoted, with '"' and '\' escaped.
std::string TruthStr(const std::string& s);
// Every non-empty line of `text` prefixed by `pad` (a YAML block nested under a key).
std::string IndentLines(const std::string& text, const std::string& pad);

}  // namespace tpcal::pipeline
