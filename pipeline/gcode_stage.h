// The stage of `tpcal gcode`: the post options (dialect defaults or a tpcal.gcode/1 file, program
// name from the output file, header date, safety checks), the test piece, the posted NC program
// (gcode::PostProgram: IR, dialect post, safety checks, backplot) and every file to write beside
// it: PROGRAM.tbl (LinuxCNC), the backplot SVG, and the effective configuration
// (PROGRAM.testpiece.yaml, PROGRAM.post.yaml) that reproduces the program. Nothing is written here.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "gcode/options.h"
#include "gcode/post_program.h"
#include "pipeline/piece_loader.h"

namespace tpcal::pipeline {

struct GcodeRequest {
  std::string post_path;  // tpcal.gcode/1; "" = the dialect's defaults
  std::string dialect;    // fanuc, linuxcnc, sinumerik or heidenhain
  std::string output;     // PROGRAM: its stem names the program unless the post file does
  std::string svg;        // "" = no backplot file
  std::string date;       // YYYY-MM-DD; "" = today (UTC); "none" = not recorded
  std::vector<std::string> skip_checks;  // strokes, rapids, tool_fit
  bool effective_config = true;
};

struct GcodeFile {
  std::string path;
  std::string text;
};

struct GcodeStageResult {
  gcode::GcodeOptions options;
  kinematics::MachineType machine_type = kinematics::MachineType::kAcTable;  // what the piece was cut on
  gcode::PostedProgram posted;  // program_file: the output's file name
  std::vector<GcodeFile> files;  // the program first
};

// The post options of a request (dialect defaults or the --post file, program name from the
// output's stem, header date, generator, skipped checks). Errors: "tpcal gcode: --FLAG: ..." for a
// bad dialect, date or check name; post file errors (file:line).
Result<gcode::GcodeOptions> GcodeOptionsFor(const GcodeRequest& request);

// kIoError at the first file whose directory is missing or not writable (checked before any write).
Status CheckWritableDirectories(const std::vector<GcodeFile>& files);

// Program name from the output file's stem: [A-Z0-9_], starting with a letter, 24 characters.
std::string ProgramNameOf(const std::string& output);

// Errors, in this order: bad dialect, date or check name ("tpcal gcode: --FLAG: ..."), post file
// errors (file:line), the piece's (LoadPiece), a safety violation at PROGRAM ("PROGRAM: N1050:
// rapid move ...", followed by a line naming --skip-check), other post errors, and an output
// directory that is missing or read-only.
Result<GcodeStageResult> RunGcodeStage(const PieceRequest& piece, const GcodeRequest& request);

// A probing program as an instrument's post writes it (gcode::PostDatumBallProgram, ...).
struct PlanProgramText {
  std::string program;
  std::string tool_table;  // LinuxCNC only; "" otherwise
};

// The probing program of `tpcal plan --instrument ... --nc PROGRAM`. With nc.output set: the dialect
// (--dialect, or the one the program's extension names: .nc, .ngc, .mpf, .h), the post options
// (GcodeOptionsFor) into *options, then `post` with them; the program (nc.output) and its tool table
// (nc.output + ".tbl", when not empty) are appended to *files. Last, every file's directory must be
// writable (CheckWritableDirectories). Errors, in this order: kInvalidArgument at "tpcal plan" for
// no dialect, or for --dialect / --post without --nc ("--dialect needs --nc PROGRAM"); the post
// options' ("tpcal gcode" ones located at "tpcal plan"); a post error without a file located at
// PROGRAM, without the repeated program name, with "tpcal plan: nothing written" added; the
// directories'.
Status PostPlanProgram(const GcodeRequest& nc,
                       const std::function<Result<PlanProgramText>(const gcode::GcodeOptions&)>& post,
                       gcode::GcodeOptions* options, std::vector<GcodeFile>* files);

// The same with an instrument's post (`post(options)` gives a Result of
// gcode::PostedInstrumentProgram), its program kept in *posted.
template <class Posted, class Post>
Status PostPlanProgram(const GcodeRequest& nc, const Post& post, gcode::GcodeOptions* options,
                       std::optional<Posted>* posted, std::vector<GcodeFile>* files) {
  const auto text = [&](const gcode::GcodeOptions& o) -> Result<PlanProgramText> {
    Result<Posted> p = post(o);
    if (!p.ok()) return p.status();
    *posted = std::move(p).value();
    return PlanProgramText{(*posted)->program_text, (*posted)->tool_table_text};
  };
  return PostPlanProgram(nc, text, options, files);
}

}  // namespace tpcal::pipeline
