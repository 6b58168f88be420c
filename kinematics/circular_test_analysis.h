// Analysis of an ISO 230-4 circular test of two linear axes measured with a double ball bar (a
// `circle` installation, kinematics/ballbar_setup.h): the usual figures, each with its standard
// uncertainty, from the bar-length changes of one or both path directions. docs/circular_test.md
// states the model and the signs in words.
//
// Plane and angle. (e1, e2) are the plane's linear axes (XY: X, Y; YZ: Y, Z; ZX: Z, X); the path
// angle phi runs from +e1 toward +e2 (ballbar_setup.h). ccw: phi increases; cw: phi decreases.
// dl (um) is the bar length minus the nominal length, read as the radial deviation of the path.
//
// Model (least squares over all readings, s = +1 ccw, -1 cw, R the nominal radius in mm):
//   dl = c0 + a cos phi + b sin phi                         set-up: bar length offset, centring
//      + A sin 2 phi + B cos 2 phi                          squareness, scale mismatch
//      + bx N1(phi, s) + by N2(phi, s)                      backlash (reversal) of e1 and e2
//      + M s sin 2 phi                                      servo mismatch (both directions only)
//      + hx P1(phi, s) + hy P2(phi, s)                      reversal spikes of e1 and e2
//   The reversals: e1 at phi_c = 0 and 180 deg, e2 at 90 and 270 deg, each with the outward
//   direction o_c (+e1, -e1, +e2, -e2), so o_c . radial = cos(phi - phi_c); alpha_c = the path
//   angle travelled since reversal c in the direction s, in [0, 360) (a reading exactly at a
//   reversal is just after it; the path is taken as run in from before the first reading, so every
//   reversal has been passed). The lost-motion and glitch model of testpieces/process_effects.h's
//   ServoReversalModel: N_k = cos(phi - phi_c*) / 2, c* the axis's reversal with the least alpha
//   (its axis lags b/2 against its new direction until its next reversal; for ccw N1 = cos phi
//   sgn(sin phi) / 2 away from the reversals, for cw the negative); P_k = sum over the axis's two
//   reversals of exp(-alpha_c / decay) cos(phi - phi_c) (height h outward, `spike_decay_deg`).
// The machine figures follow by closed forms (first order, remainder ~ R S^2 / 8):
//   squareness (urad): XY E_C(0X)Y = -2 A / R, YZ E_A(0Y)Z = -2 A / R, ZX E_B(0X)Z = +2 A / R
//     (kinematics/conventions.h: E_C(0X)Y = +S moves the tool -S y in X, dl = -(S R / 2) sin 2 phi);
//   scale mismatch (um/m) = scale of e1 - scale of e2 = 2 B / R (E_XX = e x gives dl = e R cos^2 phi);
//   servo mismatch (urad): the path-angle lag of e2 behind e1, delta = -2 M / R (a time lag dt of
//     e2 at path speed v gives delta = v dt / R);
//   backlash bx, by (um, + = lost motion: the step after the reversal points outward);
//   reversal spikes hx, hy (um, + = outward peak just after the reversal).
// u (k = 1): sigma from the residuals with dof = rows - unknowns, covariance sigma^2 (A^T A)^-1
// (scaled-column QR with column pivoting; a term whose column adds no rank is not fitted and its
// figure is named not identifiable). The circular deviations and the hysteresis are ISO 230-4's
// range statistics of the data (below); their u is the standard deviation of a residual bootstrap
// (the fitted model plus residuals drawn with replacement, scaled by sqrt(rows / dof); fixed seed).
//
// ISO 230-4 figures from the data: circular deviation G of one direction = max - min of dl minus
// that direction's own least-squares circle (c0 + a cos + b sin fitted to its readings, the
// linearised least-squares circle); combined G: the same over both directions with one common
// circle; circular hysteresis H = the largest |dl_ccw - dl_cw| at the readings' angles (the other
// direction linearly interpolated over the angle, periodic), about the common circle. They include
// the noise of the readings (a bias upward of the noise-free figure, given in the note).
// Not modelled: cyclic error (pitch-periodic scale errors), stick-slip, servo gain per axis.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/ballbar_setup.h"

namespace tpcal::kinematics {

struct CircularReading {
  double angle_deg = 0.0;   // path angle (ballbar_setup.h plane convention)
  double dl_um = 0.0;       // bar length - nominal length
  bool ccw = true;          // path direction (false: cw)
  int line = 0;             // source line (0 unknown), for messages
};

struct CircularFigure {
  std::string name;     // stable key, snake_case, e.g. "circular_deviation", "squareness", "scale_mismatch", "backlash_x"
  std::string symbol;   // ISO 230-1 / 230-4 symbol or "" (e.g. "G", "H", "E_C(0X)Y")
  std::string unit;     // "um", "urad", "um/m"
  bool identifiable = true;  // false: no number (say why in note)
  double value = 0.0, u = 0.0;  // k = 1; u = 0 only when unknown
  std::string note;     // how it was obtained / why not identifiable
  bool setup = false;   // a set-up term (bar length offset, centring), not a machine figure
  double ci95_low = 0.0, ci95_high = 0.0;  // value -+ k95 u (Student t, dof; 0 when u unknown)
};

struct CircularTestOptions {
  // Decay of the reversal-spike template with the path angle travelled after the reversal (deg),
  // > 0; ServoReversalModel's default.
  double spike_decay_deg = 4.0;
  // A spike is fitted only when at least this many readings lie strictly after a reversal of its
  // axis and within 2 decay lengths of it (a reading exactly at the reversal does not count), >= 1.
  int min_spike_readings = 3;
  bool fit_spikes = true;
  // Rank test of the scaled columns (Eigen ColPivHouseholderQR threshold), in (0, 1).
  double rank_tolerance = 1e-9;
  // Residual bootstrap of G and H: draws (0: their u is unknown; else >= 20) and the seed.
  int bootstrap_samples = 200;
  std::uint64_t bootstrap_seed = 2304;
  // kInvalidArgument naming the first bad value.
  Status Validate() const;
};

struct CircularTestResult {
  std::string plane;           // "XY", "YZ", "ZX"
  double radius_mm = 0.0;
  std::vector<CircularFigure> figures;
  int rows = 0, dof = 0;
  bool sigma_known = false;
  double sigma_um = 0.0;       // residual sd of the fitted model
  std::vector<double> residuals_um;  // per reading, input order
  std::vector<std::string> conventions;  // sign conventions stated in words
  int unknowns = 0;            // columns fitted
  int ccw_rows = 0, cw_rows = 0;
  // The figure named `name`, or nullptr.
  const CircularFigure* Find(const std::string& name) const;
};

// Figures, in this order (e1, e2 the plane's axis letters in lower case, "x", "y" for XY):
//   circular_deviation_ccw, circular_deviation_cw, circular_deviation (G, um); circular_hysteresis
//   (H, um); squareness (urad); scale_mismatch (um/m); servo_mismatch (urad); backlash_<e1>,
//   backlash_<e2>, reversal_spike_<e1>, reversal_spike_<e2> (um); set-up: bar_length_offset,
//   centre_offset_<e1>, centre_offset_<e2> (um, the path centre relative to the workpiece ball).
// Not identifiable (no number, the note says why): a direction without readings (its G; the
// combined G, H and the servo mismatch need both directions); a spike with fewer than
// min_spike_readings readings after its reversals or when fit_spikes is false; any term whose
// column the readings do not separate (e.g. a backlash when the readings do not straddle the
// axis's reversal points).
// Errors (kInvalidArgument): bad options, an installation not of kind circle or with a radius
// that is not finite and > 0, a non-finite angle or dl (naming the line when given), readings
// that do not determine the offset, centring, squareness and scale terms (fewer than 5 distinct
// angles modulo 360), fewer readings than unknowns.
Result<CircularTestResult> AnalyseCircularTest(const BallbarInstallation& circle,
                                               const std::vector<CircularReading>& readings,
                                               const CircularTestOptions& options = {});

}  // namespace tpcal::kinematics
