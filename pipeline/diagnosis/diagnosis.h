// Diagnosis of the sim-to-real gap (issue 6): where a measured test piece departs from the base
// model, which unmodelled effect explains it, and how far the gap shrinks when it is modelled.
//
// Model. The "sim" is one of three:
//  * the base model (default): the piece's DefaultParameterSet (location errors and squareness)
//    fitted to the measured points with the 6-DOF re-alignment nuisance;
//  * reference machine errors (DiagnosisOptions::reference, e.g. from a probing test): fixed, only
//    the re-alignment is fitted (with reference_free, those parameters too; with
//    reference_uncertainty, the directions the reference's own uncertainty moves the piece along);
//  * a reference point file (DiagnoseAgainstPoints, e.g. the piece simulated from known errors, or
//    a second measurement): the gap is the measured normal deviation minus the reference's normal
//    deviation at the associated reference point, with only the re-alignment fitted. Both files
//    are put in their own datum frame (the piece's inspection plan) and associated per feature
//    label: by order within the feature when both have the same number of points and every pair's
//    nominal positions (part frame) lie within `reference_match_mm`; otherwise each measured
//    point takes the reference point of its feature with the nearest nominal position (ties: the
//    first in file order), and a point with none within `reference_match_mm` is skipped and
//    listed. Deviations are normal deviations at each point's own nominal position; for two files
//    of the same probing plan the positions differ by the errors (tens of um), so the deviation
//    field's change between them is negligible. The noise of the gap is then
//    sqrt(sigma_measured^2 + sigma_reference^2).
// The "real" is the measured point file. Everything is linear least squares in display units (um, urad) on the
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
// Scores per candidate: in-sample RMS after and shrink; cross-validated RMS before and after by
// leave-one-FEATURE-out (diagnosis_cv.h): each measured feature is predicted by the joint fit
// (base + re-alignment + candidate) on the other features, e_G(-G) = (I - H_GG)^-1 e_G (Woodbury,
// p x p per feature); "before" is the same for the base fit alone. A feature whose points alone
// determine a direction of the joint design (smallest eigenvalue of the information the other
// features carry, relative to the whole design's, below `holdout_tolerance`) cannot be predicted:
// it is left out of both sums of that candidate and listed (cv_not_held_out; the base's own list
// in DiagnosisResult). The point figure (PRESS, leave-one-point-out e_i / (1 - h_ii)) is kept as
// press_rms_before_um / press_rms_after_um. Also: nested F-test against the base (p-value,
// chi-square/Wilson-Hilferty approximation of the F distribution, exact enough for n - q > 30)
// and delta BIC = n ln(SSR1/SSR0) + p ln n (tie-break of the ranking, below). A candidate is
// significant when its p-value is below alpha / (number of candidates) (Bonferroni: family-wise
// false alarm <= alpha) and its feature-CV RMS decreases (after < before over the same held-out
// features; a candidate with no held-out feature cannot pass). A candidate whose columns are zero
// on every held-out feature (an effect on one feature only, which then cannot be held out: e.g.
// servo reversal on the turning piece's groove) cannot be tested by feature, nor can one that
// makes a feature unholdable that the base model holds out (its columns there are fixed by that
// feature's points alone, e.g. a straightness polynomial by the features at the ends of its axis
// range: its feature-CV would leave out exactly the features where it extrapolates worst, over a
// smaller set than the others'): their cv_* are the PRESS figures and cv_method says so
// (cv_method_reason why). Ranking of the significant candidates is pairwise,
// because candidates hold out different features: A beats B when its held-out squared residuals
// on the features both hold out are smaller by more than 2 standard errors (paired over those
// features, which are then the base's; PRESS over all points when either is PRESS-tested); undecided pairs go to the smaller
// delta BIC. The verdict is the significant candidate with the most pairwise wins (then the
// smaller cv_rms_after / cv_rms_before); `none` if there is none. Another family is indistinguishable from the verdict
// when the verdict's columns add nothing significant (same alpha) to a fit that already holds
// that family's best candidate (the data cannot tell them apart), or when one of its candidates
// reproduces >= alias_capture of the verdict's fitted signature (the piece cannot).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/outlier_screen.h"
#include "pipeline/diagnosis/reference_agreement.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::kinematics {
struct SlotDesign;  // kinematics/slot_linearisation.h
}  // namespace tpcal::kinematics

namespace tpcal::pipeline {

// The reference's own uncertainty (DiagnosisOptions::reference_uncertainty): the covariance of
// some of its coefficients, display units (um, urad; k = 1), and the piece's noise it is weighed
// against.
struct ReferenceUncertainty {
  std::vector<std::string> names;  // coefficients of DiagnosisOptions::reference
  Eigen::MatrixXd covariance;      // names.size() square
  double noise_um = 0.0;           // the piece's CMM noise sigma (um), > 0
};

struct DiagnosisOptions {
  std::vector<std::string> base_parameters;     // empty: testpieces::DefaultParameterSet(piece, machine)
  // Reference mode: the "sim" is these machine errors (e.g. from a probing test); the base
  // parameters are not refitted (only the alignment), and a `location_errors` candidate (the
  // base set refitted) joins the catalogue.
  std::optional<kinematics::ErrorState> reference;
  // With `reference`: these parameters are refitted on top of it, the rest held (those a piece
  // and an instrument disagree on, reference_agreement.h); the gap with all held is kept too.
  std::vector<std::string> reference_free;
  // With `reference`: what it does not know. Every direction of the piece's deviations along
  // which its covariance moves them with a variance above reference_nuisance_ratio * noise_um^2
  // is fitted in the base model (a nuisance column, not reported); the variance it adds along the
  // others is weighed beside the noise's, mean and spread, in the excess, group, harmonic and
  // candidate tests, the outlier screen and the drift's u. So no candidate, group,
  // harmonic or patch is credited with the reference's own error. 1: measured on 120 effect-free turning pieces
  // against 1 um probing tests (README, tests corrected by the mean alone then): 0.25 raised 15 %
  // false alarms (so many columns bias the neighbour sigma low), 1 raised 5.8 %, 4 raised 25 %.
  std::optional<ReferenceUncertainty> reference_uncertainty;
  double reference_nuisance_ratio = 1.0;
  std::string reference_name = "reference";     // for base_model in the report
  std::string reference_path;                   // the file of `reference`: errors it causes are located there
  double alpha = 0.01;                // family-wise false-alarm probability of the verdict
  // Another family is also named indistinguishable from the verdict when one of its candidates
  // reproduces at least this share of the energy of the verdict's fitted signature (on this piece
  // and plan the two differ only by the shapes their candidates assume). 0.9: the rest is below
  // a third of the signature's RMS.
  double alias_capture = 0.9;
  double absorbed_tolerance = 1e-3;   // sine of the principal angle to the base design below which a direction is absorbed
  // A family whose candidates keep less than this share of a typical signature outside the base
  // (RMS sine of the principal angles) is reported weakly observable: at 0.1 an effect must be
  // about 10x the noise before 1x of it shows.
  double weak_visibility = 0.10;
  double noise_um = 0.0;              // known CMM noise sigma (um); 0 = estimated from the residual
  int max_harmonic = 8;               // C harmonics reported per circular profile
  double stand_out_z = 4.0;           // z-score above which a group stands out beyond noise
  // Feature-CV: a feature is not held out when the other features carry less than this share of
  // the design's information on some direction (smallest eigenvalue of I - Q_G^T Q_G, Q
  // orthonormal; 0 = exactly rank-deficient). 0.05: the held-out residual's noise variance along
  // that direction is amplified by at most 1 / 0.05 = 20x. Measured on the turning piece (paper
  // plan, base model): every feature has >= 0.157 except S5 with 0.0039, whose held-out residual
  // (21.8 um RMS on 0.6 um in-sample with a drift) would otherwise dominate the CV sums.
  double holdout_tolerance = 0.05;
  // DiagnoseAgainstPoints: largest distance (mm, part frame) between the nominal positions of a
  // measured point and its reference point. 1 mm: far above the errors' shift of one probing
  // target between two files (tens of um), far below the plan's point spacing (> 5 mm).
  double reference_match_mm = 1.0;
  // The slot linearisation of the same observations at the nominal machine (zero errors) when the
  // caller already made it (tpcal run shares it with the identification; NominalDiagnosisSlots
  // says which slots it needs). Used for the first linearisation when it holds every slot needed
  // and the base is not a reference; otherwise the diagnosis makes its own.
  std::shared_ptr<const kinematics::SlotDesign> nominal_slot_design;
  // The outlier screen's neighbour graph of the same observations when the caller made it (the
  // identification's screen); else the diagnosis makes it once for all its screens.
  std::shared_ptr<const FeatureNeighbourGraph> neighbour_graph;
  // Outliers and local defects (outlier_screen.h) are left out before the base fit and listed,
  // unless an effect of the catalogue whose model leaves them nothing to flag explains them (the
  // diagnosis of every point, diagnosis.cc); false keeps every point (they are still found and
  // listed, marked kept).
  bool screen_outliers = true;
  OutlierScreenOptions screen;
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
  double z = 0.0;            // sqrt(energy_um2) / sigma: amplitude / sigma sqrt(2 / n) on n equally spaced points
  bool stands_out = false;   // z beyond the Bonferroni 1 % Rayleigh bound over every profile's orders
  // The gap's sum of squares along this order given the others (n A^2 / 2 equally spaced); of the
  // gap over the noise scales for pooled scan cells (Observation::noise_scale), as z is.
  double energy_um2 = 0.0;
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
  // Standard uncertainties (k = 1, the joint fit's residual sigma): of the base fit alone and of
  // the joint fit of base and effect (larger: the effect takes some of the data's information).
  double u_without = 0.0, u_with = 0.0;
};

struct CandidateResult {
  std::string family;  // vocabulary of docs/formats/diagnosis_json.md
  std::string name;
  int n_columns = 0;   // parameters of the model
  int rank = 0;        // directions left after projecting out the base (0 = unobservable)
  bool observable = false;
  // Largest sine of the principal angles between the candidate's columns and the base design: the
  // share (in norm) of its most visible signature that the base model cannot absorb.
  double visible_share = 0.0;
  // RMS of those sines over its directions: the share of a typical signature of the candidate.
  double typical_visible_share = 0.0;
  double rms_after_um = 0.0, max_abs_after_um = 0.0, shrink_pct = 0.0;
  // Leave-one-feature-out (see the top of this file), over the same held-out features before and after.
  double cv_rms_before_um = 0.0, cv_rms_after_um = 0.0, cv_shrink_pct = 0.0;
  int cv_features = 0;                       // features held out (predicted) for this candidate
  // "leave-one-feature-out", or "leave-one-point-out" when no held-out feature carries the effect
  // or the candidate makes a feature unholdable that the base holds out (cv_* are then the PRESS
  // figures: the feature-CV cannot test it on the base's features).
  std::string cv_method = "leave-one-feature-out";
  std::string cv_method_reason;              // why leave-one-point-out (empty otherwise)
  std::vector<std::string> cv_not_held_out;  // features that could not be held out (base's included)
  double press_rms_before_um = 0.0, press_rms_after_um = 0.0;  // leave-one-point-out (PRESS)
  double f_stat = 0.0, p_value = 1.0, delta_bic = 0.0;
  bool significant = false;
  std::vector<EffectParameter> parameters;
  std::vector<BaseShift> base_shift;
};

struct UnobservableFamily {
  std::string family;
  std::string reason;
};

// A family observable only in a small share of its typical signature (DiagnosisOptions::weak_visibility).
struct WeaklyObservableFamily {
  std::string family;
  double visible_share = 0.0;  // typical share, largest over its candidates, 0..1 (norm ratio)
};

// A family of the effect catalogue (its candidate's parameters describe the verdict): not none,
// local_defect or unexplained.
bool IsCatalogueFamily(const std::string& family);

struct Verdict {
  std::string family = "none";
  std::string name = "nothing beyond measurement noise";
  double shrink_pct = 0.0, cv_shrink_pct = 0.0;
  std::vector<std::string> indistinguishable_from;
  // The candidates (by name, ranking order) that explain the gap about as well as the verdict's
  // by the same two tests, one by one rather than by family: another axis's candidate of the
  // verdict's own family (A's angular positioning beside C's) is listed here, which
  // indistinguishable_from, keyed by family, cannot say. Every candidate passing a test is listed
  // (of a family in indistinguishable_from, at least the one that put it there, but local_defect,
  // which has no candidate; others too);
  // `also`'s family and larger forms of the verdict's own candidate (which hold it) are left out.
  std::vector<std::string> indistinguishable_candidates;
  std::optional<std::string> also;  // a second family that adds significantly beyond the verdict
  // With `also`: the other families one of whose candidates reproduces >= alias_capture of what
  // `also`'s candidate adds beyond the verdict's (its fitted signature off the verdict's
  // directions): the data cannot tell them from `also` (sorted; not the verdict's family).
  std::vector<std::string> also_indistinguishable_from;
  // Every family the verdict names, leading first: the verdict's, `also`, and local_defect when
  // the screen found a patch beside a catalogue effect. Empty for none.
  std::vector<std::string> families;
  // unexplained: the candidates that explain most of the gap without being significant (best first).
  std::vector<std::string> partial;
};

// The verdict and the runner-up (the candidate of another family that adds most beyond it) fitted
// together, when the top two are close: the pairwise ranking does not separate them by
// prediction, or the runner-up still adds significantly beyond the verdict; or the pair a joint
// search over two-family pairs found instead (diagnosis_pair_fit.h, BetterJointPair: then the
// verdict is its lead). The verdict itself stays one family (docs/formats/diagnosis_json.md);
// this says how much more the pair explains.
struct PairFit {
  std::vector<std::string> families;  // verdict's, runner-up's (or the searched pair's other)
  std::vector<std::string> names;
  std::string why;                    // which closeness test selected the pair
  int rank = 0;                       // joint directions left after projecting out the base
  double rms_after_um = 0.0, shrink_pct = 0.0;
  // Cross-validated as the two candidates were: leave-one-feature-out over the features the
  // joint design can hold out when both were judged that way, else leave-one-point-out (PRESS).
  double cv_rms_before_um = 0.0, cv_rms_after_um = 0.0, cv_shrink_pct = 0.0;
  std::string cv_method = "leave-one-feature-out";
  double p_value_beyond_verdict = 1.0;  // F-test: the second added to base + verdict
  std::vector<EffectParameter> parameters;  // both effects' parameters from the joint fit
};

struct DiagnosisResult {
  std::string base_model;
  int n_points = 0;
  int base_columns = 0;        // identifiable base directions + alignment (+ the reference's nuisance directions)
  double rms_um = 0.0, max_abs_um = 0.0;   // the gap
  // With DiagnosisOptions::reference_free: RMS of the gap with the reference held entirely (only
  // the re-alignment fitted), before the parameters it disagrees on are refitted (um).
  std::optional<double> reference_held_rms_um;
  // sigma used for "beyond noise" (given or estimated), one probe hit's: a pooled scan cell's
  // noise is this times its Observation::noise_scale, which every noise test weighs.
  double noise_sigma_um = 0.0;
  // Leave-one-feature-out of the base fit: RMS over the features that can be held out, and those
  // that cannot (their points alone determine a direction of the base model and re-alignment).
  double cv_rms_um = 0.0, press_rms_um = 0.0;
  int n_features = 0, cv_features = 0;
  std::vector<std::string> cv_not_held_out;
  // Point reference (DiagnoseAgainstPoints): how the measured points were matched.
  struct ReferenceMatch {
    int matched_by_order = 0, matched_by_nearest = 0;  // points
    double max_offset_mm = 0.0;     // largest nominal-position distance of a matched pair
    int unmatched = 0;              // measured points without a reference point (skipped)
  };
  std::optional<ReferenceMatch> reference_match;
  std::vector<GroupGap> by_feature, by_operation, by_a_index;
  double drift_um_per_h = 0.0, drift_u_um_per_h = 0.0;  // linear trend of the gap with t_s
  std::vector<HarmonicGap> harmonics;      // every circular profile, orders 1..min(max_harmonic, distinct azimuths / 2 - 1)
  std::vector<std::string> standing_out;   // names of the groups that stand out
  std::vector<EffectParameter> base_parameters;  // identified base coefficients (without effect)
  std::vector<CandidateResult> candidates;       // best first (significant, then by cv_rms_after / cv_rms_before; unobservable last)
  std::vector<UnobservableFamily> unobservable;  // families with no observable candidate
  std::vector<WeaklyObservableFamily> weakly_observable;  // observable, but mostly absorbed by the base
  Verdict verdict;
  std::optional<PairFit> pair;                   // verdict + second jointly, when they are close
  std::vector<std::string> skipped_points;       // points no cut reaches (Diagnose), "file:line: why"
  // The outlier screen: flagged points (left out unless screen_outliers is off), the patches, and
  // the noise sigma from neighbour differences on the same feature with the test of the gap
  // against it (p-value of "the base gap is noise of that sigma"; 1 when not screened).
  std::vector<ScreenedPoint> outliers;
  std::vector<LocalDefect> local_defects;
  // Patches the screen flagged that the verdict's effect explains (its model leaves none to flag):
  // their points are kept in the fit; listed so the lab can look there (local_defect is then in
  // verdict.indistinguishable_from). Empty otherwise.
  std::vector<LocalDefect> explained_patches;
  double neighbour_sigma_um = 0.0;
  double excess_p_value = 1.0;
  std::vector<double> gap_um;                    // per observation
  std::vector<std::string> point_feature;        // per observation
  // Against an instrument (pipeline/instrument_reference.h): where the two agree, parameter by parameter.
  std::optional<ReferenceAgreement> reference_agreement;
};

// The verdict's indistinguishable_candidates of the verdict's own family (another axis, another
// shape of the same effect), by name: what indistinguishable_from, keyed by family, cannot name.
std::vector<std::string> SameFamilyAlternatives(const DiagnosisResult& result);

// The error slots the diagnosis linearises at the nominal machine for `observations`' piece: those
// of its base set (options.base_parameters, or the piece's default) and of every machine-error
// candidate (a caller sharing one linearisation passes it as options.nominal_slot_design).
// Errors: unknown base parameters.
Result<std::vector<kinematics::ErrorSlot>> NominalDiagnosisSlots(const testpieces::TestPiece& piece,
                                                                 const kinematics::MachineModel& machine,
                                                                 const DiagnosisOptions& options);

// Fills the source lines (from the point file the observations came from) of the result's
// outliers, local defects and explained patches.
void AttachSourceLines(const PointSet& measured, DiagnosisResult* result);

// Diagnosis of observations already in the nominal part frame (identify_stage.h).
Result<DiagnosisResult> DiagnoseObservations(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine,
                                             const testpieces::MeasuredObservations& observations,
                                             const DiagnosisOptions& options = {});

// Measured CMM points (any placement): datum frame from the piece's inspection plan, then
// DiagnoseObservations. Points that no cut of their feature reaches (testpieces::AssociatePoints'
// association failures, e.g. at a face edge) are skipped and listed in skipped_points.
// Errors: those of gdt::EvaluatePlan, unlabelled points or unknown features (file and line),
// kTooFewPoints when the base design has no residual degrees of freedom.
Result<DiagnosisResult> Diagnose(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                 const PointSet& measured, const DiagnosisOptions& options = {});

// The "sim" is the point set `reference` (any placement, labelled by feature, the same piece):
// the gap is measured minus reference point by point, associated as described at the top of
// this file, with the re-alignment fitted; the base set joins the catalogue as the
// `location_errors` candidate. options.reference must be empty. Measured points without a
// reference point within options.reference_match_mm, and points of either file no cut
// reaches, are skipped and listed in skipped_points (reference ones prefixed "reference: ").
// Errors: those of Diagnose for either file; kInvalidArgument with options.reference set.
Result<DiagnosisResult> DiagnoseAgainstPoints(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                              const PointSet& measured, const PointSet& reference,
                                              const DiagnosisOptions& options = {});

}  // namespace tpcal::pipeline
