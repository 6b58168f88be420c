// The table's pose at each indexed rotary position of an on-machine probing test (seed 000
// section 4.1, eq. 7-9), from the probed contact points on the artifacts.
//
// Model. The table pose error at a position is a small rigid motion of the table in the machine
// frame, translation (dx, dy, dz) of the machine origin and rotation (da, db, dc) about the
// machine X, Y, Z axes through it: a table point at nominal machine position p is at
// p + t + theta x p. A contact point m (machine frame) of face f then satisfies, to first order,
//   n_f . T0^-1 m - d_f = e_f + n . t + theta . (m x n),   n = R0 n_f (machine-frame normal),
// T0 the nominal machine_from_part at the position, d_f the face's nominal plane offset and e_f
// its offset error (the artifact's placement and size, a nuisance per face). One least-squares
// problem over every touch holds all poses and face offsets; the pose at the reference position
// is zero by definition (the artifacts are located there, as seed 000 eq. 6 does), so every pose
// is the table's pose relative to it: exactly T(p) T(ref)^-1 T0(ref) T0(p)^-1 for actual poses T
// (TablePoseError). Columns are scaled to unit norm; rank by SVD (singular values below
// `rank_tolerance` times the largest are dropped); what the touches cannot determine (a pose
// component without a touch along it, a face never touched where the pose is known) is named,
// and its covariance rows are zero. sigma = sqrt(SSR / (touches - rank)); with every touch's
// u_um given, rows are weighted by 1/u and sigma is the chi-like scale of the covariance.
// The linear axes' constant errors (TablePoseOptions::linear_errors, squareness by default) add
// one column each: -n . d(probe centre in the part frame)/d(error) at the touch's linear command
// (ToolPointInPart, the exact chain by central differences), global over every pose.
#pragma once

#include <Eigen/Core>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "kinematics/axis_state.h"
#include "kinematics/error_parameters.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/machine_model.h"
#include "kinematics/probe_artifacts.h"

namespace tpcal::kinematics {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Names and units of the six pose components, in order.
inline constexpr const char* kPoseComponents[6] = {"dx", "dy", "dz", "da", "db", "dc"};
inline constexpr const char* kPoseUnits[6] = {"um", "um", "um", "urad", "urad", "urad"};

struct TablePose {
  double a_deg = 0.0, c_deg = 0.0;  // the indexed position (C in [0, 360))
  bool reference = false;           // the pose is zero by definition
  int touches = 0;
  Vector6d value = Vector6d::Zero();  // um, urad
  std::array<bool, 6> identifiable{};
};

struct FaceOffsetEstimate {
  int artifact = 0;
  BoxFace face = BoxFace::kPlusZ;
  int touches = 0;
  bool identifiable = false;
  double value_um = 0.0, u_um = 0.0;  // along the outward normal
};

struct TablePoseOptions {
  double reference_a_deg = 0.0, reference_c_deg = 0.0;
  double position_tolerance_deg = 1e-6;  // touches within this of a position share its pose
  double rank_tolerance = 1e-9;          // relative singular value below which a direction is dropped
  // Constant errors of the linear axes fitted with the poses (catalog names): a squareness error
  // shears the probed volume, which no rigid pose of the table explains but each pose would take
  // in part. Fitted only when the touches determine every one of them (else none is, and each is
  // reported not identifiable). Empty: the linear axes taken as error-free (seed 000's model).
  std::vector<std::string> linear_errors = LinearSquarenessSet();
  // The stylus ball radius (mm): a touch's linear command is its contact minus radius x approach.
  double probe_radius_mm = kSeed000StylusRadiusMm;
};

struct TablePoseFit {
  std::vector<double> a_deg, c_deg;      // the distinct positions, ascending (C in [0, 360))
  std::vector<TablePose> poses;          // A-major, then C; only positions with touches
  std::vector<FaceOffsetEstimate> faces; // touched faces, artifact then kBoxFaces order
  // options.linear_errors, in order (urad; value and u, k = 1, when identifiable).
  std::vector<ParameterEstimate> linear_errors;
  Eigen::MatrixXd covariance;            // of the poses' 6 x poses values (um, urad), k = 1
  std::vector<double> residuals_um;      // per touch, input order
  int num_touches = 0, rank = 0, dof = 0;
  double sigma_um = 0.0;   // sqrt(SSR / dof), unweighted residuals
  bool weighted = false;   // every touch had u_um > 0
  double chi_scale = 0.0;  // weighted: sqrt(sum (r/u)^2 / dof); else 0
};

// Errors: kInvalidArgument (an artifact index out of range, an approach not unit, u_um < 0 or
// given for some touches only, the reference position without touches; Status::line() the touch's),
// kTooFewPoints (touches <= rank).
Result<TablePoseFit> FitTablePoses(const MachineModel& model, const ArtifactSet& artifacts,
                                   std::span<const ProbeTouch> touches, const TablePoseOptions& options = {});

// The exact table pose error (um, urad, as TablePose::value) of `errors` at `rotary` relative to
// `reference`: the vee of T(p) T(ref)^-1 T0(ref) T0(p)^-1 (rotation by its skew part). What
// FitTablePoses estimates; used for truths and for the separation's design.
Vector6d TablePoseError(const MachineModel& model, const ErrorState& errors, const AxisState& rotary,
                        const AxisState& reference);
// The same without a reference: the vee of T(p) T0(p)^-1 (the table's own pose error).
Vector6d AbsoluteTablePoseError(const MachineModel& model, const ErrorState& errors, const AxisState& rotary);

}  // namespace tpcal::kinematics
