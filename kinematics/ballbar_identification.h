// Identification of the six error motions of one rotary axis at every measured angle from
// double-ball-bar bar-length changes in several installations (seed 003, Ni et al., Sec. 1.3-2.2,
// Tables 1-4), the two-step linear design of kinematics/error_map_separation.h.
//
// Unknowns. At every distinct measured angle (the nodes) the error motions E_X<K>, E_Y<K>, E_Z<K>
// (um), E_A<K>, E_B<K>, E_C<K> (urad) of the axis K, as 1-D kTable terms over the nodes (linear;
// periodic when K is continuous: the angles are then reduced into [0, 360) and 360 is node 0),
// plus the set-up unknowns per installation: a constant dl offset (the bar-length calibration,
// `fit_length_offsets`) and the first harmonic a cos(angle) + b sin(angle) of dl (the centring of
// the balls over the axis, removed as ball-bar software does, `fit_centring`).
//
// Model. dl = dl0 + G e + S s (um), dl0 the nominal machine's dl (0 to rounding), G by central
// differences (h = 1e-6 internal units) of the exact chain (kinematics/ballbar.h: the bar length
// at the reading's commands, which do not depend on the errors, so this is the derivative of
// SimulateBallbarDlUm); linear to first order (second order: |e|^2 / L0 ~ 1e-7 um at 10 um).
// Every reading sits on its node, so it sees only that node's six values.
//
// Solution. Scaled-column SVD least squares (rank by `rank_tolerance` relative to the largest
// singular value); sigma from the residuals with dof = rows - rank (dof <= 0: sigma unknown, no
// u); covariance sigma^2 (A^T A)^+. The null space is what the data cannot separate: its error
// part spans the `not_separable` families, named by the candidate families they contain (the
// mean, cos and sin of the radial, tangential and axial translation and tilt, relative to the
// axis). CONVENTION (as error_map_separation.h's zero means): the reported maps carry no component
// along those families (orthogonal in display units); the set-up terms absorb them. An entry lying
// entirely in that span (|row of the orthonormal basis|^2 = 1, e.g. an error no installation
// sees) gets no number and is named in `not_identifiable`; an entry touched by the span at all is
// not determined by the data alone and is counted in `convention_dependent`.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/ballbar.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// One dl of the ball-bar file (pipeline/io/ballbar_io.h), its installation as an index.
struct BallbarReading {
  int installation = 0;   // index into the geometry list
  double angle_deg = 0.0; // command of the turned axis
  double dl_um = 0.0;     // bar length - nominal length
  double t_s = 0.0;
  int line = 0;           // source line, for messages (0: unknown)
};

struct BallbarIdentificationOptions {
  Axis axis = Axis::kC;            // the rotary axis identified; every installation must turn it
  bool fit_length_offsets = true;  // one constant dl offset per installation (um)
  bool fit_centring = true;        // per installation a cos(angle) + b sin(angle) of dl (um)
  // Singular values below this * the largest are null. G is a central difference of ~200 mm
  // lengths with h = 1e-6 mm: its rounding is ~1e-8 relative, so true null directions show
  // singular values ~1e-9 .. 1e-11 (the seven seed 003 installations: next one up is 5e-2).
  double rank_tolerance = 1e-6;
  // kInvalidArgument: a linear axis, rank_tolerance not in (0, 1).
  Status Validate() const;
};

struct BallbarErrorEntry {
  std::string symbol;       // "E_XC" .. "E_CC"
  std::string coefficient;  // ErrorState coefficient name ("E_XC.n3")
  double angle_deg = 0.0;   // the node
  std::string unit;         // "um" or "urad"
  bool identifiable = false;         // a number is given (relative to the convention)
  bool convention_dependent = true;  // the not-separable families touch it
  double value = 0.0, u = 0.0;       // display units, k = 1 (0 when not identifiable / unknown)
  double ci95_low = 0.0, ci95_high = 0.0;
};

struct BallbarSetupTerm {
  int installation = 0;
  std::string name;  // "<installation> offset", "<installation> centring cos", "... centring sin"
  bool identifiable = false;
  double value_um = 0.0, u_um = 0.0;
};

struct BallbarIdentification {
  explicit BallbarIdentification(ErrorState base) : errors(std::move(base)) {}
  std::vector<double> angle_deg;  // the nodes, ascending
  bool periodic = false;
  ErrorState errors;              // the six tables with the identified node values
  std::vector<BallbarErrorEntry> entries;  // in coefficient order of `errors` (term d, node i)
  std::vector<BallbarSetupTerm> setup_terms;
  std::vector<double> residuals_um;        // per reading, in input order
  int rows = 0, unknowns = 0, rank = 0, dof = 0;
  bool sigma_known = false;                // dof > 0
  double sigma_um = 0.0;
  Eigen::MatrixXd covariance;              // of the entries, display units
  // Orthonormal basis (entries x k, display units) of the error part of the null space: the
  // reported maps are orthogonal to it. A truth t is comparable as t - B B^T t.
  Eigen::MatrixXd not_separable_basis;
  std::vector<std::string> not_separable;  // the confounded families, in words
  std::vector<std::string> not_identifiable;  // entries without a number: "E_XC(C 40)"
  int convention_dependent = 0;               // entries not determined by the data alone
  std::vector<std::string> conventions;
};

// Errors: kInvalidArgument (bad options, an installation that is not rotary or turns another
// axis, a reading naming no installation, a non-finite value, fewer than 2 distinct angles);
// those of BallbarCommand.
Result<BallbarIdentification> IdentifyBallbar(const MachineModel& model,
                                              const std::vector<BallbarGeometry>& installations,
                                              const std::vector<BallbarReading>& readings,
                                              const BallbarIdentificationOptions& options = {});

// How IdentifyBallbar folds errors its model lacks into the maps: for each of `errors` (catalog
// names of position-independent errors, e.g. the linear axes' squareness, which the turned axis's
// motions take in part), the entries' values (display units, entry order, one column each) it
// reports from the bar-length changes 1 display unit of that error alone causes at the readings'
// installations and angles (the readings' own dl_um unused). Errors: an unknown or repeated name,
// a name that is not one position-independent error (kInvalidArgument), SimulateBallbarDlUm's,
// IdentifyBallbar's.
Result<Eigen::MatrixXd> BallbarMapResponse(const MachineModel& model, const std::vector<BallbarGeometry>& installations,
                                           const std::vector<BallbarReading>& readings,
                                           const std::vector<std::string>& errors,
                                           const BallbarIdentificationOptions& options = {});

}  // namespace tpcal::kinematics
