#include "pipeline/cli/piece_args.h"

#include <CLI/CLI.hpp>

#include <filesystem>

#include "pipeline/io/atomic_file.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"

namespace tpcal::cli {
namespace {

constexpr const char* kDensityHelp =
    "probing density: paper (as configured; the defaults are seed 002's plan: 16 points per circle, 8 per hole, "
    "one circle per face), dense (64 points per circle, 5 levels per face, 16 per hole, 3 levels per hole), or "
    "N: N points per circle and N/2 (>= 3) per hole, the rest as configured";

}  // namespace

Result<pipeline::LoadedPiece> BuildPiece(const PieceArgs& args) {
  pipeline::PieceRequest request;
  request.testpiece = args.testpiece;
  request.config_path = args.config;
  request.machine_path = args.machine;
  request.density = args.density;
  request.levels = args.levels;
  request.wording.unknown_name_prefix = "--testpiece: ";
  request.wording.name_piece_errors = true;
  request.wording.locate_piece_errors = pipeline::PieceErrorWording::Locate::kConfig;
  return pipeline::LoadPiece(request);
}

void AddPieceOptions(CLI::App* sub, PieceArgs* args, bool machine_required) {
  sub->add_option("--testpiece", args->testpiece, "test piece: " + testpieces::PieceNameList() +
                      " (iso10791_m1 = iso10791_m1_320; *_enriched: the variants proposed for the diagnosis, "
                      "samples/testpieces/)")->required();
  sub->add_option("--config", args->config,
                  "test-piece configuration YAML (schema tpcal.testpiece/1, samples/testpieces/): dimensions in mm, "
                  "probing density, time model; default: the piece's documented defaults (testpieces/README.md)");
  auto* m = sub->add_option("--machine", args->machine,
                            machine_required ? "machine model YAML (schema tpcal.machine/1, samples/machines/)"
                                             : "machine model YAML (schema tpcal.machine/1, samples/machines/); "
                                               "default: nominal A/C swiveling table (turning, cone_frustum) or "
                                               "3-axis (M1, M2), pivots at the origin");
  if (machine_required) m->required();
  sub->add_option("--density", args->density, kDensityHelp);
  sub->add_option("--levels", args->levels,
                  "probing levels (circles or lines) per face, spread over the probe-able band; default as configured (1)");
}

Status CheckDistinctOutputs(const std::vector<std::pair<std::string, std::string>>& paths) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    for (std::size_t j = i + 1; j < paths.size(); ++j) {
      if (paths[i].second.empty() || paths[j].second.empty()) continue;
      // absolute() first: libstdc++'s weakly_canonical leaves a relative path with no existing
      // prefix unchanged ("x.csv" vs "./x.csv").
      std::error_code ec_i, ec_j;
      const auto a = std::filesystem::weakly_canonical(std::filesystem::absolute(paths[i].second), ec_i);
      const auto b = std::filesystem::weakly_canonical(std::filesystem::absolute(paths[j].second), ec_j);
      if (paths[i].second == paths[j].second || (!ec_i && !ec_j && a == b))
        return Status(StatusCode::kInvalidArgument,
                      paths[i].first + " and " + paths[j].first + " name the same file '" + paths[i].second + "'");
    }
  }
  return Status::Ok();
}

Status WriteEffectiveConfig(const std::string& path, const pipeline::LoadedPiece& built) {
  if (path.empty()) return Status::Ok();
  return pipeline::WriteFileAtomic(path, testpieces::FormatPieceConfig(built.piece.config));
}

}  // namespace tpcal::cli
