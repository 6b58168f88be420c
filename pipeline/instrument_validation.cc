#include "pipeline/instrument_validation.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <system_error>

#include "pipeline/datum_ball_simulate_stage.h"
#include "pipeline/diagnose_stage.h"
#include "pipeline/instrument_reference.h"
#include "pipeline/io/atomic_file.h"

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

std::string InstrumentReferenceName(const InstrumentValidationOptions& instrument) {
  return fmt::format("{} test of the cold machine (noise {:g} um)", instrument.instrument, instrument.noise_um);
}

}  // namespace

Result<ValidationSummary> RunInstrumentValidation(const LoadedPiece& setup, ValidationOptions options,
                                                  const InstrumentValidationOptions& instrument) {
  if (instrument.instrument != "datum_ball")  // the one instrument whose test is simulated here
    return Status(StatusCode::kInvalidArgument,
                  "--validate --reference-instrument " + instrument.instrument + ": expected datum_ball");
  if (!(instrument.noise_um >= 0) || !std::isfinite(instrument.noise_um))
    return Status(StatusCode::kInvalidArgument, "--reference-noise-um must be a finite number >= 0 (um)");
  InstrumentScratchDir dir;
  dir.path = std::filesystem::temp_directory_path() / fmt::format("tpcal_instrument_validation_{}", ::getpid());
  std::error_code ec;
  std::filesystem::create_directories(dir.path, ec);
  if (ec) return Status(StatusCode::kIoError, "cannot create " + dir.path.string() + ": " + ec.message());
  const std::string ballpos = (dir.path / "ballpos.csv").string();
  options.reference_name = InstrumentReferenceName(instrument);
  options.diagnose = [&](const kinematics::ErrorState& cold, const PointSet& measured,
                         std::uint64_t seed) -> Result<DiagnosisResult> {
    TPCAL_RETURN_IF_ERROR(WriteColdBallTest(setup, cold, instrument.noise_um, seed, ballpos));
    const InstrumentReferenceRequest request{
        .path = ballpos, .instrument = instrument.instrument, .setup_path = "", .machine_path = ""};
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
