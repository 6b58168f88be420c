// The report figures, as standalone SVG documents (plain SVG, no script): what metrologists
// expect from a test-piece evaluation (seed 002 Figs. 8-10 style).
//  - hole positions: measured hole centres in the datum XY plane with their deviation from the
//    nominal position (plan hole_pattern nominals) magnified (default x1000);
//  - circularity profiles: one polar panel per circularity characteristic, the LS circle as
//    the reference and dr(theta) magnified (default x10000) at the figure's length scale;
//  - vectors: concentricity (dx, dy) in um and parallelism (da, db) in urad drawn as arrows;
//  - gap: the residual of the identified model by feature (diagnosis), against the noise level;
//  - machine errors: each identified coefficient with its 95 % interval, ISO 230-1 symbol and
//    unit, non-identifiable ones marked as such (never given a value), and optional truth marks.
// Every figure function returns nullopt when the inspection has nothing to draw for it (no
// hole pattern, no circularity characteristic, ...), never an empty figure.
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gdt/inspection.h"
#include "gdt/plan.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/diagnosis.h"

namespace tpcal::pipeline {

struct FigureOptions {
  double position_magnification = 1000.0;  // hole position errors (dimensionless)
  double profile_magnification = 10000.0;   // circularity deviations (dimensionless)
};

struct Figure {
  std::string name;     // file stem: "hole_positions", "circularity", "vectors", "machine_errors"
  std::string caption;  // one sentence for the report
  std::string svg;      // complete SVG document
};

// "delta x_CR(0 deg) = E_X0C (seed 002 eq. 1)" -> "E_X0C": the ISO 230-1 symbol of a catalog
// relation without its commentary, for figure labels and terminal tables (reports carry the full text).
std::string ShortIsoSymbol(const std::string& symbol);

// Hole centres (datum XY) versus the plan's hole_pattern nominals. Needs a hole_pattern
// characteristic in `plan` with its pitch-circle feature fitted in `inspection`.
std::optional<Figure> HolePositionsFigure(const gdt::InspectionPlan& plan, const gdt::InspectionResult& inspection,
                                          const FigureOptions& options = {});

// Polar profiles of every circularity characteristic with a profile.
// A circularity profile (sorted by theta) as drawn: every sample when there are at most 2 x
// `bins`; for a dense scan, the lowest and the highest sample of each of `bins` equal angle bins,
// in angle order, so the polygon keeps the profile's envelope (its peak-to-valley) with a few
// thousand vertices instead of 1e5.
std::vector<gdt::ProfileSample> DrawnProfile(const std::vector<gdt::ProfileSample>& profile, std::size_t bins);

std::optional<Figure> CircularityFigure(const gdt::InspectionResult& inspection, const FigureOptions& options = {});

// Concentricity and parallelism characteristics as vectors.
std::optional<Figure> VectorsFigure(const gdt::InspectionResult& inspection);

// Identified coefficients with 95 % intervals (ParameterEstimate::ci95_*), grouped by unit.
// `truth` (coefficient name -> value in its display unit) adds a truth mark where given.
std::optional<Figure> MachineErrorsFigure(std::span<const kinematics::ParameterEstimate> parameters,
                                          const std::map<std::string, double>& truth = {});

// The sim-to-real gap by feature (diagnosis.h): RMS and mean of the residual per feature against
// the noise level, features standing out beyond noise in red, and the verdict in the caption.
std::optional<Figure> GapFigure(const DiagnosisResult& diagnosis);

// All figures that apply, in report order. `identification` may be null (GD&T only).
std::vector<Figure> MakeFigures(const gdt::InspectionPlan& plan, const gdt::InspectionResult& inspection,
                                const kinematics::IdentificationResult* identification,
                                const std::map<std::string, double>& truth, const FigureOptions& options = {});

}  // namespace tpcal::pipeline
