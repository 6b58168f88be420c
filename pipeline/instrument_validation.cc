#include "pipeline/instrument_validation.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <system_error>

#include "kinematics/ballbar_setup.h"
#include "kinematics/machine_yaml.h"
#include "kinematics/probe_artifacts.h"
#include "pipeline/ballbar_simulate_stage.h"
#include "pipeline/datum_ball_simulate_stage.h"
#include "pipeline/diagnose_stage.h"
#include "pipeline/instrument_reference.h"
#include "pipeline/io/atomic_file.h"
#include "pipeline/probe_artifacts_simulate_stage.h"

namespace tpcal::pipeline {
namespace {

// A temporary folder, removed with this object.
struct InstrumentScratchDir {
  std::filesystem::path path;
  ~InstrumentScratchDir() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove_all(path, ec);
  }
};

// The datum-ball test of the cold machine (A at 0, -30, -60, -90 deg, C every 30 deg, the
// seed-001 ball), written to `path`.
Status WriteColdBallTest(const LoadedPiece& setup, const kinematics::ErrorState& cold, double noise_um,
                         std::uint64_t seed, const std::string& path) {
  DatumBallSimRequest request;
  request.plan.tilt_deg = {0.0, -30.0, -60.0, -90.0};
  request.noise_um = noise_um;
  request.seed = seed;
  request.output_path = path;
  auto sim = SimulateDatumBall(setup.machine, cold, request);
  if (!sim.ok()) return sim.status();
  return WriteFileAtomic(path, sim->csv);
}

// The probing test of seed 000's artifacts on the cold machine (seed 000's A positions, C every
// 15 deg: the maps' nodes then lie within 15 deg of every C the piece is cut at), written to `path`.
Status WriteColdProbingTest(const LoadedPiece& setup, const kinematics::ErrorState& cold, double noise_um,
                            std::uint64_t seed, const std::string& path) {
  ProbeArtifactsSimRequest request;
  request.plan.c_step_deg = 15.0;
  request.noise_um = noise_um;
  request.seed = seed;
  request.output_path = path;
  auto sim = SimulateProbeArtifacts(setup.machine, cold, kinematics::Seed000Artifacts(), request);
  if (!sim.ok()) return sim.status();
  return WriteFileAtomic(path, sim->csv);
}

// The ball bar round C on the cold machine, A held at 0 (seed 003's C table,
// kinematics::Seed003CTableSetup), written to `path`.
Status WriteColdBallbarTest(const LoadedPiece& setup, const kinematics::BallbarSetup& installations,
                            const kinematics::ErrorState& cold, double noise_um, std::uint64_t seed,
                            const std::string& path) {
  BallbarSimRequest request;
  request.noise_um = noise_um;
  request.seed = seed;
  auto sim = SimulateBallbar(setup.machine, cold, installations, request);
  if (!sim.ok()) return sim.status();
  return WriteFileAtomic(path, sim->csv);
}

// The ball bar's set-up (setup.yaml) and the machine (machine.yaml), written once to `dir`.
Status WriteBallbarFiles(const LoadedPiece& setup, const kinematics::BallbarSetup& installations,
                         const std::filesystem::path& dir) {
  TPCAL_RETURN_IF_ERROR(WriteFileAtomic((dir / "setup.yaml").string(), kinematics::FormatBallbarSetup(installations)));
  return WriteFileAtomic((dir / "machine.yaml").string(), kinematics::FormatMachineModel(setup.machine));
}

std::string InstrumentReferenceName(const InstrumentValidationOptions& instrument) {
  return fmt::format("{} test of the cold machine (noise {:g} um)", instrument.instrument, instrument.noise_um);
}

}  // namespace

Result<ValidationSummary> RunInstrumentValidation(const LoadedPiece& setup, ValidationOptions options,
                                                  const InstrumentValidationOptions& instrument) {
  const bool ball = instrument.instrument == "datum_ball", bar = instrument.instrument == "ballbar";
  if (!ball && !bar && instrument.instrument != "probe_artifacts")
    return Status(StatusCode::kInvalidArgument, "--validate --reference-instrument " + instrument.instrument +
                                                    ": expected datum_ball, probe_artifacts or ballbar");
  if (!(instrument.noise_um >= 0) || !std::isfinite(instrument.noise_um))
    return Status(StatusCode::kInvalidArgument, "--reference-noise-um must be a finite number >= 0 (um)");
  InstrumentScratchDir dir;
  dir.path = std::filesystem::temp_directory_path() / fmt::format("tpcal_instrument_validation_{}", ::getpid());
  std::error_code ec;
  std::filesystem::create_directories(dir.path, ec);
  if (ec) return Status(StatusCode::kIoError, "cannot create " + dir.path.string() + ": " + ec.message());
  const std::string file = (dir.path / (ball ? "ballpos.csv" : bar ? "ballbar.csv" : "probepts.csv")).string();
  const kinematics::BallbarSetup installations = kinematics::Seed003CTableSetup(kinematics::Axis::kA);
  if (bar) TPCAL_RETURN_IF_ERROR(WriteBallbarFiles(setup, installations, dir.path));
  options.reference_name = InstrumentReferenceName(instrument);
  options.diagnose = [&](const kinematics::ErrorState& cold, const PointSet& measured,
                         std::uint64_t seed) -> Result<DiagnosisResult> {
    TPCAL_RETURN_IF_ERROR(ball  ? WriteColdBallTest(setup, cold, instrument.noise_um, seed, file)
                          : bar ? WriteColdBallbarTest(setup, installations, cold, instrument.noise_um, seed, file)
                                : WriteColdProbingTest(setup, cold, instrument.noise_um, seed, file));
    const InstrumentReferenceRequest request{.path = file,
                                             .instrument = instrument.instrument,
                                             .setup_path = bar ? (dir.path / "setup.yaml").string() : "",
                                             .machine_path = bar ? (dir.path / "machine.yaml").string() : ""};
    return DiagnoseAgainstInstrument(setup, measured, request, DiagnosisOptions{});
  };
  return RunValidation(setup.piece, setup.machine, options);
}

Result<std::string> RunInstrumentValidationStage(const LoadedPiece& setup, const ValidationOptions& options,
                                                 const InstrumentValidationOptions& instrument) {
  auto summary = RunInstrumentValidation(setup, options, instrument);
  if (!summary.ok()) return summary.status();
  ValidationOptions named = options;
  named.reference_name = InstrumentReferenceName(instrument);
  return ValidationStageMarkdown(setup, named, *summary);
}

}  // namespace tpcal::pipeline
