// Screening of measured points before identification and diagnosis: single probe hits that no
// smooth surface explains (outliers: dust on a hit, a probe bounce) and small patches of one
// feature that depart together (local defects: a burr, a chip, a dent) are found and left out,
// each with its reason; what stays is what the machine model and the catalogue are fitted to.
//
// Method. r = residuals of the least-squares fit of y on the columns of X (the base model and the
// re-alignment, and in the diagnosis's second pass the verdict's effect) over the points not
// flagged, evaluated at every point. Noise sigma from neighbour differences: d_i = r_i - median
// of r over the k nearest points of the same feature (nominal positions, feature_neighbours.h),
// sigma = 1.4826 median |d_i| / sqrt(1 + v_k), v_k the variance of that median in units of
// sigma^2 (0.298 for k = 4). A smooth effect the model lacks hardly enters d, so sigma stays the
// CMM's noise when the model is incomplete (DiagnosisResult::neighbour_sigma_um). Observations
// of unequal noise (pooled scan cells, Observation::noise_scale s_i) are judged against sigma s_i,
// d_i against sigma sqrt(s_i^2 + v_k times its neighbours' mean s^2), and sigma is one hit's.
// Faults: components of same-sign neighbours beyond grow_z sigma (or beyond join_floor_z sigma
// and at least join_ratio of the member they touch: a tapering patch). One point is an outlier when
// |r_i| and its departure from its neighbours |d_i| / sqrt(1 + v_k) both exceed seed_z sigma;
// 2 to max_patch_points points holding at most max_patch_share of their feature are a local
// defect when |sum r| / sqrt(m) exceeds seed_z sigma; a larger component is systematic and stays
// (the diagnosis's business) unless it is at most twice that size, its core (the members
// connected to its peak through members of at least join_ratio of the peak) is such a patch and
// the rest lies within seed_z sigma: a 4-hit dent whose neighbours noise or the dent's pull took
// beyond grow_z, not a lobe of a smooth error. A fault that would grow a flagged patch of its sign
// beyond a patch's size is not one (the rest of something systematic). Worst first: each round
// flags the faults within a factor 2 of the largest z (|sum r| / sqrt(m) sigma) and refits (a
// gross outlier's pull on the fit is gone before its neighbours are judged), until no fault is
// left (at most 40 rounds). Finally the flagged points are grouped into
// outliers and patches, and a feature with more groups than max(2, max_components_share x its
// points) keeps all its points (an effect of short wavelength, not isolated faults).
// Thresholds: at seed_z = 4.5 a clean point is flagged with probability 7e-6, a clean pair of
// neighbours about 3e-6 (one of them may lie down to join_floor_z); a 10x-noise outlier is found
// unless its neighbours are themselves off.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/feature_neighbours.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {

struct OutlierScreenOptions {
  double seed_z = 4.5;              // |r| / sigma above which a point starts a flagged component
  // Above this many observations seed_z rises (SeedZFor) so that noise alone starts as many
  // components, in expectation, as in a file of this size (0: never): a dense scan of 2e5 points
  // screened at 4.5 sigma expects 1.4 chance outliers or patches, at 5.3 sigma 0.014. Patches
  // rise with it: grow_z and join_floor_z by seed_z's ratio, and an m-point patch is judged at
  // SeedZFor of N + m (n - N) candidates (N this size; a point starts about m times as many
  // connected m-point sets as single points).
  std::size_t seed_reference_points = 2000;
  double grow_z = 3.0;              // |r| / sigma for a neighbour to join it (same sign)
  // A neighbour down to join_floor_z sigma also joins when it is at least join_ratio of the member
  // it touches: a patch tapering off (a 2-hit burr at 5x noise has its second hit near 3.5 sigma),
  // while a clean neighbour of a gross outlier (>= 10x) is far below half of it.
  double join_floor_z = 2.5;
  double join_ratio = 0.5;
  int neighbours = 4;               // k of the neighbour comparison
  int max_patch_points = 12;        // a larger component is systematic
  double max_patch_share = 0.25;    // of its feature's points
  double max_components_share = 0.05;  // flagged components per feature point (at least 2 allowed)
  // Floor of sigma: 10 nm, below any CMM's probing noise, so that the rounding of noise-free
  // (simulated) data is not screened; the diagnosis raises it to a known noise_um.
  double min_sigma_um = 0.01;
  Status Validate() const;
};

// The seed threshold a screen of n observations uses: options.seed_z up to seed_reference_points,
// above it the z with n erfc(z / sqrt 2) = seed_reference_points erfc(seed_z / sqrt 2).
double SeedZFor(const OutlierScreenOptions& options, std::size_t n);

enum class ScreenFlag { kKept, kOutlier, kLocalDefect };

// One local defect: a patch of one feature departing together.
struct DefectPatch {
  int group = 0;                    // Observation::group of its points
  std::vector<int> members;         // observation indices, in order
  double peak_um = 0.0;             // signed residual of largest magnitude
  double mean_um = 0.0;             // mean residual over the patch
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // mean nominal position, part frame
  double extent_mm = 0.0;           // largest distance of a member from the centre
};

struct OutlierScreen {
  std::vector<ScreenFlag> flag;     // per observation
  Eigen::VectorXd residual_um;      // r of the final round, per observation
  Eigen::VectorXd neighbour_dev_um; // d of the final round, per observation
  double sigma_um = 0.0;            // noise sigma from neighbour differences
  double sigma_dof = 0.0;           // its effective degrees of freedom (MAD: 0.37 n)
  std::vector<DefectPatch> patches;
  std::shared_ptr<const FeatureNeighbourGraph> neighbours;  // the graph used, to screen these observations again
  int rounds = 0;
  int CountFlagged() const;
  std::vector<int> KeptIndices() const;  // observations with kKept, in order
};

// Screens the observations: X (n x p, any scaling; rank-deficient allowed) the linear model, y
// (n) the deviations to explain (um), observations for their groups and nominal positions. With
// fewer than 3 points in a feature its points are never flagged. With a reference's leftover
// uncertainty (its factor, n rows x r, um: BaseFit::reference_remaining_um, off the base's columns
// but not off further columns of X, which makes the bounds a little wide; no column: none), a
// fault's tests weigh the variance it adds to a hit, to its departure from its neighbours and to
// a patch's sum beside the noise's. `neighbours`: a graph of these observations made before (used
// when it Fits; else one is made). Never fails: a design with no residual freedom flags nothing.
OutlierScreen ScreenOutliers(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                             std::span<const kinematics::Observation> observations,
                             const OutlierScreenOptions& options = {},
                             const Eigen::MatrixXd& reference_remaining_um = Eigen::MatrixXd(),
                             std::shared_ptr<const FeatureNeighbourGraph> neighbours = nullptr);

// The reason a flagged observation is left out, for listings: "outlier: 12.3 um from the model,
// 11.8 um from its 4 neighbours (noise 0.50 um)" or "local defect: one of 3 points on S2 ...".
std::string ScreenReason(const OutlierScreen& screen, int observation, const std::string& feature);

// A measured point the outlier screen flagged (outlier_screen.h).
struct ScreenedPoint {
  std::size_t point_index = 0;  // into the measured PointSet
  std::size_t line = 0;         // its source line (AttachScreenLines; 0 = not from a text file)
  std::string feature;
  std::string kind;             // "outlier" or "local_defect"
  double deviation_um = 0.0;    // from the base model fitted without it (normal direction)
  std::string reason;
  bool left_out = true;         // false with DiagnosisOptions::screen_outliers off
};

// A patch of one feature departing together (burr, chip, dent, dirt).
struct LocalDefect {
  std::string feature;
  int n_points = 0;
  double peak_um = 0.0, mean_um = 0.0;                  // signed, normal direction
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // nominal position, part frame
  double extent_mm = 0.0;                               // largest distance of a point from the centre
  std::vector<std::size_t> point_index, lines;          // lines filled by AttachScreenLines
};

// The flagged observations of `mo` as listed points (lines 0 until AttachScreenLines) and its
// patches; `left_out` says whether they were left out of the fit.
void ListFlagged(const OutlierScreen& screen, const testpieces::MeasuredObservations& mo, bool left_out,
                 std::vector<ScreenedPoint>* points, std::vector<LocalDefect>* defects);

// Fills the source lines of listed points and patches from the measured point file.
void AttachScreenLines(const PointSet& measured, std::vector<ScreenedPoint>* points, std::vector<LocalDefect>* defects);

// The observations `rows` of `all` (feature names and groups unchanged, point_index kept).
testpieces::MeasuredObservations ObservationRows(const testpieces::MeasuredObservations& all, std::span<const int> rows);

}  // namespace tpcal::pipeline
