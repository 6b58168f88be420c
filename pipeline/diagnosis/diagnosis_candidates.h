// The catalogue of candidate effects of the diagnosis (diagnosis.h): each a small linear model
// whose columns are the predicted normal deviation (um) per unit of each of its parameters.
//
// Machine-error families are ErrorState terms (kinematics/errors_yaml.md effect items, added at
// zero to the base errors) whose columns come from kinematics::LineariseObservations through the
// full chain:
//   thermal_drift        linear drift (um/h) of the workpiece-branch translations (E_X0A, E_Y0A,
//                        E_Z0A and the C translations E_Y0C, E_Z0C on an A/C table), and the
//                        exponential form K (1 - exp(-t / tau)), tau = one third of the program;
//   linear_straightness  quadratic, quadratic to quartic and to sextic straightness error motions
//                        E_YX, E_ZX, E_XY, E_ZY, E_XZ, E_YZ together (polynomials in the axis
//                        position, mm), and quadratic to quartic of each of them alone;
//   linear_positioning   scale E_XX.c1, E_YY.c1, E_ZZ.c1, and scale + quadratic;
//   rotary_error_motion  Fourier orders 2..5 of the last rotary axis (C): radial E_XC, E_YC;
//                        axial E_ZC; tilt E_AC, E_BC;
//   rotary_positioning   Fourier orders 1..4 of the angular positioning of each rotary axis: E_CC,
//                        then E_AA (A/C table) or E_BB (B/C). The other axis's error motions are
//                        not candidates: at the few angles a piece uses they act as offsets per
//                        angle, which the location errors also hold.
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
#include <memory>
#include <utility>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/jacobians.h"
#include "kinematics/machine_model.h"
#include "kinematics/slot_linearisation.h"
#include "testpieces/point_association.h"
#include "testpieces/test_piece.h"

namespace tpcal::pipeline {

// A candidate's design columns: n x p, um per unit of each parameter. The machine-error
// candidates share one matrix of every candidate coefficient (linearised once; nested candidates
// such as quadratic / quartic / sextic straightness would otherwise copy the same columns, 2 GB at
// 2e6 points): `shared_columns` of *shared, J_dev_effect empty. The process candidates own theirs.
struct CandidateColumns {
  std::string family;
  std::string name;
  Eigen::MatrixXd J_dev_effect;          // n x p (empty when shared)
  std::vector<std::string> parameter_names;
  std::vector<std::string> units;
  std::shared_ptr<const Eigen::MatrixXd> shared;
  std::vector<Eigen::Index> shared_columns;

  Eigen::Index cols() const {
    return shared ? static_cast<Eigen::Index>(shared_columns.size()) : J_dev_effect.cols();
  }
  // Column j (n entries).
  Eigen::Map<const Eigen::VectorXd> col(Eigen::Index j) const {
    const Eigen::MatrixXd& m = shared ? *shared : J_dev_effect;
    const Eigen::Index k = shared ? shared_columns[static_cast<std::size_t>(j)] : j;
    return {m.col(k).data(), m.rows()};
  }
};

struct CandidateCatalogue {
  std::vector<CandidateColumns> candidates;
  // Families of the contract vocabulary that this machine / piece gives no candidate for, with why.
  std::vector<std::pair<std::string, std::string>> not_applicable;
};

// The slots the machine-error candidates of BuildCandidates write (for one kinematics::LineariseSlots
// shared with the base model). Errors: those of BuildCandidates' parameter selection.
Result<std::vector<kinematics::ErrorSlot>> CandidateSlots(const testpieces::TestPiece& piece,
                                                          const kinematics::MachineModel& machine,
                                                          const kinematics::ErrorState& errors,
                                                          const std::vector<std::string>& base_names,
                                                          bool reference_mode);

// Builds every candidate's columns at the linearisation point `errors` (the fitted base or the
// reference). `base_names` are the base parameter names (for the reference-mode candidate).
// `design`: a slot design at `errors` holding CandidateSlots (no second linearisation); null:
// linearised here.
Result<CandidateCatalogue> BuildCandidates(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                           const kinematics::ErrorState& errors,
                                           const testpieces::MeasuredObservations& observations,
                                           const std::vector<std::string>& base_names, bool reference_mode,
                                           const kinematics::SlotDesign* design = nullptr);

}  // namespace tpcal::pipeline
