// Artifacts of an on-machine probing test (seed 000): square columns (boxes) fixed on the rotary
// table, probed by the spindle's touch-trigger probe at indexed rotary positions. This file holds
// their nominal geometry in the part (table) frame and one probed touch; the identification is in
// kinematics/probe_artifact_identification.h, the virtual touch in kinematics/probe_touch.h.
//
// Geometry. A box stands on the table: `base_centre_mm` is the centre of its bottom face (part
// frame, mm), `size_mm` its extent along its own x, y (the column's cross-section) and z (height),
// `rotation_deg` the turn of its own x, y about the part frame's +z. Faces are named by their
// outward normal in the box's own frame: "+X", "-X", "+Y", "-Y", "+Z" (the bottom sits on the
// table and is never probed).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/frames.h"
#include "kinematics/axis_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

enum class BoxFace { kPlusX, kMinusX, kPlusY, kMinusY, kPlusZ };
inline constexpr BoxFace kBoxFaces[] = {BoxFace::kPlusX, BoxFace::kMinusX, BoxFace::kPlusY,
                                       BoxFace::kMinusY, BoxFace::kPlusZ};

const char* BoxFaceName(BoxFace f);                          // "+X", "-X", "+Y", "-Y", "+Z"
std::optional<BoxFace> BoxFaceFromName(std::string_view name);  // exact names above

struct ArtifactBox {
  std::string name;                                        // as in the probed-point file ("1")
  Eigen::Vector3d base_centre_mm = Eigen::Vector3d::Zero();  // part frame
  Eigen::Vector3d size_mm = Eigen::Vector3d(30.0, 30.0, 60.0);  // own x, y, height; all > 0
  double rotation_deg = 0.0;                               // own x from part +x, about part +z
};

// One face of a box in the part frame: the outward unit normal, the centre of the face, and two
// unit in-plane directions (u, v: right-handed u x v = normal) with the half extents along them.
struct FaceGeometry {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY();
  double half_u_mm = 0.0, half_v_mm = 0.0;
  double offset_mm() const { return normal.dot(centre_mm); }  // plane: normal . p = offset
};
FaceGeometry FaceOf(const ArtifactBox& box, BoxFace face);

struct ArtifactSet {
  std::vector<ArtifactBox> boxes;
  // Index of the box named `name`, or -1.
  int Find(std::string_view name) const;
};

// Seed 000's set (Fig. 2 is missing from the extracted paper; its text gives three square
// columns placed symmetrically in X and Y, far apart to magnify the tilts, eq. 5): three
// 30 x 30 x 60 mm columns named "1", "2", "3" standing on the table (z = 0 of the part frame) at
// (100, 0), (-100, 0) and (0, 100) mm.
ArtifactSet Seed000Artifacts();

// The stylus ball radius a probing test is taken with when nothing says otherwise (mm): seed
// 000's 6 mm ruby.
inline constexpr double kSeed000StylusRadiusMm = 3.0;

// machine_from_part of the error-free `model` at the rotary commands of `rotary` (its linear
// members ignored: an A/C or B/C table carries the part on rotary axes only).
Rigid3 NominalMachineFromTable(const MachineModel& model, const AxisState& rotary);
// The nominal approach direction (machine frame, unit, toward the surface) of `face` at `rotary`.
Eigen::Vector3d NominalApproach(const MachineModel& model, const AxisState& rotary, const FaceGeometry& face);

// One touch of the probe: rotary commands (linear members ignored), the face touched, the contact
// point in the machine frame (probe-ball centre at the trigger + its radius along the approach
// direction) and the approach direction (unit, machine frame, toward the surface).
struct ProbeTouch {
  AxisState rotary;
  int artifact = 0;                  // index into ArtifactSet::boxes
  BoxFace face = BoxFace::kPlusZ;
  Eigen::Vector3d contact_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d approach = -Eigen::Vector3d::UnitZ();
  std::size_t line = 0;              // source line (0: none)
  double u_um = 0.0;                 // standard uncertainty along the approach, um (0: not given)
};

}  // namespace tpcal::kinematics
