// The test-piece options `tpcal plan` and `tpcal simulate` share: --testpiece NAME, --config
// TP.yaml, --machine M.yaml, --density, --levels, turned into a built piece (pipeline/piece_loader.h).
// CLI layer only.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "pipeline/piece_loader.h"

namespace CLI {
class App;
}

namespace tpcal::cli {

struct PieceArgs {
  // testpieces::PieceNames(): turning, turning_enriched, iso10791_m1 (= _320), _160, iso10791_m2, cone_frustum, ...
  std::string testpiece;
  std::string config;   // optional tpcal.testpiece/1 YAML (its `piece:` must agree with testpiece)
  std::string machine;  // tpcal.machine/1 YAML; optional for plan (default: the piece's usual machine)
  std::string density;  // "" or paper (as configured), dense, or N points per circle
  std::optional<int> levels;  // unset: as configured; else probing.levels_per_face (>= 1)
};

// Adds --testpiece, --config, --machine, --density, --levels to `sub`.
void AddPieceOptions(CLI::App* sub, PieceArgs* args, bool machine_required);

// Builds the piece. Without --machine: nominal ac_table for turning and cone_frustum, xyz for M1
// and M2. Errors (file:line where a file is at fault): unknown NAME, a config for another piece,
// bad density, config / machine file errors, a machine the piece cannot be cut on.
Result<pipeline::LoadedPiece> BuildPiece(const PieceArgs& args);

// Error (kInvalidArgument) if two of the non-empty output paths name the same file: one would
// silently overwrite the other. `paths` are (option, path) pairs.
Status CheckDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& paths);

// Writes the effective test-piece configuration (every key) to `path` atomically; no-op if empty.
Status WriteEffectiveConfig(const std::string& path, const pipeline::LoadedPiece& built);

}  // namespace tpcal::cli
