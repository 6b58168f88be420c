// Separation of an A/C table's poses into the position-dependent errors of its two rotary axes
// (seed 000 section 4.2, Table 1, eq. 10-13): the A-axis error motions E_XA .. E_CA as functions
// of A, the C-axis error motions E_XC .. E_CC as functions of A and C, as tpcal tables
// (kinematics/errors_yaml.md: 1-D tables over A, 2-D tables over C with A as second axis, nodes
// at the measured positions, linear).
//
// Method. The table pose is linear in the node values e (first order): pose(p) = G(p) e, G from
// the exact chain (AbsoluteTablePoseError, central differences; the conventions of
// kinematics/conventions.h, not the paper's printed eq. 11, which assumes pivots at the origin).
// The equations: G(p) e = measured pose for every determined pose component, G(ref) e = 0 (the
// reference pose is zero by definition, table_poses.h), and seed 000's eq. 1: at every A the C
// maps sum to zero over the C positions probed there (their constant part belongs to the A maps). With the full grid the
// system is square; it is solved by SVD (scaled columns) and the covariance propagated from the
// poses' (linear, exact). Entries the system leaves undetermined (a position never probed, a pose
// component no touch saw) get no number and are named.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"
#include "kinematics/table_poses.h"

namespace tpcal::kinematics {

struct ErrorMapEntry {
  std::string symbol;       // "E_XA" .. "E_CA", "E_XC" .. "E_CC"
  std::string coefficient;  // its ErrorState coefficient name ("E_XA.n2", "E_XC.n3_1")
  std::string unit;         // "um" or "urad"
  double a_deg = 0.0;
  double c_deg = 0.0;       // C maps only (A maps: 0)
  bool c_map = false;
  bool identifiable = false;
  double value = 0.0, u = 0.0;  // display units, k = 1 (0 when not identifiable)
  double ci95_low = 0.0, ci95_high = 0.0;
};

struct ErrorMaps {
  explicit ErrorMaps(ErrorState base) : maps(std::move(base)) {}
  std::vector<double> a_deg, c_deg;
  ErrorState maps;                     // the 12 tables with the identified node values
  std::vector<ErrorMapEntry> entries;  // in coefficient order of `maps`
  Eigen::MatrixXd covariance;          // of the entries, display units
  std::vector<std::string> not_identifiable;  // entries without a number, by name
  std::vector<std::string> conventions;       // what the maps are relative to, in words
};

// Errors: kInvalidArgument (not an A/C table, fewer than 2 A or 2 C positions, a covariance of
// the wrong size). `dof` sets the 95 % interval (Student t; 0: normal).
Result<ErrorMaps> SeparateTablePoses(const MachineModel& model, const TablePoseFit& fit, int dof);

// The 12 zero-valued tables over `a_deg` x `c_deg` (ascending; C in [0, 360)) that
// SeparateTablePoses fills. Errors: those of SeparateTablePoses's grid checks.
Result<ErrorState> ZeroErrorMaps(const MachineModel& model, const std::vector<double>& a_deg,
                                 const std::vector<double>& c_deg);

}  // namespace tpcal::kinematics
