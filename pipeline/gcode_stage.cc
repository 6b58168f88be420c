#include "pipeline/gcode_stage.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>

#include "gcode/options_yaml.h"
#include "pipeline/version.h"
#include "testpieces/piece_config.h"

namespace tpcal::pipeline {
namespace {

Status GcodeArgError(const std::string& message) {
  return Status(StatusCode::kInvalidArgument, message, "tpcal gcode");
}

std::string TodayUtc() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

// A post error without a file: a safety violation ("NAME.ngc: N1050: rapid move ...") is
// reported at PROGRAM with a hint; option errors ("tools: ...") belong to the post file.
Status LocatePostError(const GcodeRequest& args, const gcode::GcodeOptions& options, Status s) {
  if (!s.file().empty()) return s;
  std::string message = s.message();
  const std::string posted_name = options.program_name + gcode::ProgramExtension(options.dialect) + ": ";
  const bool safety_violation = message.rfind(posted_name, 0) == 0;
  if (safety_violation) {
    message.erase(0, posted_name.size());
    message +=
        "\ntpcal gcode: nothing written. The safety checks (strokes, rapids vs stock, tool fit) are "
        "described in gcode/DIALECTS.md; --skip-check NAME switches one off at your own risk.";
  }
  const bool post_key = !args.post_path.empty() && message.rfind("tools:", 0) == 0;
  return Status(s.code(), message, post_key ? args.post_path : args.output);
}

// --dialect, or the dialect the program's extension names (.nc, .ngc, .mpf, .h).
Result<std::string> PlanProgramDialect(const GcodeRequest& nc) {
  if (!nc.dialect.empty()) return nc.dialect;
  const std::string ext = std::filesystem::path(nc.output).extension().string();
  for (gcode::Dialect d : {gcode::Dialect::kFanuc, gcode::Dialect::kLinuxCnc, gcode::Dialect::kSinumerik,
                           gcode::Dialect::kHeidenhain}) {
    if (ext == gcode::ProgramExtension(d)) return std::string(gcode::DialectName(d));
  }
  return Status(StatusCode::kInvalidArgument,
                "--dialect: needed for --nc " + nc.output +
                    " (fanuc, linuxcnc, sinumerik or heidenhain; or name the program .nc, .ngc, .mpf or .h)",
                "tpcal plan");
}

// A program error without a file ("NAME.ngc: N40: rapid target outside ...") located at the
// program's path, without the repeated program name, and "tpcal plan: nothing written" added.
Status LocatePlanProgramError(const Status& s, const gcode::GcodeOptions& options, const std::string& path) {
  if (!s.file().empty()) return s;
  std::string message = s.message();
  const std::string name = options.program_name + gcode::ProgramExtension(options.dialect) + ": ";
  if (message.rfind(name, 0) == 0) message.erase(0, name.size());
  return Status(s.code(), message + "\ntpcal plan: nothing written", path);
}

}  // namespace

Result<gcode::GcodeOptions> GcodeOptionsFor(const GcodeRequest& args) {
  const auto dialect = gcode::DialectFromName(args.dialect);
  if (!dialect) {
    return GcodeArgError("--dialect: expected fanuc, linuxcnc, sinumerik or heidenhain, got '" + args.dialect + "'");
  }
  gcode::GcodeOptions o = gcode::GcodeOptions::ForDialect(*dialect);
  bool named_in_file = false;
  if (!args.post_path.empty()) {
    auto loaded = gcode::LoadGcodeOptions(args.post_path);
    if (!loaded.ok()) return loaded.status();
    o = std::move(*loaded);
    if (o.dialect != *dialect) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("dialect: the post options are for ") + gcode::DialectName(o.dialect) +
                        ", but --dialect is " + args.dialect,
                    args.post_path);
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
    if (!ok) return GcodeArgError("--date: expected YYYY-MM-DD or none, got '" + d + "'");
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
      return GcodeArgError("--skip-check: expected strokes, rapids or tool_fit, got '" + check + "'");
    }
  }
  if (Status s = o.Validate(); !s.ok()) return s.WithLocation(args.post_path.empty() ? "tpcal gcode" : args.post_path);
  return o;
}

Status CheckWritableDirectories(const std::vector<GcodeFile>& files) {
  for (const GcodeFile& f : files) {
    const std::filesystem::path parent = std::filesystem::path(f.path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
      return Status(StatusCode::kIoError, "cannot write here: '" + dir + "' is not a writable directory", f.path);
  }
  return Status::Ok();
}

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

Result<GcodeStageResult> RunGcodeStage(const PieceRequest& piece, const GcodeRequest& request) {
  auto options = GcodeOptionsFor(request);
  if (!options.ok()) return options.status();
  auto loaded = LoadPiece(piece);
  if (!loaded.ok()) return loaded.status();
  auto posted = gcode::PostProgram(loaded->piece, *options);
  if (!posted.ok()) return LocatePostError(request, *options, posted.status());

  posted->program_file = std::filesystem::path(request.output).filename().string();  // for the summary
  std::vector<GcodeFile> files = {{request.output, posted->program_text}};
  if (!posted->tool_table_text.empty()) files.push_back({request.output + ".tbl", posted->tool_table_text});
  if (!request.svg.empty()) files.push_back({request.svg, posted->backplot_svg});
  if (request.effective_config) {
    files.push_back({request.output + ".testpiece.yaml", "# effective test-piece configuration of " + request.output +
                                                             " (--testpiece " + piece.testpiece + ")\n" +
                                                             testpieces::FormatPieceConfig(loaded->piece.config)});
    files.push_back({request.output + ".post.yaml",
                     "# effective post options of " + request.output + "\n" + gcode::FormatGcodeOptions(*options)});
  }
  if (Status s = CheckWritableDirectories(files); !s.ok()) return s;
  return GcodeStageResult{std::move(*options), loaded->piece.machine.type, std::move(*posted), std::move(files)};
}

Status PostPlanProgram(const GcodeRequest& request,
                       const std::function<Result<PlanProgramText>(const gcode::GcodeOptions&)>& post,
                       gcode::GcodeOptions* options, std::vector<GcodeFile>* files) {
  if (!request.output.empty()) {
    GcodeRequest nc = request;
    auto dialect = PlanProgramDialect(nc);
    if (!dialect.ok()) return dialect.status();
    nc.dialect = *dialect;
    auto effective = GcodeOptionsFor(nc);
    if (!effective.ok())
      return effective.status().file() == "tpcal gcode" ? effective.status().WithLocation("tpcal plan")
                                                        : effective.status();
    *options = *effective;
    auto posted = post(*options);
    if (!posted.ok()) return LocatePlanProgramError(posted.status(), *options, nc.output);
    files->push_back({nc.output, posted->program});
    if (!posted->tool_table.empty()) files->push_back({nc.output + ".tbl", posted->tool_table});
  } else if (!request.dialect.empty() || !request.post_path.empty()) {
    return Status(StatusCode::kInvalidArgument,
                  std::string(request.dialect.empty() ? "--post" : "--dialect") + " needs --nc PROGRAM", "tpcal plan");
  }
  return CheckWritableDirectories(*files);
}

}  // namespace tpcal::pipeline
