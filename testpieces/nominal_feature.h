// Nominal features of a test piece: the surface patches a CMM probes, as small value types in
// the PART frame (the frame fixed to the table / last workpiece link, kinematics/conventions.h;
// for the turning piece its origin is the nominal A/C intersection and +Z the C axis).
// Lengths in mm, angles in rad. Normals point OUT OF THE MATERIAL.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace tpcal::testpieces {

enum class SurfaceType {
  kPlane,     // bounded by an annulus about `origin_mm` or by a convex polygon
  kCylinder,  // full revolution, axial band [h_min, h_max] along `axis` from `origin_mm`
  kCone,      // full revolution, r(h) = radius_mm - h tan(half_angle) (narrowing toward +axis)
};
const char* SurfaceTypeName(SurfaceType t);  // "plane", "cylinder", "cone"

// How a CMM probes the feature (probing_plan.h):
enum class ProbePattern {
  kCircles,  // cylinder / cone: circles at heights h; annulus: circles at radii (points evenly
             // spaced in azimuth from azimuth 0)
  kLines,    // plane: lines along u at levels v (straight side faces)
  kGrid,     // plane polygon: a grid over the patch
};

// A nominal surface patch. Frame: `origin_mm`, unit `axis` (plane: outward normal; cylinder and
// cone: the axis, pointing toward the part's top), unit `ref_dir` (perpendicular to axis: the
// direction of azimuth 0, and the in-plane u axis of a plane; v = axis x ref_dir).
struct NominalFeature {
  std::string name;         // the point-file label ("S1", "H3", "SQ_XP")
  SurfaceType type = SurfaceType::kPlane;
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d ref_dir = Eigen::Vector3d::UnitX();
  double radius_mm = 0.0;       // cylinder radius; cone radius at h = 0
  double half_angle_rad = 0.0;  // cone only, in (0, pi/2)
  bool internal = false;        // cylinder: material outside (hole, bore, groove outer wall):
                                // the normal points toward the axis
  bool hole = false;            // a small hole: probed with ProbingOptions::points_per_hole
  // Cylinder / cone: axial band (mm along axis from origin). Plane annulus: radial band about
  // origin (r_min may be 0). Polygon planes ignore these.
  double h_min_mm = 0.0, h_max_mm = 0.0;
  double r_min_mm = 0.0, r_max_mm = 0.0;
  // Plane polygon (convex, counter-clockwise about `axis`) in (u, v) coordinates; empty: annulus.
  std::vector<Eigen::Vector2d> polygon_uv_mm;
  // Optional convex hole in the polygon (a frame-shaped floor around an island), (u, v), CCW.
  std::vector<Eigen::Vector2d> hole_uv_mm;
  ProbePattern pattern = ProbePattern::kCircles;
  // Design probing levels (h for cylinders / cones, radius for annuli, v for lines) used when one
  // level per face is asked; the paper's heights for the turning piece.
  std::vector<double> design_levels_mm;
  // Always probe exactly the design levels, whatever the density asks (a straight face fitted as
  // a line, a cone section fitted as a circle: more levels would break the fitted primitive).
  bool fixed_levels = false;
  // Probe-able band for several levels (same coordinate as the levels): inside the patch, away
  // from fillets and edges.
  double level_min_mm = 0.0, level_max_mm = 0.0;
  // kLines: the probed u range.
  double line_u_min_mm = 0.0, line_u_max_mm = 0.0;
  std::string description;  // what the face is, one line ("turned side face, A = 0, tool at +X")

  Eigen::Vector3d v_dir() const { return axis.cross(ref_dir); }
};

// Checks unit axis / ref_dir, orthogonality, positive radii, ordered bands, cone angle range,
// convex CCW polygon. kInvalidArgument naming the feature.
Status ValidateFeature(const NominalFeature& f);

// Surface coordinates of a point on (or near) a feature.
//   plane: (u, v) in-plane; cylinder / cone: (theta, h) with theta in [0, 2 pi) from ref_dir
//   counter-clockwise about axis, h along axis from origin.
struct SurfaceCoords {
  double s1 = 0.0;  // u (mm) or theta (rad)
  double s2 = 0.0;  // v (mm) or h (mm)
};

// Nearest point of the (unbounded) nominal surface to p, with its outward normal.
struct Projection {
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // out of the material
  SurfaceCoords coords;
  double signed_distance_mm = 0.0;  // (p - point) . normal: positive outside the material
  bool in_patch = false;            // the projection lies inside the patch bounds
};

// Orthogonal projection onto the nominal surface (a cone is projected along its normal).
// Fails (kDegenerate) for a point on the axis of a cylinder / cone (azimuth undefined).
Result<Projection> ProjectOnto(const NominalFeature& f, const Eigen::Vector3d& p_mm);

// Point and outward normal at surface coordinates (no bounds check).
Eigen::Vector3d PointAt(const NominalFeature& f, const SurfaceCoords& c);
Eigen::Vector3d NormalAt(const NominalFeature& f, const SurfaceCoords& c);

// True if (u, v) lies in the plane patch (annulus, or polygon minus hole) shrunk by `margin_mm`.
bool InPlanePatch(const NominalFeature& f, const Eigen::Vector2d& uv_mm, double margin_mm = 0.0);

// Name lookup in a feature list; nullptr if absent.
const NominalFeature* FindFeature(const std::vector<NominalFeature>& features, const std::string& name);

}  // namespace tpcal::testpieces
