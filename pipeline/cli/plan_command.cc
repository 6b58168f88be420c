// tpcal plan --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--density paper|dense|N]
//            [--levels N] -o PLAN.csv [--step PIECE.step] [--write-config TP_OUT.yaml]
//
// Writes the CMM probing plan of a test piece as the `tpcal plan v1` CSV (docs/formats/probing_plan.md):
// nominal points and outward normals in the part's DATUM frame, then op, t_s, the
// rotary axes (A_deg/B_deg, C_deg: those the machine has), X_mm, Y_mm, Z_mm of the machine
// state that cut each point. Thin: testpieces builds the piece and the plan, pipeline writes.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>

#include "kinematics/machine_yaml.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/commands.h"
#include "pipeline/cli/piece_args.h"
#include "pipeline/io/point_io.h"
#include "testpieces/brep.h"
#include "testpieces/dmis_program.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"
#include "testpieces/probing_plan.h"
#include "testpieces/test_piece.h"

namespace tpcal::cli {
namespace {

constexpr const char* kDensityHelp =
    "probing density: paper (as configured; the defaults are seed 002's plan: 16 points per circle, 8 per hole, "
    "one circle per face), dense (64 points per circle, 5 levels per face, 16 per hole, 3 levels per hole), or "
    "N: N points per circle and N/2 (>= 3) per hole, the rest as configured";

}  // namespace

Result<BuiltPiece> BuildPiece(const PieceArgs& args) {
  const std::string& n = args.testpiece;
  auto named = testpieces::NamedPieceConfig(n);
  if (!named.ok()) return Status(StatusCode::kInvalidArgument, "--testpiece: " + named.status().message());
  testpieces::PieceConfig config = named->config;
  if (!args.config.empty()) {
    auto loaded = testpieces::LoadPieceConfig(args.config);
    if (!loaded.ok()) return loaded.status().file().empty() ? loaded.status().WithLocation(args.config) : loaded.status();
    if (Status s = testpieces::CheckConfigMatchesName(*loaded, *named, n, args.config); !s.ok()) return s;
    config = std::move(*loaded);
  }

  // Density.
  if (args.density.empty() || args.density == "paper") {
    // the configuration's probing section (its defaults are the paper's plan)
  } else if (args.density == "dense") {
    config.probing = testpieces::ProbingOptions::Dense();
  } else {
    int per_circle = 0;
    std::size_t used = 0;
    try {
      per_circle = std::stoi(args.density, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != args.density.size() || per_circle < 3)
      return Status(StatusCode::kInvalidArgument,
                    "--density: expected paper, dense or a number of points per circle >= 3, got '" + args.density + "'");
    config.probing.points_per_circle = per_circle;
    config.probing.points_per_hole = std::max(3, per_circle / 2);
  }
  if (args.levels < 0) return Status(StatusCode::kInvalidArgument, "--levels must be >= 1");
  if (args.levels > 0) config.probing.levels_per_face = args.levels;
  if (Status s = config.Validate(); !s.ok()) return args.config.empty() ? s : s.WithLocation(args.config);

  BuiltPiece out;
  if (!args.machine.empty()) {
    auto m = kinematics::LoadMachineModel(args.machine);
    if (!m.ok()) return m.status().file().empty() ? m.status().WithLocation(args.machine) : m.status();
    out.machine = std::move(*m);
  } else {
    // The piece's usual machine: A/C table for the turning piece and the cone, 3-axis for M1, M2.
    auto m = kinematics::MakeMachine(testpieces::UsualMachine(config));
    if (!m.ok()) return m.status();
    out.machine = std::move(*m);
  }
  auto piece = testpieces::MakeTestPiece(config, out.machine);
  if (!piece.ok()) {
    Status s = piece.status().WithContext("test piece " + n);
    return args.config.empty() || !s.file().empty() ? s : s.WithLocation(args.config);
  }
  out.piece = std::move(*piece);
  return out;
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

Status WriteEffectiveConfig(const std::string& path, const BuiltPiece& built) {
  if (path.empty()) return Status::Ok();
  return pipeline::WriteFileAtomic(path, testpieces::FormatPieceConfig(built.piece.config));
}

namespace {

struct PlanArgs {
  PieceArgs piece;
  std::string out;
  std::string step;
  std::string write_config;
  std::string dmis;
};

// The plan as a contract PointSet: datum-frame points and normals, then the extra columns.
PointSet PlanAsPointSet(const testpieces::ProbingPlan& plan, const kinematics::MachineModel& machine) {
  PointSet ps = testpieces::PlanPointSet(plan);
  // No negative zeros in the file ("-0" reads back as 0 but looks like a sign).
  for (auto* v : {&ps.xyz_mm, &ps.normal})
    for (Eigen::Vector3d& p : *v) p = p.array() + 0.0;
  const std::vector<testpieces::PlanRow> rows = testpieces::PlanRows(plan);
  for (const std::string& col : testpieces::PlanExtraColumns(machine)) {
    PointAttribute a;
    a.name = col;
    a.values.reserve(rows.size());
    for (const testpieces::PlanRow& r : rows) {
      double v = 0;
      if (col == "op") v = r.op;
      else if (col == "t_s") v = r.t_s;
      else if (col == "A_deg") v = r.a_deg;
      else if (col == "B_deg") v = r.b_deg;
      else if (col == "C_deg") v = r.c_deg;
      else if (col == "X_mm") v = r.x_mm;
      else if (col == "Y_mm") v = r.y_mm;
      else if (col == "Z_mm") v = r.z_mm;
      a.values.push_back(v);
    }
    ps.attributes.push_back(std::move(a));
  }
  return ps;
}

int RunPlan(const PlanArgs& args) {
  if (Status s = CheckDistinctOutputs({{"-o", args.out}, {"--step", args.step}, {"--write-config", args.write_config}, {"--dmis", args.dmis}});
      !s.ok())
    return ReportError(s);
  auto built = BuildPiece(args.piece);
  if (!built.ok()) return ReportError(built.status());
  Info(fmt::format("tpcal plan: {} on {}, {} operations, {:.1f} min of machining", built->piece.name,
                   kinematics::MachineTypeName(built->machine.type), built->piece.operations.size(),
                   built->piece.duration_s() / 60.0));
  auto plan = testpieces::MakeProbingPlan(built->piece);
  if (!plan.ok()) return ReportError(plan.status().WithContext("probing plan of " + built->piece.name));
  const PointSet ps = PlanAsPointSet(*plan, built->machine);
  pipeline::PointWriteOptions wo;
  wo.kind = pipeline::PointFileKind::kPlan;
  // Format first: a row the dialect cannot hold fails before anything is written.
  auto text = pipeline::FormatPointCsv(ps, wo);
  if (!text.ok()) return ReportError(text.status().WithLocation(args.out));
  auto dmis = args.dmis.empty() ? Result<std::string>(std::string()) : testpieces::FormatDmisProgram(built->piece, *plan);
  if (!dmis.ok()) return ReportError(dmis.status().WithLocation(args.dmis));

  if (!args.step.empty()) {
    Info("building the B-rep (OpenCASCADE) for " + args.step);
    Status s = pipeline::WriteFileAtomicVia(
        args.step, [&](const std::string& temp) { return testpieces::WriteStep(built->piece, temp); });
    if (!s.ok()) return ReportError(s.file().empty() ? s.WithLocation(args.step) : s);
    Info("wrote " + args.step);
  }
  if (Status s = pipeline::WriteFileAtomic(args.out, *text); !s.ok()) return ReportError(s);
  Info(fmt::format("wrote {}: {} points on {} features (datum frame, mm)", args.out, ps.size(), ps.feature_names.size()));
  if (Status s = WriteEffectiveConfig(args.write_config, *built); !s.ok()) return ReportError(s);
  if (!args.write_config.empty()) Info("wrote " + args.write_config);
  if (Status s = args.dmis.empty() ? Status::Ok() : pipeline::WriteFileAtomic(args.dmis, *dmis); !s.ok()) return ReportError(s);
  if (!args.dmis.empty()) Info("wrote " + args.dmis + " (DMIS inspection program, docs/formats/dmis.md)");
  return kExitOk;
}

}  // namespace

Command RegisterPlan(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* sub = app.add_subcommand(
      "plan",
      "Write the CMM probing plan of a test piece (tpcal plan v1 CSV).\n"
      "One row per point to probe: feature label, nominal point x,y,z (mm) and outward unit normal i,j,k in the\n"
      "part's datum frame (turning piece: z = 0 on B_R, origin at the S_R centre, +X toward H1), then the machine\n"
      "state that cut it: op (1 = first operation), t_s (s from the start of machining), the rotary axes in deg\n"
      "(A_deg, C_deg on A/C tables; B_deg on B/C), and X_mm, Y_mm, Z_mm of the tool reference point.");
  AddPieceOptions(sub, &args->piece, /*machine_required=*/false);
  sub->add_option("-o,--output", args->out, "plan CSV to write (docs/formats/probing_plan.md)")->required();
  sub->add_option("--step", args->step, "also write the nominal B-rep of the piece as AP214 STEP (part frame, mm)");
  sub->add_option("--write-config", args->write_config,
                  "also write the effective test-piece configuration (every key, defaults included) as YAML");
  sub->add_option("--dmis", args->dmis, "also write the plan as a DMIS inspection program (.dmi, docs/formats/dmis.md)");
  return {sub, [args] { return RunPlan(*args); }};
}

}  // namespace tpcal::cli
