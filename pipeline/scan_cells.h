// Data reduction of dense scans before identification and diagnosis: consecutive points of one
// scan line (same feature, same operation, neighbours in space and in cutting time) are pooled
// into short cells, each replaced by one observation: the cut of the member nearest the cell's
// centroid, measured at the deviation a straight line fitted to the members' normal deviations
// (n0 . (m - p0), against the distance along the cell) predicts there. The line is fitted to the
// deviations less their feature's smooth part (a quadratic in the nominal position fitted to all
// the feature's points: a hole's offset, tilt and oval, a face's bow), added back at the
// representative.
//
// What it keeps: every effect that is smooth over a cell. A cell of length L is a box filter of
// what the feature's quadratic leaves; it attenuates a profile harmonic of wavelength lambda by
// about (pi L / lambda)^2 / 6 (0.13 % for a 5-lobe profile over a 2 deg cell) and leaves linear
// trends along the line exact. What it changes: the noise of a cell is the CMM noise times its
// Observation::noise_scale, the line's prediction error at the representative, sqrt(1 / k +
// t^2 / S_tt) for k points (about 1 / sqrt(k)): cells of unequal size have unequal noise, which
// the identification (weighted least squares) and the diagnosis's noise tests weigh. Every count,
// RMS and maximum downstream is per cell. Cells follow scan order (a file in the order the CMM took the points). A file that is not
// (consecutive points pool fewer than 3 a cell) is pooled on a fixed grid instead: one cell per
// bin of feature, operation, feed direction, cutting-time window, axis commands, nominal point
// and normal (the caps as bin widths, half the normal turn), split at the points cap, its value
// that of a line or plane fitted over the directions its members span (noise_scale alike).
// Before a cell is valued its single hits are screened (hit_outlier_z): a hit departing from the
// fit through the cell's other members by more than that many of one hit's sigma (robust, from all
// cells) is flagged and left out of it, worst first, while the fit keeps 2 degrees of freedom; two
// flagged hits side by side with one sign are a patch and stay, for the screen of cells.
#pragma once

#include <cstddef>
#include <optional>

#include "core/status.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {

struct ScanCellOptions {
  // Only files with more points than this are reduced (0: never). The 16-points-per-face plans
  // and dense plans of 1e5 points are identified point by point.
  std::size_t above_points = 250000;
  // Points per cell at most; 0 = n / target_cells, rounded up.
  std::size_t points_per_cell = 0;
  std::size_t target_cells = 100000;
  // A cell's extent at most: in space and in every linear axis command (mm), in every rotary axis
  // command (deg), and in the turn of the surface normal (deg). Machine errors are functions of
  // the axes: a cell is short where the table turns fast and long where no axis moves much (one
  // plunge, one generatrix). The normal turn bounds the filtering of the piece's own harmonics:
  // 10 deg attenuates a first harmonic (an offset hole) by 0.13 %.
  double max_cell_mm = 4.0;
  double max_cell_deg = 2.0;
  double max_normal_turn_deg = 10.0;
  double max_step_mm = 2.0;       // consecutive points farther apart start a new cell
  // Consecutive points cut further apart in time, or with another feed direction, or a step back
  // in cutting time after steps forward (another pass), start a new cell.
  double max_time_step_s = 10.0;
  // Single hits departing from the fit through their cell's other members by more than this many
  // of one hit's sigma (> 0) are flagged, and left out of their cell unless leave_out_flagged_hits
  // is off. 0: RunIdentifyStage takes its outlier screen's seed threshold for the file's size
  // (SeedZFor: 5.8 for 2e6 hits), ReduceToScanCells alone screens none; negative: none.
  double hit_outlier_z = 0.0;
  bool leave_out_flagged_hits = true;
  Status Validate() const;
};

// A hit of a dense scan that departs from its cell (ReduceToScanCells).
struct FlaggedHit {
  std::size_t point_index = 0;  // into the measured PointSet
  std::size_t observation = 0;  // into the per-point observations
  double departure_um = 0.0;    // from the fit through its cell's other hits, along the nominal normal
  double z = 0.0;               // in its sigma (one hit's, times the fit's leverage)
  int cell_hits = 0;            // hits of its cell, itself included
};

struct ScanCells {
  testpieces::MeasuredObservations observations;        // one per cell; point_index: the representative point
  std::vector<std::uint32_t> cell_points;   // members of each cell
  std::size_t num_points = 0;               // points before the reduction
  std::size_t points_per_cell_max = 0;      // the cap used
  double max_cell_mm = 0.0;
  double max_cell_deg = 0.0;
  bool on_grid = false;                     // cells of a fixed grid (the file not in scan order)
  std::vector<FlaggedHit> flagged_hits;     // in cell order
  double hit_sigma_um = 0.0;                // one hit's noise about its cell's fit (robust); 0: not screened
  double hit_outlier_z = 0.0;               // the threshold used
  bool hits_left_out = true;                // flagged hits left out of their cells
};

// What a run reports of the reduction.
struct ScanCellSummary {
  std::size_t num_points = 0;           // observations before
  std::size_t num_cells = 0;            // observations after
  std::size_t points_per_cell_max = 0;  // the cap used
  double max_cell_mm = 0.0;
  double max_cell_deg = 0.0;
  double mean_points_per_cell = 0.0;
  bool on_grid = false;
  std::size_t flagged_hits = 0;         // single hits flagged inside their cells
  double hit_sigma_um = 0.0;            // one hit's noise about its cell's fit (0: not screened)
};
ScanCellSummary Summarise(const ScanCells& cells);

// Pools `per_point` (one observation per point, in file order) into scan-line cells. Returns
// nullopt when the file is not above `options.above_points`. Errors: invalid options.
Result<std::optional<ScanCells>> ReduceToScanCells(const testpieces::MeasuredObservations& per_point,
                                                   const ScanCellOptions& options = {});

}  // namespace tpcal::pipeline
