#include "pipeline/run_stage.h"

#include <fmt/format.h>

#include <chrono>

#include "kinematics/error_state.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/identified_gap.h"
#include "pipeline/instrument_reference.h"
#include "pipeline/io/file_bytes.h"
#include "pipeline/piece_loader.h"
#include "pipeline/raw_scan_labeling.h"
#include "pipeline/run_sample.h"
#include "pipeline/io/xxh64.h"
#include "pipeline/io/xyzijk_reader.h"
#include "testpieces/default_parameters.h"

namespace tpcal::pipeline {
namespace {

class StageClock {
 public:
  StageClock(std::vector<StageTiming>* timings, const ProgressFn& progress) : timings_(timings), progress_(progress) {}
  void Start(const char* stage) {
    Stop();
    stage_ = stage;
    t0_ = std::chrono::steady_clock::now();
    if (progress_) progress_(stage);
  }
  void Stop() {
    if (stage_.empty()) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    timings_->push_back({stage_, s});
    stage_.clear();
  }

 private:
  std::vector<StageTiming>* timings_;
  const ProgressFn& progress_;
  std::string stage_;
  std::chrono::steady_clock::time_point t0_;
};

// A reference instrument the user asked for is input: its file (or set-up) unreadable or
// malformed, its test not identifiable, or of another machine type, the run stops before any
// output with that status (file:line); what the comparison cannot do later (e.g. no residual
// degrees of freedom) is the diagnosis's status, as without a reference.
Result<std::optional<InstrumentReference>> RunReference(const PipelineConfig& config, const LoadedPiece& setup) {
  if (config.reference_file.empty()) return std::optional<InstrumentReference>();
  auto ref = IdentifyInstrumentReference(setup, {.path = config.reference_file,
                                                 .instrument = config.reference_instrument,
                                                 .setup_path = config.reference_setup,
                                                 .machine_path = config.machine,
                                                 .probe_radius_mm = config.reference_probe_radius_mm});
  if (!ref.ok()) return ref.status().WithContext("the reference instrument (" + config.reference_instrument + ")");
  return std::optional<InstrumentReference>(std::move(*ref));
}

}  // namespace

Result<RunResult> RunPipeline(const PipelineConfig& config, const RunOptions& options) {
  if (Status s = config.Validate(); !s.ok()) return s;
  std::vector<StageTiming> timings;
  StageClock clock(&timings, options.progress);

  clock.Start("setup");
  auto setup = LoadPiece({.testpiece = config.testpiece, .machine_path = config.machine, .allow_piece_file = true});
  if (!setup.ok()) return setup.status();
  auto reference = RunReference(config, *setup);
  if (!reference.ok()) return reference.status();

  clock.Start("read");
  PointReadOptions read;
  read.threads = options.read_threads;
  read.columns = config.columns;
  // The file's bytes are read once: hashed for the digest, and parsed from memory when the
  // format is text (PLY and PCD go through PCL's own readers).
  auto bytes = ReadFileBytes(config.points);
  if (!bytes.ok()) return bytes.status();
  const std::string digest = fmt::format("{:016x}", Xxh64(bytes->view()));
  const PointFormat format = read.format == PointFormat::kAuto ? PointFormatFromExtension(config.points) : read.format;
  auto file = format == PointFormat::kCsv   ? ParsePointCsv(bytes->view(), config.points, read)
              : format == PointFormat::kXyz && !IsXyzijkText(bytes->view()) ? ParsePointXyz(bytes->view(), config.points, read)
                                            : ReadPointFile(config.points, read);
  bytes->data.reset();
  if (!file.ok()) return file.status();

  const std::size_t num_points_in_file = file->points.size();
  std::optional<RawScanLabeling> raw_scan;
  if (!file->points.has_labels()) {  // a raw scan: assign points to nominal features first
    clock.Start("label");
    RawScanLabelingOptions labelling;
    labelling.anchor_feature = config.anchor_feature;
    labelling.anchor_near_mm = config.anchor_near_mm;
    auto labelled = LabelIfRawScan(setup->piece, &file->points, labelling);
    if (!labelled.ok()) return labelled.status();
    raw_scan = std::move(*labelled);
  }

  std::vector<std::string> parameters =
      config.parameters.empty() ? testpieces::DefaultParameterSet(setup->piece, setup->machine) : config.parameters;
  {
    kinematics::ErrorState probe(setup->machine);
    auto active = kinematics::ActivateParameters(setup->machine, &probe, parameters);
    if (!active.ok()) return active.status().WithLocation(config.source.empty() ? "--parameters" : config.source);
  }
  // The identification stage of `tpcal identify`, with the run's options: the same parameters,
  // values and u to the last bit.
  IdentifyStageOptions stage_options;
  stage_options.parameters = parameters;
  stage_options.identify.primary = config.primary;
  stage_options.identify.jackknife_groups = config.jackknife_groups;
  stage_options.identify.monte_carlo_trials = config.monte_carlo_trials;
  stage_options.identify.seed = config.seed;
  stage_options.scan_cells = config.scan_cells;
  stage_options.screen_outliers = !config.keep_outliers;
  stage_options.on_step = [&clock](const char* step) { clock.Start(step); };
  auto stage = RunIdentifyStage(setup->piece, setup->machine, file->points, stage_options);
  if (!stage.ok()) return stage.status();

  std::optional<DiagnosisResult> diagnosis;
  Status diagnosis_status;
  if (config.diagnose) {
    clock.Start("diagnose");
    DiagnosisOptions gap_options;
    gap_options.screen_outliers = !config.keep_outliers;
    // The run's identification is reused for error maps when its screen flagged nothing, and for
    // parameters when its set is the instrument's; else the comparison identifies the piece again.
    auto d = !*reference ? DiagnoseIdentified(setup->piece, setup->machine, *stage, file->points, gap_options)
                         : DiagnoseAgainstInstrument(*setup, file->points, **reference, gap_options, &*stage);
    if (d.ok())
      diagnosis = std::move(*d);
    else
      diagnosis_status = d.status();
  }

  std::map<std::string, double> truth;
  if (!config.truth.empty()) {
    std::vector<std::string> names;
    for (const auto& p : stage->identification.parameters) names.push_back(p.name);
    auto t = LoadTruthValues(config.truth, names);
    if (!t.ok()) return t.status();
    truth = std::move(*t);
  }

  clock.Start("figures");
  RunResult r{.config = config,
              .piece_name = setup->piece.name,
              .machine_name = setup->machine.name,
              .plan = setup->piece.inspection,
              .points_info = file->info,
              .num_points = num_points_in_file,
              .raw_scan = std::move(raw_scan),
              .points_digest = digest,
              .scan_cells = stage->scan_cells,
              .stage = std::move(*stage),
              .diagnosis = std::move(diagnosis),
              .diagnosis_status = diagnosis_status,
              .truth = std::move(truth),
              .figures = {},
              .timings = {}};
  r.config.parameters = parameters;
  r.figures = MakeFigures(r.plan, r.stage.inspection, &r.stage.identification, r.truth, config.figures);
  if (r.diagnosis) {
    if (auto f = GapFigure(*r.diagnosis)) r.figures.push_back(std::move(*f));
  }
  clock.Stop();
  r.timings = std::move(timings);
  if (options.progress) options.progress("done");
  return r;
}

}  // namespace tpcal::pipeline
