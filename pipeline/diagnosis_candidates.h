// The catalogue of candidate effects of the diagnosis (diagnosis.h): each a small linear model
// whose columns are the predicted normal deviation (um) per unit of each of its parameters.
//
// Machine-error families are ErrorState terms (kinematics/errors_yaml.md effect items, added at
// zero to the base errors) whose columns come from kinematics::LineariseObservations through the
// full chain:
//   thermal_drift        linear drift (um/h) of the workpiece-branch translations (E_X0A, E_Y0A,
//                        E_Z0A and the C translations E_Y0C, E_Z0C on an A/C table), and the
//                        exponential form K (1 - exp(-t / tau)), tau = one third of the program;
//   linear_straightness  quadratic, and quadratic to quartic, straightness error motions E_YX, E_ZX,
//                        E_XY, E_ZY, E_XZ, E_YZ (polynomials in the axis position, mm);
//   linear_positioning   scale E_XX.c1, E_YY.c1, E_ZZ.c1, and scale + quadratic;
//   rotary_error_motion  Fourier orders 2..5 of the last rotary axis (C): radial E_XC, E_YC;
//                        axial E_ZC; tilt E_AC, E_BC;
//   rotary_positioning   Fourier orders 1..4 of its angular positioning E_CC.
// Process families are columns from the cut model of each point's feature (testpieces/cut_model.h):
//   tool_deflection      per cut class (turned side face, turned bottom face, side-milled wall,
//                        end-milled floor): compliance along machine X, Y, Z with a force along
//                        the normal, columns n_mx^2, n_my^2, n_mz^2 (+ n_mx n_my on milled walls);
//   servo_reversal       side-milled circles interpolated in machine X-Y: a triangular glitch
//                        (half-width 12 deg) after each X (Y) reversal in the direction of travel,
//                        outward along that axis, projected on the normal; and with lost motion
//                        (backlash: half-circle steps along X and Y);
//   probe_radius         +b along every measured normal; and with CMM scale (n . p, part frame).
// In reference mode the catalogue adds `location_errors`: the base parameter set itself.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "pipeline/identify_stage.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

struct CandidateColumns {
  std::string family;
  std::string name;
  Eigen::MatrixXd J_dev_effect;          // n x p, um per unit of each parameter
  std::vector<std::string> parameter_names;
  std::vector<std::string> units;
};

struct CandidateCatalogue {
  std::vector<CandidateColumns> candidates;
  // Families of the contract vocabulary that this machine / piece gives no candidate for, with why.
  std::vector<std::pair<std::string, std::string>> not_applicable;
};

// Builds every candidate's columns at the linearisation point `errors` (the fitted base or the
// reference). `base_names` are the base parameter names (for the reference-mode candidate).
Result<CandidateCatalogue> BuildCandidates(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const kinematics::ErrorState& errors,
                                           const MeasuredObservations& observations,
                                           const std::vector<std::string>& base_names, bool reference_mode);

// d deviation / d coefficient (um per display unit) of the coefficients `coefficients` of `errors`
// at the state `errors`, by the chain rule through the error slots they write: one
// kinematics::LineariseObservations over one zero-valued probe term per slot used (a handful of
// slots instead of every coefficient), times each coefficient's gain and basis value at the cut's
// nominal axis state (EvaluateTermBasis, conditions included). Equal to the direct Jacobian at
// zero errors; at non-zero errors the basis is taken at the nominal instead of the solved sweep
// position, a relative change of order (error / tangent speed) (~1e-4 for tens of um).
// Returns the LinearDesign with J_dev_params holding these columns (alignment, measured and
// predicted deviations as LineariseObservations gives them).
Result<kinematics::LinearDesign> LineariseBySlots(const kinematics::MachineModel& machine,
                                                  const kinematics::ErrorState& errors,
                                                  const std::vector<int>& coefficients,
                                                  std::span<const kinematics::Observation> observations);

// Machine-frame outward normal of an observation (nominal kinematics at its cut state).
Eigen::Vector3d MachineNormal(const kinematics::MachineModel& machine, const kinematics::Observation& o);

}  // namespace tpcal::pipeline
