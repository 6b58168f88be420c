#include "pipeline/piece_loader.h"

#include <algorithm>
#include <exception>
#include <optional>
#include <string>

#include "core/input_echo.h"
#include "kinematics/machine_yaml.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

bool IsPieceFile(const std::string& testpiece) {
  return testpiece.ends_with(".yaml") || testpiece.ends_with(".yml");
}

Status UnknownName(const PieceRequest& r, const Status& named) {
  const std::string message =
      r.allow_piece_file ? "unknown test piece '" + r.testpiece + "' (expected one of: " +
                               testpieces::PieceNameList() + ", or a tpcal.testpiece/1 file)"
                         : named.message();
  const PieceErrorWording& w = r.wording;
  return Status(StatusCode::kInvalidArgument, w.unknown_name_prefix + message + w.unknown_name_suffix,
                w.unknown_name_file);
}

// The configuration: NAME's, or the file's (checked against NAME), or the piece file's.
Result<testpieces::PieceConfig> LoadConfig(const PieceRequest& r) {
  if (r.allow_piece_file && IsPieceFile(r.testpiece)) return testpieces::LoadPieceConfig(r.testpiece);
  auto named = testpieces::NamedPieceConfig(r.testpiece);
  if (!named.ok()) return UnknownName(r, named.status());
  if (r.config_path.empty()) return std::move(named->config);
  auto loaded = testpieces::LoadPieceConfig(r.config_path);
  if (!loaded.ok()) return loaded.status();
  if (r.config_must_match_name)
    if (Status s = testpieces::CheckConfigMatchesName(*loaded, *named, r.testpiece, r.config_path); !s.ok()) return s;
  return loaded;
}

Status ApplyDensity(const std::string& density, std::optional<int> levels, testpieces::PieceConfig* config) {
  if (density.empty() || density == "paper") {
    // the configuration's probing section (its defaults are the paper's plan)
  } else if (density == "dense") {
    config->probing = testpieces::ProbingOptions::Dense();
  } else {
    int per_circle = 0;
    std::size_t used = 0;
    try {
      per_circle = std::stoi(density, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != density.size() || per_circle < 3)
      return Status(StatusCode::kInvalidArgument,
                    "--density: expected paper, dense or a number of points per circle >= 3, got '" + density + "'");
    config->probing.points_per_circle = per_circle;
    config->probing.points_per_hole = std::max(3, per_circle / 2);
  }
  if (!levels) return Status::Ok();
  if (*levels < 1)
    return Status(StatusCode::kInvalidArgument,
                  "--levels: expected a number of probing levels per face >= 1, got " + std::to_string(*levels));
  config->probing.levels_per_face = *levels;
  return Status::Ok();
}

// A plan beyond testpieces::kMaxPlanPoints, named after the options that asked for it.
Status CheckRequestPlanSize(const PieceRequest& r, const testpieces::TestPiece& piece) {
  Status s = testpieces::CheckPlanSize(piece, piece.config.probing);
  if (s.ok()) return s;
  std::string options;
  if (!r.density.empty() && r.density != "paper") options = "--density " + EchoInput(r.density);
  if (r.levels) options += (options.empty() ? "--levels " : " --levels ") + std::to_string(*r.levels);
  if (!options.empty()) return s.WithContext(options);
  return r.config_path.empty() ? s : s.WithLocation(r.config_path);
}

Status LocatePieceError(const PieceRequest& r, Status s) {
  using Locate = PieceErrorWording::Locate;
  if (r.wording.name_piece_errors) s = s.WithContext("test piece " + r.testpiece);
  if (!s.file().empty()) return s;
  switch (r.wording.locate_piece_errors) {
    case Locate::kNone: return s;
    case Locate::kConfig: return r.config_path.empty() ? s : s.WithLocation(r.config_path);
    case Locate::kConfigElseMachine: return s.WithLocation(r.config_path.empty() ? r.machine_path : r.config_path);
  }
  return s;
}

}  // namespace

Result<LoadedPiece> LoadPiece(const PieceRequest& request) {
  auto config = LoadConfig(request);
  if (!config.ok()) return config.status();
  if (Status s = ApplyDensity(request.density, request.levels, &*config); !s.ok()) return s;
  if (Status s = config->Validate(); !s.ok())
    return request.config_path.empty() ? s : s.WithLocation(request.config_path);
  auto machine = request.machine_path.empty() ? kinematics::MakeMachine(testpieces::UsualMachine(*config))
                                              : kinematics::LoadMachineModel(request.machine_path);
  if (!machine.ok()) return machine.status();
  auto piece = testpieces::MakeTestPiece(*config, *machine);
  if (!piece.ok()) return LocatePieceError(request, piece.status());
  if (Status s = CheckRequestPlanSize(request, *piece); !s.ok()) return s;
  return LoadedPiece{std::move(*machine), std::move(*piece)};
}

}  // namespace tpcal::pipeline
