// Validation of the diagnosis on data whose effect is withheld (issue 6): test pieces simulated
// with one unmodelled effect switched on that the diagnosis is not told about, produced by the
// simulator's physics, not by the candidate formulas of diagnosis_candidates.h:
//   thermal_drift        exponential (random tau, 0.15 to 1.5 x the program duration) or linear
//                        drift of one workpiece-branch translation (E_X0A ... E_Z0C), tilt of the
//                        C line (E_A0C, E_B0C) or Z squareness (E_B(0X)Z), ErrorState term
//                        (3-axis machines: one of the three squareness errors);
//   linear_straightness  a 5-node cubic (Catmull-Rom) table over the axis range used by the piece,
//                        random values with the linear trend removed, on one of E_YX ... E_YZ;
//   linear_positioning   scale (+ quadratic, half the trials) of one of E_XX, E_YY, E_ZZ;
//   rotary_error_motion  one or two random harmonics (orders 2 to 5) of one of E_XC, E_YC, E_ZC,
//                        E_AC, E_BC;
//   rotary_positioning   random harmonics 1 to 3 of E_CC;
//   tool_deflection      testpieces/process_effects.h cutting-force model, random compliances
//                        and force ratios;
//   servo_reversal       process_effects.h quadrant glitches (random heights, decay 2 to 8 deg),
//                        lost motion in half the trials;
//   probe_radius         the virtual CMM's probe-radius error (random sign);
//   outliers, local_defect, fixture_bend, spindle_growth: point offsets (validation_injections.h);
//   lobes7               a 7-lobe radial error motion of C (the catalogue has orders 2 to 5);
//   pairs                two different catalogue families at once, each scaled to the magnitude;
//   none                 no effect.
// A verdict is right (top-1) when it is the withheld family; for outliers when it is none (the
// screen leaves them out); for pairs when verdict.families holds both; for fixture_bend,
// spindle_growth and lobes7, which no candidate models, when it is unexplained or a catalogue
// family (not none, not local_defect).
// Every trial draws random base errors (the machine's ISO 230-1 location and squareness errors,
// kinematics::IsoLocationSet, +-20 um / urad, whatever parameters the diagnosis's base model
// uses; M2 also its straightness base terms), a random placement of the part on the CMM and Gaussian CMM noise. The effect is scaled so that its
// signature left after the base model and the re-alignment absorb what they can (the part of the
// gap the diagnosis can see) peaks at `magnitude` x the noise sigma (or its raw signature, with
// scale_raw_peak); an effect the base absorbs (almost) entirely (|visible| < min_visible_fraction
// |signature|, default 2 %) is run at that peak of its raw signature and counted as unobservable:
// scaling a 99.9 %-absorbed effect up until its remainder shows would make the remainder a
// second-order (nonlinear) artefact of a huge error, not the effect's own signature. A trial is
// also unobservable when the scaled effect alone, noise-free, keeps less than half its intended
// peak after the diagnosis's own (nonlinear) base fit: on the single cone the drifts are 2-3 %
// visible by the linear projection at the nominal state, and scaled 30-50x the base fit absorbs
// the rest (noise-free, an E_Y0C drift leaves 2.3 % of its RMS at 1 um but 0.13 % at 100 um).
// With ValidationOptions::diagnose each trial's piece is diagnosed by that function instead (the
// pipeline layer's diagnosis against an instrument test of the trial's cold machine,
// pipeline/instrument_validation.h); the effects, their scaling and the table are the same.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "pipeline/diagnosis/diagnosis.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct ValidationOptions {
  std::vector<std::string> families;             // empty: every family above and "none"
  std::vector<double> magnitudes = {1, 2, 5, 10, 20};  // peak visible signature / noise sigma
  std::vector<double> noise_um = {0.5, 1.0, 2.0};
  int trials = 2;                                // per family, magnitude and noise level
  std::uint64_t seed = 1;
  double base_error = 20.0;                      // um / urad, uniform +- of each base parameter
  bool random_placement = true;
  // false (default): scale so the VISIBLE signature (after the base absorbs what it can) peaks at
  // magnitude x sigma; true: scale the RAW signature's peak instead (the visible part is then
  // smaller, often much smaller for effects the location errors nearly mimic).
  bool scale_raw_peak = false;
  double min_visible_fraction = 0.02;  // below: the trial is counted unobservable
  // Empty: each piece is diagnosed against the fitted base model (Diagnose). Otherwise it is
  // diagnosed by this function, given the trial's cold machine (its random base errors, without
  // the withheld effect), the measured points and a seed drawn for the trial (for the
  // reference's own noise). Its errors are counted as the verdict "error".
  std::function<Result<DiagnosisResult>(const kinematics::ErrorState& cold, const PointSet& measured,
                                        std::uint64_t seed)>
      diagnose;
  std::string reference_name;  // what `diagnose` compares with, for the table's text ("" = none)
  Status Validate() const;
};

struct ValidationTrial {
  std::string true_family;
  std::string true_detail;     // what was switched on
  double magnitude = 0.0, noise_um = 0.0;
  bool observable = true;      // false: the base model absorbs the effect (visible_fraction < min)
  double visible_fraction = 0.0;  // |signature left after the base| / |signature|
  std::string verdict;
  std::string verdict_name;    // the verdict candidate's name (which axis a rotary family's is)
  std::vector<std::string> indistinguishable_from;
  std::vector<std::string> also_indistinguishable_from;  // Verdict::also_indistinguishable_from
  // Every candidate named, by name (which axis): the verdict's, the pair's, the indistinguishable ones.
  std::vector<std::string> candidates_named;
  double effect_rms_um = 0.0;     // RMS of the visible signature
  // Of the verdict (0 for none): (cv_before^2 - cv_after^2) / cv_effect^2, cv_effect = the same CV
  // figure (cv_method, held-out features) of the noise-free visible signature (diagnosis_validate.cc).
  double cv_explained = 0.0;
  double press_explained = 0.0;   // the same with the leave-one-point-out figures, for every verdict
  std::string cv_method;          // the verdict's (empty for none)
  std::vector<std::string> verdict_families;  // verdict.families
  std::vector<std::string> pair_families;     // pairs: the two withheld families
  // The outlier screen against the injected points (outliers, local_defect; 0 otherwise).
  int injected_points = 0, found_points = 0, false_flags = 0, clean_points = 0;
  double seconds = 0.0;           // diagnosis time
  double shrink_pct = 0.0, cv_shrink_pct = 0.0;  // the verdict's (0 for none)
  // In-sample shrink of the gap against the reference held entirely (reference_held_rms_um; the
  // plain gap when nothing was refitted) by the refitted parameters and the verdict together.
  double held_shrink_pct = 0.0;
  // Against a reference (DiagnosisResult::reference_agreement): parameters compared and disagreeing.
  int reference_compared = 0, reference_disagreeing = 0;
};

struct ValidationSummary {
  std::vector<ValidationTrial> trials;
  std::vector<std::string> families;                              // rows
  std::map<std::string, std::map<std::string, int>> confusion;    // true family -> verdict -> count (magnitude >= 5, observable)
  std::map<std::string, double> top1_rate;             // magnitude >= 5 and observable
  std::map<std::string, double> top1_or_alias_rate;    // true family is the verdict or indistinguishable from it
  std::map<std::string, int> unobservable_trials;
  std::map<std::string, std::map<double, double>> top1_by_magnitude;  // family -> magnitude -> rate (observable)
  // Verdict != none on effect-free pieces; against a reference also a disagreeing parameter.
  double false_alarm_rate = 0.0;
  int none_trials = 0, none_alarms = 0, none_disagreeing = 0;  // effect-free pieces: trials, alarms, disagreements
  double median_cv_shrink_pct = 0.0;  // the verdict's cross-validated shrink, right verdicts (>= 5x, observable)
  double median_held_shrink_pct = 0.0;  // the same verdicts' held_shrink_pct
  bool against_reference = false;     // the trials were diagnosed against a reference
  double median_cv_explained = 0.0;                    // magnitude >= 5, observable, effect present
  double median_press_explained = 0.0;                 // the same, leave-one-point-out figures
  std::map<std::string, int> verdict_cv_method;        // correct verdicts (>= 5x, observable) per cv_method
  double median_diagnosis_s = 0.0;
  int simulation_failures = 0;                         // trials the simulator could not produce (not scored)
  long outliers_injected = 0;      // outlier trials at magnitude >= 10
  double outliers_found_rate = 0.0;  // of those, flagged by the screen
  double false_flag_rate = 0.0;      // flagged clean points / clean points, outlier and effect-free trials
};

Result<ValidationSummary> RunValidation(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                        const ValidationOptions& options);

// The confusion matrix and rates as a Markdown table (for the README).
std::string ValidationMarkdown(const ValidationSummary& summary);

}  // namespace tpcal::pipeline
