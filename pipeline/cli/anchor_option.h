// The --anchor FEATURE@X,Y,Z option that `tpcal fit`, `identify`, `diagnose` and `run` share: for
// a raw scan of a symmetric piece (the turning piece's 16 equivalent hole labellings), the
// labelling placing FEATURE nearest the point (X, Y, Z) is chosen (mm, scan frame; e.g. H1's
// approximate centre: --anchor H1@120,-80,40). pipeline/raw_scan_labeling.h,
// RawScanLabelingOptions::anchor_feature / anchor_near_mm. CLI layer only.
#pragma once

#include <string>

#include "core/status.h"
#include "pipeline/raw_scan_labeling.h"

namespace CLI {
class App;
}

namespace tpcal::cli {

// Adds --anchor to `sub`, stored as text in `anchor` (parsed later by ParseAnchor).
void AddAnchorOption(CLI::App* sub, std::string* anchor);

// "" -> default labelling options (no anchor). Otherwise FEATURE@X,Y,Z: a non-empty FEATURE, '@',
// exactly three finite numbers (mm) separated by commas -> options with anchor_feature and
// anchor_near_mm set. Anything else: kInvalidArgument "--anchor: expected FEATURE@X,Y,Z (mm), got
// '...'". Whether FEATURE is a feature of the piece is checked by the labelling.
Result<pipeline::RawScanLabelingOptions> ParseAnchor(const std::string& text);

}  // namespace tpcal::cli
