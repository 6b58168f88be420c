// tpcal gcode --testpiece NAME [--config TP.yaml] [--machine M.yaml] [--post POST.yaml]
//             --dialect fanuc|linuxcnc|sinumerik|heidenhain -o PROGRAM [--svg BACKPLOT.svg]
// Posts the NC program of a test piece (gcode::PostProgram: IR, dialect post, safety checks) and
// writes it atomically; LinuxCNC also gets PROGRAM.tbl (inches, what rs274 reads). The effective
// configuration is written beside it: PROGRAM.testpiece.yaml and PROGRAM.post.yaml reproduce
// the program with --config / --post.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "gcode/options.h"
#include "gcode/options_yaml.h"
#include "gcode/post_program.h"
#include "kinematics/machine_model.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/cli/commands.h"
#include "pipeline/piece_loader.h"
#include "pipeline/version.h"
#include "testpieces/named_pieces.h"
#include "testpieces/piece_config.h"
#include "testpieces/test_piece.h"

namespace tpcal::cli {
namespace {

struct GcodeArgs {
  std::string testpiece;
  std::string config;
  std::string machine;
  std::string post;
  std::string dialect;
  std::string output;
  std::string svg;
  std::string date;  // "" = today (UTC); "none" = not recorded
  std::vector<std::string> skip_checks;
  bool no_effective_config = false;
};

Status ArgError(const std::string& message) { return Status(StatusCode::kInvalidArgument, message, "tpcal gcode"); }

Result<testpieces::TestPiece> BuildPiece(const GcodeArgs& args) {
  pipeline::PieceRequest request;
  request.testpiece = args.testpiece;
  request.config_path = args.config;
  request.machine_path = args.machine;
  request.wording.unknown_name_prefix = "--testpiece: ";
  request.wording.unknown_name_file = "tpcal gcode";
  request.wording.locate_piece_errors = pipeline::PieceErrorWording::Locate::kConfigElseMachine;
  auto loaded = pipeline::LoadPiece(request);
  if (!loaded.ok()) return loaded.status();
  return std::move(loaded->piece);
}

// Program name from the output file's stem: [A-Z0-9_], starting with a letter, 24 characters.
std::string ProgramNameOf(const std::string& output) {
  std::string stem = std::filesystem::path(output).stem().string();
  std::string name;
  for (char ch : stem) {
    const auto u = static_cast<unsigned char>(ch);
    name += std::isalnum(u) ? static_cast<char>(std::toupper(u)) : '_';
  }
  if (name.empty() || !std::isupper(static_cast<unsigned char>(name[0]))) name = "P" + name;
  if (name.size() > 24) name.resize(24);
  return name;
}

std::string TodayUtc() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

Result<gcode::GcodeOptions> BuildOptions(const GcodeArgs& args) {
  const auto dialect = gcode::DialectFromName(args.dialect);
  if (!dialect) {
    return ArgError("--dialect: expected fanuc, linuxcnc, sinumerik or heidenhain, got '" + args.dialect + "'");
  }
  gcode::GcodeOptions o = gcode::GcodeOptions::ForDialect(*dialect);
  bool named_in_file = false;
  if (!args.post.empty()) {
    auto loaded = gcode::LoadGcodeOptions(args.post);
    if (!loaded.ok()) return loaded.status();
    o = std::move(*loaded);
    if (o.dialect != *dialect) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("dialect: the post options are for ") + gcode::DialectName(o.dialect) +
                        ", but --dialect is " + args.dialect,
                    args.post);
    }
    named_in_file = o.program_name != gcode::GcodeOptions().program_name;
  }
  if (!named_in_file) o.program_name = ProgramNameOf(args.output);
  o.tool_table_file = std::filesystem::path(args.output).filename().string() + ".tbl";
  if (args.date == "none") {
    o.date.clear();
  } else if (!args.date.empty()) {
    const std::string& d = args.date;
    const bool ok = d.size() == 10 && d[4] == '-' && d[7] == '-' &&
                    std::all_of(d.begin(), d.end(), [](char ch) { return ch == '-' || std::isdigit(static_cast<unsigned char>(ch)); });
    if (!ok) return ArgError("--date: expected YYYY-MM-DD or none, got '" + d + "'");
    o.date = d;
  } else if (o.date.empty()) {
    o.date = TodayUtc();
  }
  o.generator = std::string("tpcal ") + kVersion + " rev " + kGitRevision;
  for (const std::string& check : args.skip_checks) {
    if (check == "strokes") {
      o.safety.check_strokes = false;
    } else if (check == "rapids") {
      o.safety.check_rapids = false;
    } else if (check == "tool_fit") {
      o.safety.check_tool_fit = false;
    } else {
      return ArgError("--skip-check: expected strokes, rapids or tool_fit, got '" + check + "'");
    }
  }
  if (Status s = o.Validate(); !s.ok()) return s.WithLocation(args.post.empty() ? "tpcal gcode" : args.post);
  return o;
}

int RunGcode(const GcodeArgs& args) {
  auto options = BuildOptions(args);
  if (!options.ok()) return ReportError(options.status());
  auto piece = BuildPiece(args);
  if (!piece.ok()) return ReportError(piece.status());

  auto posted = gcode::PostProgram(*piece, *options);
  if (!posted.ok()) {
    Status s = posted.status();
    bool safety_violation = false;
    if (s.file().empty()) {
      // Safety violations come as "NAME.ngc: N1050: rapid move ..." -> "PROGRAM: N1050: ...";
      // option errors ("tools: ...") belong to the --post file.
      std::string message = s.message();
      const std::string posted_name = options->program_name + gcode::ProgramExtension(options->dialect) + ": ";
      safety_violation = message.rfind(posted_name, 0) == 0;
      if (safety_violation) message.erase(0, posted_name.size());
      const bool post_key = !args.post.empty() && message.rfind("tools:", 0) == 0;
      s = Status(s.code(), message, post_key ? args.post : args.output);
    }
    ReportError(s);
    if (safety_violation) {
      std::cerr << "tpcal gcode: nothing written. The safety checks (strokes, rapids vs stock, tool fit) are "
                   "described in gcode/DIALECTS.md; --skip-check NAME switches one off at your own risk.\n";
    }
    return kExitBadInput;
  }

  posted->program_file = std::filesystem::path(args.output).filename().string();  // for the summary
  // Everything is formatted before the first file is written.
  struct Out {
    std::string path, text;
  };
  std::vector<Out> outs = {{args.output, posted->program_text}};
  if (!posted->tool_table_text.empty()) outs.push_back({args.output + ".tbl", posted->tool_table_text});
  if (!args.svg.empty()) outs.push_back({args.svg, posted->backplot_svg});
  if (!args.no_effective_config) {
    outs.push_back({args.output + ".testpiece.yaml",
                    "# effective test-piece configuration of " + args.output + " (--testpiece " + args.testpiece +
                        ")\n" + testpieces::FormatPieceConfig(piece->config)});
    outs.push_back({args.output + ".post.yaml",
                    "# effective post options of " + args.output + "\n" + gcode::FormatGcodeOptions(*options)});
  }
  // A missing or read-only output directory is found before the first file is written.
  for (const Out& o : outs) {
    const std::filesystem::path parent = std::filesystem::path(o.path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0) {
      return ReportError(Status(StatusCode::kIoError, "cannot write here: '" + dir + "' is not a writable directory", o.path));
    }
  }
  for (const Out& o : outs) {
    if (Status s = pipeline::WriteFileAtomic(o.path, o.text); !s.ok()) return ReportError(s);
  }

  Info(posted->Summary());
  if (!options->safety.check_strokes || !options->safety.check_rapids || !options->safety.check_tool_fit) {
    Info(fmt::format("tpcal gcode: WARNING: safety checks switched off:{}{}{}", options->safety.check_strokes ? "" : " strokes",
                     options->safety.check_rapids ? "" : " rapids", options->safety.check_tool_fit ? "" : " tool_fit"));
  }
  if (args.machine.empty()) {
    Info("tpcal gcode: no --machine: nominal " + std::string(kinematics::MachineTypeName(piece->machine.type)) +
         " machine with unlimited strokes (the stroke check checks nothing)");
  }
  for (const Out& o : outs) Info("wrote " + o.path);
  if (options->dialect == gcode::Dialect::kLinuxCnc) {
    Info("check it with LinuxCNC's interpreter: rs274 -g " + args.output + " -t " + args.output + ".tbl");
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
  sub->add_option("--testpiece", args->testpiece, "test piece: " + testpieces::PieceNameList() +
                                                     " (iso10791_m1 = iso10791_m1_320)")->required();
  sub->add_option("--config", args->config,
                  "test-piece configuration YAML (schema tpcal.testpiece/1: sizes, tools, feeds, speeds, stock; "
                  "its piece: must match --testpiece); default: the paper's / standard's piece");
  sub->add_option("--machine", args->machine,
                  "machine YAML (schema tpcal.machine/1, e.g. samples/machines/ac_table.yaml); default: nominal "
                  "ac_table (turning, cone_frustum) or xyz (M1, M2) with unlimited strokes");
  sub->add_option("--post", args->post,
                  "post options YAML (schema tpcal.gcode/1, samples/gcode/<dialect>.yaml): work offset, coolant, "
                  "block numbers, decimals, tool numbers / lengths (mm), C-axis spindle codes, five-axis mode, checks");
  sub->add_option("--dialect", args->dialect, "controller: fanuc (ISO, .nc), linuxcnc (RS274NGC, .ngc + .tbl), "
                                              "sinumerik (840D, .mpf), heidenhain (TNC 640 Klartext, .h)")
      ->required();
  sub->add_option("-o,--output", args->output,
                  "PROGRAM: the NC program file; its stem (upper case) is the program name unless --post sets "
                  "program_name")
      ->required();
  sub->add_option("--svg", args->svg, "BACKPLOT.svg: top and side view of the tool path in the part frame (mm)");
  sub->add_option("--date", args->date, "header date YYYY-MM-DD, or none; default: today (UTC)");
  sub->add_option("--skip-check", args->skip_checks,
                  "switch a safety check off: strokes, rapids or tool_fit (repeatable; at your own risk)");
  sub->add_flag("--no-effective-config", args->no_effective_config,
                "do not write PROGRAM.testpiece.yaml and PROGRAM.post.yaml");
  return {sub, [args] { return RunGcode(*args); }};
}

}  // namespace tpcal::cli
