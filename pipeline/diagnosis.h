// Diagnosis of the sim-to-real gap (issue 6): where a measured test piece departs from the base
// model, which unmodelled effect explains it, and how far the gap shrinks when it is modelled.
//
// Model. The "sim" is the base model: the piece's DefaultParameterSet (location errors and
// squareness) fitted to the measured points with the 6-DOF re-alignment nuisance, or (reference
// mode) fixed machine errors given by the user, with only the re-alignment fitted. The "real" is
// the measured point file. Everything is linear least squares in display units (um, urad) on the
// design of kinematics::LineariseObservations, linearised at zero base errors (or the reference),
// re-linearised once at the fitted base when a fitted value exceeds 1000 um / urad (below that,
// second-order terms stay under 5e-4 um on a 500 mm piece). The gap is the residual per point (um, along the nominal normal,
// + = material outside the nominal surface relative to the model).
//
// Candidate effects (diagnosis_candidates.h) are small linear models added to the base design:
// machine-error families as extra ErrorState coefficients (their columns through the kinematic
// chain), process families as columns from the cut model. Each candidate is fitted jointly with
// the base and the alignment (Frisch-Waugh: on the residual, with its columns projected on the
// complement of the base design). Its directions that the base or the alignment absorb (span of
// the candidate orthonormalised, principal angles to the base design with a sine below
// `absorbed_tolerance`) are dropped:
// a candidate with no direction left is reported as unobservable on this piece and plan.
//
// Scores per candidate: in-sample RMS after and shrink; cross-validated RMS before and after =
// leave-one-point-out (PRESS residuals e_i / (1 - h_ii) of the joint fit: the effect's and the
// base's parameters fitted without the point they predict); nested F-test against the base
// (p-value, chi-square/Wilson-Hilferty approximation of the F distribution, exact enough for
// n - q > 30), delta BIC = n ln(SSR1/SSR0) + p ln n. A candidate is significant when its p-value
// is below alpha / (number of candidates) (Bonferroni: family-wise false alarm <= alpha), its
// BIC decreases and its cross-validated RMS decreases. The verdict is the significant candidate
// with the smallest cross-validated RMS (`none` if there is none). Another family is
// indistinguishable from the verdict when the verdict's columns add nothing significant (same
// alpha) to a fit that already holds that family's best candidate: the data cannot tell them apart.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "pipeline/identify_stage.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct DiagnosisOptions {
  std::vector<std::string> base_parameters;     // empty: DefaultParameterSet(piece, machine)
  // Reference mode: the "sim" is these machine errors (e.g. from a probing test); the base
  // parameters are not refitted (only the alignment), and a `location_errors` candidate (the
  // base set refitted) joins the catalogue.
  std::optional<kinematics::ErrorState> reference;
  std::string reference_name = "reference";     // for base_model in the report
  double alpha = 0.01;                // family-wise false-alarm probability of the verdict
  double absorbed_tolerance = 1e-3;   // sine of the principal angle to the base design below which a direction is absorbed
  double noise_um = 0.0;              // known CMM noise sigma (um); 0 = estimated from the residual
  int max_harmonic = 8;               // C harmonics reported per circular profile
  double stand_out_z = 4.0;           // z-score above which a group stands out beyond noise
  Status Validate() const;
};

// Gap statistics of a group of points (feature, operation, A index).
struct GroupGap {
  std::string group;
  int n_points = 0;
  double rms_um = 0.0, max_abs_um = 0.0, mean_um = 0.0;
  double mean_t_s = 0.0;    // mean machining time of the group's points
  double z = 0.0;           // (SSR / sigma^2 - n) / sqrt(2 n): excess over noise
  bool stands_out = false;  // z > stand_out_z
};

// Harmonic k of the gap around a circular profile (azimuth about the feature's centroid, part Z).
struct HarmonicGap {
  std::string feature;
  int order = 0;
  double amplitude_um = 0.0, phase_deg = 0.0;
  double z = 0.0;            // amplitude / its noise standard deviation sigma sqrt(2 / n)
  bool stands_out = false;   // z > stand_out_z
};

struct EffectParameter {
  std::string name;
  std::string unit;
  double value = 0.0, u = 0.0;   // k = 1 (analytic, residual sigma of the joint fit)
  bool identifiable = true;      // false: in a direction the base absorbs or the data do not see
};

struct BaseShift {     // change of an identified base coefficient when the effect is modelled
  std::string name;
  std::string unit;
  double without_um = 0.0, with_um = 0.0;  // display units (um or urad)
};

struct CandidateResult {
  std::string family;  // contract vocabulary (contracts README section 4)
  std::string name;
  int n_columns = 0;   // parameters of the model
  int rank = 0;        // directions left after projecting out the base (0 = unobservable)
  bool observable = false;
  double rms_after_um = 0.0, max_abs_after_um = 0.0, shrink_pct = 0.0;
  double cv_rms_before_um = 0.0, cv_rms_after_um = 0.0, cv_shrink_pct = 0.0;
  double f_stat = 0.0, p_value = 1.0, delta_bic = 0.0;
  bool significant = false;
  std::vector<EffectParameter> parameters;
  std::vector<BaseShift> base_shift;
  std::vector<double> effect_um;  // the fitted effect per point (um)
};

struct UnobservableFamily {
  std::string family;
  std::string reason;
};

struct Verdict {
  std::string family = "none";
  std::string name = "nothing beyond measurement noise";
  double shrink_pct = 0.0, cv_shrink_pct = 0.0;
  std::vector<std::string> indistinguishable_from;
  std::optional<std::string> also;  // a second family that adds significantly beyond the verdict
};

struct DiagnosisResult {
  std::string base_model;
  int n_points = 0;
  int base_columns = 0;        // identifiable base directions + alignment
  double rms_um = 0.0, max_abs_um = 0.0;   // the gap
  double noise_sigma_um = 0.0;             // sigma used for "beyond noise" (given or estimated)
  std::vector<GroupGap> by_feature, by_operation, by_a_index;
  double drift_um_per_h = 0.0, drift_u_um_per_h = 0.0;  // linear trend of the gap with t_s
  std::vector<HarmonicGap> harmonics;      // every circular profile, orders 1..max_harmonic
  std::vector<std::string> standing_out;   // names of the groups that stand out
  std::vector<EffectParameter> base_parameters;  // identified base coefficients (without effect)
  std::vector<CandidateResult> candidates;       // best first (cv_rms_after ascending; unobservable last)
  std::vector<UnobservableFamily> unobservable;  // families with no observable candidate
  Verdict verdict;
  std::vector<std::string> skipped_points;       // points no cut reaches (Diagnose), "file:line: why"
  std::vector<double> gap_um;                    // per observation
  std::vector<std::string> point_feature;        // per observation
};

// Diagnosis of observations already in the nominal part frame (identify_stage.h).
Result<DiagnosisResult> DiagnoseObservations(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine,
                                             const MeasuredObservations& observations,
                                             const DiagnosisOptions& options = {});

// Measured CMM points (any placement): datum frame from the piece's inspection plan, then
// DiagnoseObservations. Points that no cut of their feature reaches (ObservationsFromPoints'
// association failures, e.g. at a face edge) are skipped and listed in skipped_points.
// Errors: those of gdt::EvaluatePlan, unlabelled points or unknown features (file and line),
// kTooFewPoints when the base design has no residual degrees of freedom.
Result<DiagnosisResult> Diagnose(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                 const PointSet& measured, const DiagnosisOptions& options = {});

}  // namespace tpcal::pipeline
