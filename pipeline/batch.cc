#include "pipeline/batch.h"

#include <glob.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include <fmt/format.h>

#include "core/ascii.h"
#include "core/parallel.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/run_output.h"
#include "pipeline/report/run_tables.h"
#include "pipeline/report/svg_writer.h"

namespace tpcal::pipeline {
namespace {

namespace fs = std::filesystem;

bool IsPointFileName(const fs::path& p) {
  const std::string ext = AsciiLower(p.extension().string());
  return ext == ".csv" || ext == ".ply" || ext == ".pcd" || ext == ".xyz" || ext == ".txt";
}

// Unique run-directory names from the file stems, in input order.
std::vector<std::string> RunNames(const std::vector<std::string>& files) {
  std::vector<std::string> names;
  std::set<std::string> used;
  for (const auto& f : files) {
    std::string stem = fs::path(f).stem().string();
    if (stem.empty() || stem == "summary") stem = "run";
    std::string name = stem;
    for (int k = 2; !used.insert(name).second; ++k) name = fmt::format("{}-{}", stem, k);
    names.push_back(name);
  }
  return names;
}

// Parameter columns: names in order of first appearance over successful items, with units.
std::vector<std::pair<std::string, std::string>> ParameterColumns(const BatchResult& r) {
  std::vector<std::pair<std::string, std::string>> cols;
  std::set<std::string> seen;
  for (const auto& item : r.items)
    for (const auto& p : item.parameters)
      if (seen.insert(p.name).second) cols.emplace_back(p.name, p.unit);
  return cols;
}

}  // namespace

Result<std::vector<std::string>> ExpandBatchInputs(const std::string& dir_or_glob) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(dir_or_glob, ec)) {
    for (const auto& e : fs::directory_iterator(dir_or_glob, ec))
      if (e.is_regular_file() && IsPointFileName(e.path())) files.push_back(e.path().string());
    if (ec) return Status(StatusCode::kIoError, "cannot list directory: " + ec.message(), dir_or_glob);
  } else {
    glob_t g{};
    const int rc = ::glob(dir_or_glob.c_str(), 0, nullptr, &g);
    if (rc == 0)
      for (std::size_t i = 0; i < g.gl_pathc; ++i)
        if (fs::is_regular_file(g.gl_pathv[i], ec)) files.emplace_back(g.gl_pathv[i]);
    ::globfree(&g);
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
    return Status(StatusCode::kInvalidArgument, "no point files (.csv .ply .pcd .xyz .txt) match", dir_or_glob);
  return files;
}

Result<BatchResult> RunBatch(const std::vector<std::string>& files, const BatchOptions& options,
                             const BatchItemFn& on_item) {
  if (options.out_dir.empty()) return Status(StatusCode::kInvalidArgument, "batch needs an output directory (--out)");
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) return Status(StatusCode::kIoError, "cannot create directory: " + ec.message(), options.out_dir);

  BatchResult result;
  result.items.resize(files.size());
  const std::vector<std::string> names = RunNames(files);
  std::size_t done = 0;
  std::mutex mu;
  auto run_item = [&](std::size_t i) {
    const auto t0 = std::chrono::steady_clock::now();
    BatchItem item;
    item.points = files[i];
    PipelineConfig config = options.base;
    config.points = files[i];
    RunOptions run_options;
    run_options.read_threads = 1;  // the pool already uses every core
    auto run = RunPipeline(config, run_options);
    if (!run.ok()) {
      item.status = run.status().file().empty() ? run.status().WithLocation(files[i]) : run.status();
    } else {
      const auto& id = run->stage.identification;
      item.num_points = run->num_points;
      item.rms_after_um = id.rms_after_um;
      item.sigma_um = id.sigma_um;
      item.parameters = id.parameters;
      if (options.write_runs) {
        item.run_dir = (fs::path(options.out_dir) / names[i]).string();
        if (Status s = WriteDirectoryAtomic(item.run_dir, RenderRunFiles(*run)); !s.ok()) {
          item.status = s;
          item.run_dir.clear();
        }
      }
    }
    item.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lock(mu);
    result.items[i] = std::move(item);
    ++done;
    if (on_item) on_item(result.items[i], done, files.size());
  };
  // -j N bounds every thread of the batch, the items' own loops included (one shared pool).
  WithThreadLimit(options.threads, [&] { ParallelForEach(files.size(), true, run_item); });

  for (const auto& item : result.items) result.failed += item.status.ok() ? 0 : 1;
  if (Status s = WriteFileAtomic((fs::path(options.out_dir) / "summary.csv").string(), BatchSummaryCsv(result));
      !s.ok())
    return s;
  if (const std::string svg = BatchTrendSvg(result); !svg.empty()) {
    if (Status s = WriteFileAtomic((fs::path(options.out_dir) / "summary_trend.svg").string(), svg); !s.ok()) return s;
  }
  return result;
}

std::string BatchSummaryCsv(const BatchResult& r) {
  const auto cols = ParameterColumns(r);
  std::string out = "run,file,status,error,num_points,rms_after_um,sigma_um";
  for (const auto& [name, unit] : cols) out += "," + CsvCell(name + "_" + unit) + "," + CsvCell(name + "_u_" + unit);
  out += "\n";
  for (std::size_t i = 0; i < r.items.size(); ++i) {
    const auto& item = r.items[i];
    out += std::to_string(i + 1) + "," + CsvCell(item.points) + ",";
    if (!item.status.ok()) {
      out += "error," + CsvCell(item.status.ToString()) + ",,,";
      for (std::size_t k = 0; k < cols.size(); ++k) out += ",,";
      out += "\n";
      continue;
    }
    out += "ok,," + std::to_string(item.num_points) + "," + CsvNumber(item.rms_after_um) + "," +
           CsvNumber(item.sigma_um);
    for (const auto& col : cols) {
      const std::string& name = col.first;  // a named variable: clang 14 cannot capture a binding
      auto it = std::find_if(item.parameters.begin(), item.parameters.end(),
                             [&](const auto& p) { return p.name == name; });
      if (it != item.parameters.end() && it->identifiable)
        out += "," + CsvNumber(it->value) + "," + CsvNumber(it->u);
      else
        out += ",,";
    }
    out += "\n";
  }
  return out;
}

std::string BatchTrendSvg(const BatchResult& r) {
  const auto cols = ParameterColumns(r);
  if (cols.empty()) return {};
  const double pw = 340, ph = 150, W = 2 * pw;
  const int rows = (static_cast<int>(cols.size()) + 1) / 2;
  SvgWriter svg(W, 40 + ph * rows, "Machine errors across the batch",
                ".ax{stroke:#888;fill:none}.bar{stroke:#9bb8dd;stroke-width:2}.ln{stroke:#1f5fa8;fill:none;"
                "stroke-width:1.2}.pt{fill:#1f5fa8}.sm{fill:#555;font-size:9px}.lbl{fill:#222}.ttl{font-size:13px;"
                "font-weight:bold}.bad{stroke:#c0392b;stroke-width:1}");
  svg.Text(12, 22, "Identified machine errors across the batch (run index; bars: 95 % intervals; red: failed run)",
           "ttl");
  const double n = static_cast<double>(r.items.size());
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const double ox = pw * static_cast<double>(c % 2) + 40, oy = 40 + ph * static_cast<double>(c / 2);
    const double w = pw - 60, h = ph - 45;
    double lo = 0, hi = 0;
    std::vector<std::pair<double, const kinematics::ParameterEstimate*>> pts;
    for (std::size_t i = 0; i < r.items.size(); ++i)
      for (const auto& p : r.items[i].parameters)
        if (p.name == cols[c].first && p.identifiable) {
          pts.emplace_back(static_cast<double>(i), &p);
          lo = std::min({lo, p.ci95_low, p.value});
          hi = std::max({hi, p.ci95_high, p.value});
        }
    if (hi - lo < 1e-9) { lo -= 1; hi += 1; }
    auto X = [&](double i) { return ox + (n <= 1 ? w / 2 : i / (n - 1) * w); };
    auto Y = [&](double v) { return oy + 20 + (hi - v) / (hi - lo) * h; };
    svg.Text(ox, oy + 12, fmt::format("{} [{}]", cols[c].first, cols[c].second), "lbl");
    svg.Rect(ox, oy + 20, w, h, "ax");
    svg.Text(ox - 4, Y(hi) + 4, fmt::format("{:.3g}", hi), "sm", "end");
    svg.Text(ox - 4, Y(lo) + 4, fmt::format("{:.3g}", lo), "sm", "end");
    std::vector<std::pair<double, double>> line;
    for (const auto& [i, p] : pts) {
      svg.Line(X(i), Y(p->ci95_low), X(i), Y(p->ci95_high), "bar");
      line.emplace_back(X(i), Y(p->value));
    }
    if (line.size() >= 2) svg.Polyline(line, false, "ln");
    for (const auto& [x, y] : line) svg.Circle(x, y, 1.8, "pt");
    for (std::size_t i = 0; i < r.items.size(); ++i)
      if (!r.items[i].status.ok()) svg.Line(X(static_cast<double>(i)), oy + 20, X(static_cast<double>(i)), oy + 26, "bad");
  }
  return svg.Finish();
}

}  // namespace tpcal::pipeline
