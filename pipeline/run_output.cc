#include "pipeline/run_output.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "core/parallel.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/report/run_tables.h"
#include "pipeline/report/report_html.h"
#include "pipeline/report/run_json.h"
#include "pipeline/run_config.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

Status Errno(const std::string& call, const std::string& path) {
  return Status(StatusCode::kIoError, call + ": " + std::strerror(errno), path);
}

Status FsyncDir(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Errno("open", dir.string());
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) return Errno("fsync", dir.string());
  return Status::Ok();
}

std::string RandomHex() {
  std::random_device rd;
  return fmt::format("{:08x}", rd());
}

// The pid in a sibling "<name>.tmp.<pid>.<hex>" or "<name>.old.<pid>.<hex>", or 0.
pid_t SiblingPid(const std::string& sibling, const std::string& name) {
  for (const char* kind : {".tmp.", ".old."}) {
    const std::string prefix = name + kind;
    if (sibling.rfind(prefix, 0) != 0) continue;
    const std::string rest = sibling.substr(prefix.size());
    const std::size_t dot = rest.find('.');
    if (dot == 0 || dot == std::string::npos || rest.find_first_not_of("0123456789") != dot) return 0;
    return static_cast<pid_t>(std::stol(rest.substr(0, dot)));
  }
  return 0;
}

// Removes the siblings a killed run left (their process is gone); a live run's are kept.
void RemoveStaleSiblings(const fs::path& parent, const std::string& name) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(parent, ec)) {
    const pid_t pid = SiblingPid(e.path().filename().string(), name);
    if (pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(e.path());
  }
  for (const auto& p : stale) fs::remove_all(p, ec);
}

RunSettings SettingsOf(const PipelineConfig& c) {
  return {.testpiece = c.testpiece,
          .points = c.points,
          .machine = c.machine,
          .parameters = c.parameters,
          .seed = c.seed,
          .primary = c.primary,
          .jackknife_groups = c.jackknife_groups,
          .monte_carlo_trials = c.monte_carlo_trials,
          .diagnose = c.diagnose,
          .truth = c.truth,
          .figures = c.figures,
          .reference_instrument = c.reference_instrument,
          .reference_file = c.reference_file,
          .yaml = FormatPipelineConfig(c)};
}

RawScanSummary RawScanSummaryOf(const RawScanLabeling& l) {
  RawScanSummary s{.num_points = l.num_points,
                   .num_rejected = l.num_rejected,
                   .labelled_fraction = l.labelled_fraction,
                   .rms_distance_um = l.rms_distance_um,
                   .symmetry_order = l.symmetry_order,
                   .symmetry_resolved_by = l.symmetry_resolved_by,
                   .part_from_cmm = l.part_from_cmm,
                   .points_per_feature = {},
                   .message = l.message};
  for (const auto& c : l.counts) s.points_per_feature.emplace_back(c.feature, c.points);
  return s;
}

ScanCellsSummary ScanCellsSummaryOf(const ScanCellSummary& c) {
  return {.num_points = c.num_points,
          .num_cells = c.num_cells,
          .mean_points_per_cell = c.mean_points_per_cell,
          .max_points_per_cell = c.points_per_cell_max,
          .max_cell_mm = c.max_cell_mm,
          .max_cell_deg = c.max_cell_deg,
          .on_grid = c.on_grid,
          .flagged_hits = c.flagged_hits,
          .hit_sigma_um = c.hit_sigma_um};
}

}  // namespace

RunReport ReportOf(const RunResult& r) {
  RunReport report{.settings = SettingsOf(r.config),
                   .piece_name = r.piece_name,
                   .machine_name = r.machine_name,
                   .input = {.format = PointFormatName(r.points_info.format),
                             .source_units = r.points_info.source_units == LengthUnit::kMm ? "mm" : "in",
                             .num_points = r.num_points,
                             .digest_xxh64 = r.points_digest},
                   .raw_scan = std::nullopt,
                   .scan_cells = std::nullopt,
                   .inspection = &r.stage.inspection,
                   .identification = &r.stage.identification,
                   .identification_outliers = &r.stage.outliers,
                   .identification_local_defects = &r.stage.local_defects,
                   .diagnosis = r.diagnosis ? &*r.diagnosis : nullptr,
                   .diagnosis_error = r.diagnosis ? std::string() : r.diagnosis_status.ToString(),
                   .truth = &r.truth,
                   .figures = &r.figures};
  if (r.raw_scan) report.raw_scan = RawScanSummaryOf(*r.raw_scan);
  if (r.scan_cells) report.scan_cells = ScanCellsSummaryOf(*r.scan_cells);
  return report;
}

std::vector<RunFile> RenderRunFiles(const RunResult& r) {
  const RunReport report = ReportOf(r);
  std::vector<RunFile> files;
  files.push_back({"report.html", RenderReportHtml(report)});
  files.push_back({"result.json", RunReportJson(report)});
  files.push_back({"config.yaml", FormatPipelineConfig(r.config)});
  files.push_back({"identification.csv", IdentificationCsv(r.stage.identification, r.truth)});
  files.push_back({"identifiability.csv", IdentifiabilityCsv(r.stage.identification)});
  files.push_back({"characteristics.csv", CharacteristicsCsv(r.stage.inspection)});
  files.push_back({"features.csv", FeaturesCsv(r.stage.inspection)});
  for (const auto& f : r.figures) files.push_back({"figures/" + f.name + ".svg", f.svg});
  return files;
}

Status WriteDirectoryAtomic(const std::string& out_dir, const std::vector<RunFile>& files) {
  if (out_dir.empty()) return Status(StatusCode::kInvalidArgument, "no output directory given");
  fs::path target = fs::path(out_dir).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();  // "out/run/" -> "out/run"
  const fs::path name = target.filename();
  if (name.empty() || name == "." || name == "..")
    return Status(StatusCode::kInvalidArgument, "output directory must name a directory, not '.' or '/'", out_dir);
  const fs::path parent = fs::absolute(target).parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) return Status(StatusCode::kIoError, "cannot create directory: " + ec.message(), parent.string());

  const bool exists = fs::exists(target, ec);
  if (exists) {
    if (!fs::is_directory(target, ec))
      return Status(StatusCode::kInvalidArgument, "output path exists and is not a directory", out_dir);
    if (!fs::is_empty(target, ec) && !fs::exists(target / "result.json", ec))
      return Status(StatusCode::kInvalidArgument,
                    "refusing to replace a directory that is neither empty nor a previous tpcal run (no result.json)",
                    out_dir);
  }

  RemoveStaleSiblings(parent, name.string());
  const fs::path temp = parent / fmt::format("{}.tmp.{}.{}", name.string(), ::getpid(), RandomHex());
  if (!fs::create_directory(temp, ec) || ec)
    return Status(StatusCode::kIoError, "cannot create directory: " + ec.message(), temp.string());
  auto cleanup = [&](Status s) {
    std::error_code ignored;
    fs::remove_all(temp, ignored);
    return s;
  };
  for (const auto& f : files) {
    const fs::path p = temp / f.relative_path;
    fs::create_directories(p.parent_path(), ec);
    if (ec) return cleanup(Status(StatusCode::kIoError, "cannot create directory: " + ec.message(), p.string()));
  }
  // The files are written (and fsynced) concurrently: the fsyncs then share journal commits
  // instead of waiting for one each.
  std::vector<Status> written(files.size());
  ParallelForEach(files.size(), true, [&](std::size_t i) {
    written[i] = WriteFileAtomic((temp / files[i].relative_path).string(), files[i].contents);
  });
  for (const Status& s : written)
    if (!s.ok()) return cleanup(s);
  if (Status s = FsyncDir(temp); !s.ok()) return cleanup(s);

  if (!exists) {
    if (::rename(temp.c_str(), target.c_str()) != 0) return cleanup(Errno("rename", out_dir));
  } else {
    if (::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) != 0) {
      // File systems without RENAME_EXCHANGE: move the old one aside first (a short window with
      // no `out`, never a mixed one).
      const fs::path old = parent / fmt::format("{}.old.{}.{}", name.string(), ::getpid(), RandomHex());
      if (::rename(target.c_str(), old.c_str()) != 0) return cleanup(Errno("rename", out_dir));
      if (::rename(temp.c_str(), target.c_str()) != 0) {
        const Status s = Errno("rename", out_dir);
        ::rename(old.c_str(), target.c_str());
        return cleanup(s);
      }
      fs::remove_all(old, ec);
    } else {
      fs::remove_all(temp, ec);  // now holds the previous run
    }
  }
  return FsyncDir(parent);
}

}  // namespace tpcal::pipeline
