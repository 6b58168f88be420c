// Solver (a) of the inversion: the seed 002 Table 2 machine errors from the GD&T values of the
// finished turning test piece (its Table 1), by the closed-form first-order relations.
//
// Two equation sets:
//  - kKinematics: the relations derived from tpcal's kinematics (kinematics/SEED002_SIGNS.md),
//    proven by virtually machining the piece (seed002_closed_form_test.cc compares every
//    coefficient with finite differences through the simulator and the GD&T evaluation);
//  - kPrinted: eqs. 10-21 exactly as printed in seed 002 (gamma_YX taken as zero,
//    alpha_CY(-90) read as alpha_CR(-90)), kept to document what the paper's own equations give.
// The items are solved by least squares (SVD, minimum norm); coefficients the items cannot
// separate are reported as not identifiable, with the combinations they do determine.
//
// Units: items in um (translations) and urad (angles); heights in mm; results in um / urad.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/identification.h"

namespace tpcal::kinematics {

enum class Seed002Equations { kKinematics, kPrinted };
const char* Seed002EquationsName(Seed002Equations e);  // "kinematics", "printed"

// Heights from the A axis and probing radii (mm), seed 002 section 3.2 / 4.1 notation.
struct Seed002Geometry {
  double z_R = 405.702;  // B_R (and the Z of the S_R milling pass)
  double z_h = 405.702;  // probing height of the holes (the paper leaves it open)
  double z1 = 400.702, z2 = 390.702, z3 = 380.702, z4 = 160.702, z5 = 150.702, z6 = 140.702;
  double rho_B3 = 0.0;   // probing radius on B3 (kinematics set: B3 is a cone when alpha != 0)
};

// GD&T items (seed 002 Table 1 names; optional ones may be missing). Keys:
//   "dx_Ch_SR_um", "dy_Ch_SR_um"   #1 concentricity of the hole pitch circle to S_R
//   "da_B1_BR_urad", "db_B1_BR_urad" #2 parallelism of B1 to B_R
//   "dd_B3_BR_um"                  #3 error in distance between B3 and B_R
//   "dr_S3_um"                     #4 error in radius of S3
//   "dx_S4_SR_um", "dy_S4_SR_um"   #5 concentricity of S4 to S_R
//   "dx_S4_S1_um", "dy_S4_S1_um"   #6 concentricity of S4 to S1
//   "dx_S6_S3_um", "dy_S6_S3_um"   #7 concentricity of S6 to S3
// Items beyond Table 1 that the same CMM data give (kinematics set only):
//   "dx_S3_SR_um", "dy_S3_SR_um"   concentricity of S3 to S_R
//   "dr_S1_S4_um"                  radius of S1 minus radius of S4 (errors vs nominal)
//   "dr_S2_S5_um"                  radius of S2 minus radius of S5
using Seed002Items = std::map<std::string, double>;

// The Table 2 names, in the order of the results.
const std::vector<std::string>& Seed002ParameterNames();

struct ClosedFormParameter {
  std::string name;
  std::string unit;  // "um" or "urad"
  bool identifiable = false;
  double value = 0.0;
  double u = 0.0;    // propagated from the item uncertainties (if given), k = 1
};

struct ClosedFormResult {
  Seed002Equations equations = Seed002Equations::kKinematics;
  std::vector<ClosedFormParameter> parameters;  // Seed002ParameterNames() order
  int rank = 0;
  std::vector<std::string> items_used;
  std::vector<double> item_residuals;  // item minus its prediction, same order
  std::vector<std::string> estimable;  // combinations of non-identifiable parameters, with values
  std::vector<Combination> combinations;  // the same, structured (u propagated when item_u is given)
  // The sensitivity matrix: row per item used, column per parameter (um or urad per um or urad).
  std::vector<std::vector<double>> matrix;
};

// Prediction of every item the equation set knows, for parameter values in um / urad.
Seed002Items PredictSeed002Items(const std::map<std::string, double>& parameters, const Seed002Geometry& g,
                                 Seed002Equations equations);

// Solves for the parameters from the items present. `item_u` (same keys) gives standard
// uncertainties used to weight and propagate (default 1, no propagated u). Errors:
// kInvalidArgument for an unknown item key; kTooFewPoints if no known item is present.
Result<ClosedFormResult> SolveSeed002(const Seed002Items& items, const Seed002Geometry& g,
                                      Seed002Equations equations, const Seed002Items& item_u = {});

// C-axis error motion profiles from circularity profiles (seed 002 eqs. 22-27, kinematics
// signs: Delta r(theta) = -E_radial(C) - E_tilt(C) z, the table's actual-minus-nominal motion).
// Inputs: the radial deviations (um) of two faces turned at the same A, sampled at the same C
// angles (deg), at heights z_upper > z_lower (mm). Outputs per C: radial (um) and tilt (urad).
struct ErrorMotionProfile {
  std::vector<double> c_deg;
  std::vector<double> radial_um;
  std::vector<double> tilt_urad;
  double radial_pv_um = 0.0;
  double tilt_pv_urad = 0.0;
};
Result<ErrorMotionProfile> SeparateErrorMotion(const std::vector<double>& c_deg, const std::vector<double>& dr_upper_um,
                                               const std::vector<double>& dr_lower_um, double z_upper_mm,
                                               double z_lower_mm);

}  // namespace tpcal::kinematics
