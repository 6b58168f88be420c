#include "testpieces/probe_artifacts_plan.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

constexpr double kArtifactPlanFacesDownNz = -0.1;   // header: a face pointing down is not probed
constexpr double kArtifactPlanRiseMm = 1000.0;       // the vertical corridor: this far up (mm)
constexpr double kArtifactPlanTouchTolMm = 1e-9;     // grazing an inflated box is not a collision

Status ArtifactPlanError(const std::string& what) {
  return {StatusCode::kInvalidArgument, "probe-artifacts plan: " + what};
}

// Does the segment a-b (part frame) pass through the interior of `box` grown by `r_mm` on every
// side (the slab test in the box's own frame)? Grazing a face (within 1e-9 mm) does not count.
bool ArtifactPlanSegmentMeetsBox(const Eigen::Vector3d& a_part, const Eigen::Vector3d& b_part,
                                 const kinematics::ArtifactBox& box, double r_mm) {
  const double rot = DegToRad(box.rotation_deg);
  const Eigen::Vector3d ex(std::cos(rot), std::sin(rot), 0.0), ey(-std::sin(rot), std::cos(rot), 0.0);
  auto local = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - box.base_centre_mm;
    return Eigen::Vector3d(ex.dot(d), ey.dot(d), d.z());
  };
  const Eigen::Vector3d a = local(a_part), b = local(b_part);
  const Eigen::Vector3d lo(-0.5 * box.size_mm.x() - r_mm, -0.5 * box.size_mm.y() - r_mm, -r_mm);
  const Eigen::Vector3d hi(0.5 * box.size_mm.x() + r_mm, 0.5 * box.size_mm.y() + r_mm, box.size_mm.z() + r_mm);
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    if (std::abs(d) < 1e-15) {
      if (a[k] <= lo[k] + kArtifactPlanTouchTolMm || a[k] >= hi[k] - kArtifactPlanTouchTolMm) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d, tb = (hi[k] - a[k]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return (t1 - t0) * (b_part - a_part).norm() > kArtifactPlanTouchTolMm;
}

// Why the stylus-ball centre path (machine frame) `path_m` cannot be used, or nothing. The first
// leg (the approach to the face) is checked against the other boxes; every later leg against all
// boxes (the touched box included) and every leg against the table, each grown by the radius.
std::optional<std::string> ArtifactPlanCorridorBlock(const std::vector<Eigen::Vector3d>& path_m,
                                                     const Rigid3& table_from_machine,
                                                     const kinematics::ArtifactSet& artifacts, int own,
                                                     const ProbeArtifactsPlanOptions& o) {
  for (std::size_t leg = 0; leg + 1 < path_m.size(); ++leg) {
    const Eigen::Vector3d a = table_from_machine * path_m[leg], b = table_from_machine * path_m[leg + 1];
    for (std::size_t j = 0; j < artifacts.boxes.size(); ++j) {
      if (leg == 0 && static_cast<int>(j) == own) continue;
      if (ArtifactPlanSegmentMeetsBox(a, b, artifacts.boxes[j], o.probe_radius_mm)) {
        const std::string& name = artifacts.boxes[j].name;
        return "corridor meets artifact " + (name.empty() ? std::to_string(j + 1) : name);
      }
    }
    if (std::min(a.z(), b.z()) < o.table_z_mm + o.probe_radius_mm - kArtifactPlanTouchTolMm)
      return std::string("corridor meets the table");
  }
  return std::nullopt;
}

Status CheckArtifacts(const kinematics::ArtifactSet& artifacts) {
  if (artifacts.boxes.empty()) return ArtifactPlanError("no artifact");
  for (std::size_t i = 0; i < artifacts.boxes.size(); ++i) {
    const kinematics::ArtifactBox& b = artifacts.boxes[i];
    if (!(b.size_mm.minCoeff() > 0.0) || !b.size_mm.allFinite() || !b.base_centre_mm.allFinite() ||
        !std::isfinite(b.rotation_deg))
      return ArtifactPlanError("artifact " + std::to_string(i + 1) + " ('" + b.name +
                               "'): sizes must be > 0 and every value finite");
  }
  return Status::Ok();
}

}  // namespace

Status ProbeArtifactsPlanOptions::Validate() const {
  if (a_deg.empty()) return ArtifactPlanError("a_deg: no tilt angle");
  for (double a : a_deg)
    if (!std::isfinite(a)) return ArtifactPlanError("a_deg: a value is not finite");
  if (!(c_step_deg > 0.0 && c_step_deg <= 360.0))
    return ArtifactPlanError("c_step_deg " + std::to_string(c_step_deg) + ", expected in (0, 360]");
  if (!(probe_radius_mm > 0.0) || !std::isfinite(probe_radius_mm))
    return ArtifactPlanError("probe_radius_mm must be > 0");
  if (!(clearance_mm > 0.0) || !std::isfinite(clearance_mm)) return ArtifactPlanError("clearance_mm must be > 0");
  if (!std::isfinite(table_z_mm)) return ArtifactPlanError("table_z_mm is not finite");
  return Status::Ok();
}

Result<ProbeArtifactsPlan> MakeProbeArtifactsPlan(const kinematics::MachineModel& model,
                                                  const kinematics::ArtifactSet& artifacts,
                                                  const ProbeArtifactsPlanOptions& options) {
  if (model.type != kinematics::MachineType::kAcTable)
    return ArtifactPlanError(std::string("machine type ") + kinematics::MachineTypeName(model.type) +
                             ", expected ac_table");
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(CheckArtifacts(artifacts));
  ProbeArtifactsPlan plan;
  plan.artifacts = artifacts;
  plan.probe_radius_mm = options.probe_radius_mm;
  const double r = options.probe_radius_mm;
  const int c_count = static_cast<int>(std::ceil(360.0 / options.c_step_deg - 1e-9));
  for (double a : options.a_deg) {
    for (int k = 0; k < c_count; ++k) {
      kinematics::AxisState pose;
      pose.a_rad = DegToRad(a);
      pose.c_rad = DegToRad(k * options.c_step_deg);
      if (Status st = kinematics::CheckStrokes(model, pose); !st.ok())
        return ArtifactPlanError("A " + std::to_string(a) + " deg: " + st.message());
      plan.poses.push_back(pose);
    }
  }
  for (const kinematics::AxisState& pose : plan.poses) {
    const Rigid3 machine_from_table = kinematics::NominalMachineFromTable(model, pose);
    const Rigid3 table_from_machine = machine_from_table.inverse();
    for (std::size_t i = 0; i < artifacts.boxes.size(); ++i) {
      for (kinematics::BoxFace f : kinematics::kBoxFaces) {
        const kinematics::FaceGeometry g = kinematics::FaceOf(artifacts.boxes[i], f);
        const Eigen::Vector3d n_m = (machine_from_table.linear() * g.normal).normalized();
        const int box = static_cast<int>(i);
        std::optional<std::string> reason;
        const Eigen::Vector3d contact_m = machine_from_table * g.centre_mm;
        if (n_m.z() < kArtifactPlanFacesDownNz) {
          reason = "faces down";
        } else {
          const Eigen::Vector3d start = contact_m + (r + options.clearance_mm) * n_m;
          reason = ArtifactPlanCorridorBlock(
              {contact_m + r * n_m, start, start + kArtifactPlanRiseMm * Eigen::Vector3d::UnitZ()},
              table_from_machine, artifacts, box, options);
        }
        if (reason) {
          plan.skipped.push_back({pose, box, f, *reason});
          continue;
        }
        PlannedTouch t;
        t.rotary = pose;
        t.artifact = box;
        t.face = f;
        t.target_part_mm = g.centre_mm;
        t.contact_mm = contact_m;
        t.approach = -n_m;
        plan.touches.push_back(t);
      }
    }
  }
  return plan;
}

}  // namespace tpcal::testpieces
