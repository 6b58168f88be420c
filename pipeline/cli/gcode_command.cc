// tpcal gcode --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--post POST.yaml]
//             --dialect fanuc|linuxcnc|sinumerik|heidenhain -o PROGRAM [--svg BACKPLOT.svg]
// Posts the NC program of a test piece (gcode::PostProgram: IR, dialect post, safety checks) and
// writes it atomically; LinuxCNC also gets PROGRAM.tbl (inches, what rs274 reads). The effective
// configuration is written beside it: PROGRAM.testpiece.yaml and PROGRAM.post.yaml reproduce
// the program with --config / --post.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <memory>
#include <string>

#include "pipeline/cli/commands.h"
#include "pipeline/gcode_stage.h"
#include "pipeline/io/atomic_file.h"
#include "testpieces/named_pieces.h"

namespace tpcal::cli {
namespace {

struct GcodeArgs {
  pipeline::PieceRequest piece;
  pipeline::GcodeRequest request;
  bool no_effective_config = false;
};

int RunGcode(const GcodeArgs& args) {
  pipeline::PieceRequest piece = args.piece;
  piece.wording.unknown_name_prefix = "--testpiece: ";
  piece.wording.unknown_name_file = "tpcal gcode";
  piece.wording.locate_piece_errors = pipeline::PieceErrorWording::Locate::kConfigElseMachine;
  pipeline::GcodeRequest request = args.request;
  request.effective_config = !args.no_effective_config;
  auto stage = pipeline::RunGcodeStage(piece, request);
  if (!stage.ok()) return ReportError(stage.status());
  for (const pipeline::GcodeFile& f : stage->files) {
    if (Status s = pipeline::WriteFileAtomic(f.path, f.text); !s.ok()) return ReportError(s);
  }

  const gcode::SafetyOptions& safety = stage->options.safety;
  Info(stage->posted.Summary());
  if (!safety.check_strokes || !safety.check_rapids || !safety.check_tool_fit) {
    Info(fmt::format("tpcal gcode: WARNING: safety checks switched off:{}{}{}", safety.check_strokes ? "" : " strokes",
                     safety.check_rapids ? "" : " rapids", safety.check_tool_fit ? "" : " tool_fit"));
  }
  if (piece.machine_path.empty()) {
    Info("tpcal gcode: no --machine: nominal " + std::string(kinematics::MachineTypeName(stage->machine_type)) +
         " machine with unlimited strokes (the stroke check checks nothing)");
  }
  for (const pipeline::GcodeFile& f : stage->files) Info("wrote " + f.path);
  if (stage->options.dialect == gcode::Dialect::kLinuxCnc) {
    Info("check it with LinuxCNC's interpreter: rs274 -g " + request.output + " -t " + request.output + ".tbl");
  }
  return kExitOk;
}

}  // namespace

Command RegisterGcode(CLI::App& app) {
  auto args = std::make_shared<GcodeArgs>();
  CLI::App* sub = app.add_subcommand(
      "gcode",
      "Write the NC program of a test piece for a controller dialect.\n"
      "Metric program (mm, mm/min, turning feeds mm/rev, cutting speed m/min, angles deg, dwell s), absolute,\n"
      "G54 / preset 1 at the MCS origin (A/C machines: the nominal A/C intersection; 3-axis pieces: the centre\n"
      "of the piece's bottom face), numbered blocks, a comment header naming piece, standard clause, units,\n"
      "tools and date. Before writing: axis strokes of the machine, no rapid into the stock, tool fits the\n"
      "feature; a violation is an error naming the block and nothing is written. LinuxCNC also writes\n"
      "PROGRAM.tbl (tool lengths and diameters in inches, what LinuxCNC's interpreter reads), so\n"
      "`rs274 -g PROGRAM -t PROGRAM.tbl` runs as it is. PROGRAM.testpiece.yaml and PROGRAM.post.yaml hold\n"
      "the effective configuration (feed them back with --config / --post). Dialect choices: gcode/DIALECTS.md.");
  sub->add_option("--testpiece", args->piece.testpiece, "test piece: " + testpieces::PieceNameList() +
                                                     " (iso10791_m1 = iso10791_m1_320)")->required();
  sub->add_option("--config", args->piece.config_path,
                  "test-piece configuration YAML (schema tpcal.testpiece/1: sizes, tools, feeds, speeds, stock; "
                  "its piece: must match --testpiece); default: the paper's / standard's piece");
  sub->add_option("--machine", args->piece.machine_path,
                  "machine YAML (schema tpcal.machine/1, e.g. samples/machines/ac_table.yaml); default: nominal "
                  "ac_table (turning, cone_frustum) or xyz (M1, M2) with unlimited strokes");
  sub->add_option("--post", args->request.post_path,
                  "post options YAML (schema tpcal.gcode/1, samples/gcode/<dialect>.yaml): work offset, coolant, "
                  "block numbers, decimals, tool numbers / lengths (mm), C-axis spindle codes, five-axis mode, checks");
  sub->add_option("--dialect", args->request.dialect, "controller: fanuc (ISO, .nc), linuxcnc (RS274NGC, .ngc + .tbl), "
                                              "sinumerik (840D, .mpf), heidenhain (TNC 640 Klartext, .h)")
      ->required();
  sub->add_option("-o,--output", args->request.output,
                  "PROGRAM: the NC program file; its stem (upper case) is the program name unless --post sets "
                  "program_name")
      ->required();
  sub->add_option("--svg", args->request.svg, "BACKPLOT.svg: top and side view of the tool path in the part frame (mm)");
  sub->add_option("--date", args->request.date, "header date YYYY-MM-DD, or none; default: today (UTC)");
  sub->add_option("--skip-check", args->request.skip_checks,
                  "switch a safety check off: strokes, rapids or tool_fit (repeatable; at your own risk)");
  sub->add_flag("--no-effective-config", args->no_effective_config,
                "do not write PROGRAM.testpiece.yaml and PROGRAM.post.yaml");
  return {sub, [args] { return RunGcode(*args); }};
}

}  // namespace tpcal::cli
