// The parameter equivalent of an A/C table's error maps (a probing test of artifacts, seed 000):
// the constant errors (ISO 230-1 location errors, seed 002's parameters, ...) whose table poses
// best match the maps' at the maps' grid positions, so that a map instrument can be compared
// with a test piece parameter by parameter (issue 22).
//
// Method. At every grid position (A node x C node of the maps' 2-D C tables) whose entries the
// instrument determined, the table's pose error of the maps (AbsoluteTablePoseError, um and urad)
// is matched by least squares to that of the parameters plus a constant pose (the maps are
// relative to a reference pose, so a constant pose is a nuisance: a parameter that only moves
// the table as a whole is not determined). Linear to first order; columns scaled to unit norm,
// rank by SVD (singular values below 1e-9 of the largest dropped); a parameter outside the
// determined subspace (one that moves no table pose, e.g. the squareness of the linear axes, or
// one the poses only fix in combination) gets no number. Covariance propagated from the map
// entries' (full, or their u alone): exact for the linear step.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

struct MapEquivalentInput {
  // Of the maps' coefficients, display units (um, urad), k = 1. Either the full covariance
  // (num_coefficients square), or the standard uncertainties alone (num_coefficients; their
  // correlations then ignored), or neither (u unknown: every u is 0).
  Eigen::MatrixXd covariance;
  std::vector<double> u;
  // Per coefficient: determined by the instrument (empty = all). A grid position is used only
  // when every table entry that moves its pose is determined (other terms, e.g. constant errors
  // identified with the maps, are taken as given).
  std::vector<bool> determined;
};

struct MapEquivalent {
  std::vector<ParameterEstimate> parameters;  // in the order asked; value and u in display units
  bool u_known = false;
  int positions = 0;                         // grid positions used
  double residual_rms_um = 0.0;              // of the poses' translations the parameters leave
  double residual_rms_urad = 0.0;            // of their rotations
};

// Errors: kInvalidArgument (a machine other than an A/C table, maps without a 2-D C table over
// A, a covariance / u / determined of the wrong size, an unknown parameter name), kTooFewPoints
// (no grid position with every entry determined).
Result<MapEquivalent> ParameterEquivalentOfMaps(const MachineModel& model, const ErrorState& maps,
                                                const std::vector<std::string>& names,
                                                const MapEquivalentInput& input);

}  // namespace tpcal::kinematics
