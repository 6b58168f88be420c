#include "kinematics/probe_artifacts.h"

#include <cmath>
#include <numbers>

#include "kinematics/error_state.h"
#include "kinematics/forward_kinematics.h"

namespace tpcal::kinematics {

const char* BoxFaceName(BoxFace f) {
  switch (f) {
    case BoxFace::kPlusX: return "+X";
    case BoxFace::kMinusX: return "-X";
    case BoxFace::kPlusY: return "+Y";
    case BoxFace::kMinusY: return "-Y";
    case BoxFace::kPlusZ: return "+Z";
  }
  return "?";
}

std::optional<BoxFace> BoxFaceFromName(std::string_view name) {
  for (BoxFace f : kBoxFaces) {
    if (name == BoxFaceName(f)) return f;
  }
  return std::nullopt;
}

FaceGeometry FaceOf(const ArtifactBox& box, BoxFace face) {
  const double r = box.rotation_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d ex(std::cos(r), std::sin(r), 0.0), ey(-std::sin(r), std::cos(r), 0.0);
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d mid = box.base_centre_mm + 0.5 * box.size_mm.z() * ez;
  FaceGeometry g;
  auto side = [&](const Eigen::Vector3d& n, double half_depth, const Eigen::Vector3d& along, double half_along) {
    g.normal = n;
    g.centre_mm = mid + half_depth * n;
    g.u = along;
    g.v = n.cross(along);  // u x v = normal for a right-handed (u, v, n)
    g.half_u_mm = half_along;
    g.half_v_mm = 0.5 * box.size_mm.z();
  };
  switch (face) {
    case BoxFace::kPlusX: side(ex, 0.5 * box.size_mm.x(), ey, 0.5 * box.size_mm.y()); break;
    case BoxFace::kMinusX: side(-ex, 0.5 * box.size_mm.x(), -ey, 0.5 * box.size_mm.y()); break;
    case BoxFace::kPlusY: side(ey, 0.5 * box.size_mm.y(), -ex, 0.5 * box.size_mm.x()); break;
    case BoxFace::kMinusY: side(-ey, 0.5 * box.size_mm.y(), ex, 0.5 * box.size_mm.x()); break;
    case BoxFace::kPlusZ:
      g.normal = ez;
      g.centre_mm = box.base_centre_mm + box.size_mm.z() * ez;
      g.u = ex;
      g.v = ey;
      g.half_u_mm = 0.5 * box.size_mm.x();
      g.half_v_mm = 0.5 * box.size_mm.y();
      break;
  }
  return g;
}

int ArtifactSet::Find(std::string_view name) const {
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (boxes[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

ArtifactSet Seed000Artifacts() {
  ArtifactSet s;
  const double xy[3][2] = {{100.0, 0.0}, {-100.0, 0.0}, {0.0, 100.0}};
  for (int i = 0; i < 3; ++i) {
    ArtifactBox b;
    b.name = std::to_string(i + 1);
    b.base_centre_mm = Eigen::Vector3d(xy[i][0], xy[i][1], 0.0);
    s.boxes.push_back(b);
  }
  return s;
}

Rigid3 NominalMachineFromTable(const MachineModel& model, const AxisState& rotary) {
  AxisState s;
  s.a_rad = rotary.a_rad;
  s.b_rad = rotary.b_rad;
  s.c_rad = rotary.c_rad;
  Workspace ws;
  return MachineFromPart(model, ErrorState(model), s, &ws);
}

Eigen::Vector3d NominalApproach(const MachineModel& model, const AxisState& rotary, const FaceGeometry& face) {
  return -(NominalMachineFromTable(model, rotary).linear() * face.normal).normalized();
}

}  // namespace tpcal::kinematics
