// CMM probing plan of a test piece: nominal points and outward normals on every feature, each
// with the machine state that cut it (kinematics::CutPoint from the cut-state association), and
// the rows of the `tpcal plan v1` CSV (docs/formats/probing_plan.md) the pipeline writes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/point_set.h"
#include "core/status.h"
#include "kinematics/simulate.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct PlanPoint {
  std::string feature;
  Eigen::Vector3d point_part_mm = Eigen::Vector3d::Zero();  // nominal, part frame
  Eigen::Vector3d normal_part = Eigen::Vector3d::UnitZ();   // unit, out of the material
  double level_mm = 0.0;  // the probing level it belongs to (h, radius or v of the feature)
  kinematics::CutPoint cut;  // cut.nominal_point_mm == point_part_mm
};

struct ProbingPlan {
  std::string piece_name;
  Rigid3 part_from_datum = Rigid3::Identity();
  std::vector<PlanPoint> points;  // feature order of the piece, then level, then azimuth / u
};

// Most points a probing plan may hold. Memory budget 4 GB: `tpcal plan` peaks at about 1.05 kB
// per plan point (measured on turning: 0.29 GB for 0.22 M points, 2.4 GB for 2.2 M), so 3 M
// points stay near 3.2 GB; the dense-scan benchmark's 2 M points fit.
inline constexpr std::int64_t kMaxPlanPoints = 3'000'000;

// The number of points MakeProbingPlan makes at `options` (grid patches counted as their whole
// raster, an upper bound), without making them; saturates at a value above kMaxPlanPoints.
std::int64_t PlannedPointCount(const TestPiece& piece, const ProbingOptions& options);

// kInvalidArgument naming the count if the plan at `options` would exceed kMaxPlanPoints.
Status CheckPlanSize(const TestPiece& piece, const ProbingOptions& options);

// The plan at `options` density (the piece's config.probing when omitted). Errors: options
// validation; more than kMaxPlanPoints points (CheckPlanSize, before any is made); a level count
// the feature cannot hold (band too narrow); association failures.
Result<ProbingPlan> MakeProbingPlan(const TestPiece& piece, const ProbingOptions& options);
Result<ProbingPlan> MakeProbingPlan(const TestPiece& piece);

// One row of the probing-plan CSV, in the DATUM frame (docs/formats/probing_plan.md). Rotary angles in
// degrees (A_deg and C_deg on A/C machines; B_deg on B/C machines), linear axes in mm.
struct PlanRow {
  std::string feature;
  Eigen::Vector3d xyz_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d ijk = Eigen::Vector3d::UnitZ();
  int op = 0;
  double t_s = 0.0;
  double a_deg = 0.0, b_deg = 0.0, c_deg = 0.0;
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0;
};
// Column names after feature,x,y,z,i,j,k for `machine`: op, t_s, then A_deg and/or B_deg, C_deg
// (the rotary axes the machine has), X_mm, Y_mm, Z_mm.
std::vector<std::string> PlanExtraColumns(const kinematics::MachineModel& machine);
std::vector<PlanRow> PlanRows(const ProbingPlan& plan);

// The plan's nominal points as a PointSet in the datum frame (labels and normals), the form a
// CMM program or an ideal measurement takes.
PointSet PlanPointSet(const ProbingPlan& plan);

}  // namespace tpcal::testpieces
