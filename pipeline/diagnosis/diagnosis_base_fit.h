// Step 1 of the diagnosis (diagnosis.h): the base model fitted to the measured deviations (or
// the reference machine errors, only the re-alignment fitted), and the gap it leaves with its
// leave-one-point-out and leave-one-feature-out figures. Internal to the diagnosis library.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/slot_linearisation.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "pipeline/diagnosis/diagnosis_cv.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline::diagnosis_internal {

// The slots one linearisation writes: the base coefficients' and every machine-error candidate's.
std::vector<kinematics::ErrorSlot> DiagnosisSlotUnion(const kinematics::ErrorState& errors,
                                                      const std::vector<int>& base_coefficients,
                                                      const std::vector<kinematics::ErrorSlot>& candidate_slots);

// The base model's linear fit (display units: um, urad) at its linearisation point.
struct BaseFit {
  explicit BaseFit(kinematics::ErrorState at) : errors(std::move(at)) {}

  kinematics::ErrorState errors;   // linearisation point: the base at zero, re-linearised at the fit, or the reference
  kinematics::ActiveSet active;    // the base coefficients of `errors`
  int q_fit = 0;                   // fitted base columns (0 in reference mode)
  int nuisance_columns = 0;        // the reference's uncertainty directions, last in the design
  // Per point: the variance the reference's uncertainty adds to the gap off every fitted column
  // (DiagnosisOptions::reference_uncertainty; empty without it): its mean is taken off a
  // candidate's residual, the noise estimate and the excess's effect size.
  Eigen::VectorXd reference_var_um2;
  // The same as a factor: that variance's covariance is reference_remaining_um
  // reference_remaining_um^T (n x r, um; n x 0 or empty without). Weighed by its spread
  // (SatterthwaiteLaw) in a candidate's reduction, the excess test, the groups, harmonics and
  // outlier screen.
  Eigen::MatrixXd reference_remaining_um;
  Basis basis;                     // of the design [base columns, 6 alignment columns, nuisance columns]
  Eigen::VectorXd y;               // per point: measured - predicted deviation (- the reference's), um
  Eigen::VectorXd coef, u;         // fitted correction at `errors` and its uncertainty, per design column
  std::vector<bool> identifiable;  // per design column
  std::optional<double> held_rms_um;  // with reference_free: RMS of y with only the re-alignment fitted
  // The last linearisation (it holds every machine-error candidate's slots): the caller's
  // nominal one (DiagnosisOptions::nominal_slot_design) or one made here.
  std::shared_ptr<const kinematics::SlotDesign> design;
};

// A reference's own uncertainty along the orthonormal directions `U` (n x k, columns a
// candidate's or the verdict's): U^T R, k x r factor columns in um (k x 0 without a reference).
Eigen::MatrixXd ReferenceShareAlong(const BaseFit& fit, const Eigen::MatrixXd& U);

// The variance it adds along `U` (um^2, |U^T R|^2): what fitting them takes of it. 0 without one.
double ReferenceVarianceAlong(const BaseFit& fit, const Eigen::MatrixXd& U);

// `ssr` less what a reference's own uncertainty is expected to add to it (um^2, at least 0).
double SsrBeyondReference(const BaseFit& fit, double ssr);

// The base set `base_names` fitted with the re-alignment (Gauss-Newton: a second linearisation
// at the fit when a fitted value exceeds 1000 um / urad), or in reference mode only the
// re-alignment at the reference; `reference_dev_um` (or null) is subtracted from the measured
// deviations. Errors: unknown base parameters, kTooFewPoints (n <= fitted columns), those of the
// linearisation.
Result<BaseFit> FitBaseModel(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                             std::span<const kinematics::Observation> observations, const DiagnosisOptions& options,
                             const std::vector<std::string>& base_names, bool reference_mode,
                             const Eigen::VectorXd* reference_dev_um);

// Writes the base model's description, size and identified coefficients (fitted value =
// linearisation point + correction) into `out`.
void DescribeBaseModel(const BaseFit& fit, const DiagnosisOptions& options, bool point_reference, bool reference_mode,
                       DiagnosisResult* out);

// The gap the base model leaves, and its cross-validation: what every candidate is compared with.
struct BaseGap {
  Eigen::VectorXd r;             // residual per point (um)
  Eigen::VectorXd h;             // leverage per point (hat-matrix diagonal of the base design)
  double ssr = 0.0;              // sum of squared residuals (um^2)
  double rms_um = 0.0;           // RMS of r
  double press_rms_um = 0.0;     // leave-one-point-out RMS
  GroupCrossValidation feature_cv;  // leave-one-feature-out on the base design
  GroupCvResult cv;                 // of the base fit alone
  std::vector<std::string> feature_names;
  // Observations of unequal noise (Observation::noise_scale s_i): sum of (r_i / s_i)^2, in one
  // hit's noise (um^2), and the mean of s_i^2; ssr and 1 for hits.
  double noise_ssr = 0.0, mean_noise_scale2 = 1.0;
};

// Per observation its noise_scale (Observation::noise_scale), or empty when every one is 1 (hits).
Eigen::VectorXd NoiseScales(const testpieces::MeasuredObservations& observations);

BaseGap MakeBaseGap(const BaseFit& fit, const testpieces::MeasuredObservations& observations,
                    double holdout_tolerance);

// Writes the gap and the base's cross-validation figures into `out`.
void ReportBaseGap(const BaseGap& gap, const testpieces::MeasuredObservations& observations, DiagnosisResult* out);

// Names of the features with points that `holdable` (per feature) does not hold out.
std::vector<std::string> NotHeldOut(const BaseGap& gap, const std::vector<bool>& holdable);

// Number of true entries.
int CountTrue(const std::vector<bool>& v);

}  // namespace tpcal::pipeline::diagnosis_internal
