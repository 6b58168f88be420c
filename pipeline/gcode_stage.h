// The stage of `tpcal gcode`: the post options (dialect defaults or a tpcal.gcode/1 file, program
// name from the output file, header date, safety checks), the test piece, the posted NC program
// (gcode::PostProgram: IR, dialect post, safety checks, backplot) and every file to write beside
// it: PROGRAM.tbl (LinuxCNC), the backplot SVG, and the effective configuration
// (PROGRAM.testpiece.yaml, PROGRAM.post.yaml) that reproduces the program. Nothing is written here.
#pragma once

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

// For the instruments' probing programs (`tpcal plan --instrument ... --nc PROGRAM`):
// --dialect, or the dialect the program's extension names (.nc, .ngc, .mpf, .h). Errors:
// kInvalidArgument at "tpcal plan" when neither names one.
Result<std::string> PlanProgramDialect(const GcodeRequest& nc);
// A program error without a file ("NAME.ngc: N40: rapid target outside ...") located at the
// program's path, without the repeated program name, and "tpcal plan: nothing written" added.
Status LocatePlanProgramError(const Status& s, const gcode::GcodeOptions& options, const std::string& path);

}  // namespace tpcal::pipeline
