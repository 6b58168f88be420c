// The nominal B-rep of a test piece (OpenCASCADE: primitives and booleans, kept inside brep.cc)
// and its STEP export. Sharp edges: nose radii and tool corner fillets are not modelled (the
// probing plan keeps ProbingOptions::edge_margin_mm away from them).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

// Writes the piece's solid (part frame, mm) as an AP214 STEP file. Errors: kInternal when
// OpenCASCADE fails to build the solid or the boolean, kIoError when the file cannot be written.
Status WriteStep(const TestPiece& piece, const std::string& path);

// Solid statistics: volume (mm^3), number of faces, bounding box (part frame).
struct BrepSummary {
  double volume_mm3 = 0.0;
  int num_faces = 0;
  Eigen::Vector3d box_min_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max_mm = Eigen::Vector3d::Zero();
};
Result<BrepSummary> SummarizeBrep(const TestPiece& piece);

// Checks points against the solid: distance to its boundary (BRepExtrema_DistShapeShape) and
// classification (BRepClass3d_SolidClassifier) of point +- step_mm * normal. A point passes when
// it is within distance_tol_mm of the boundary, p + step n is outside and p - step n inside.
struct BrepPointCheck {
  double distance_mm = 0.0;
  bool outside_plus = false;
  bool inside_minus = false;
  bool ok = false;
};
Result<std::vector<BrepPointCheck>> CheckPointsOnBrep(const TestPiece& piece,
                                                      const std::vector<Eigen::Vector3d>& points_part_mm,
                                                      const std::vector<Eigen::Vector3d>& normals_part,
                                                      double step_mm = 0.01, double distance_tol_mm = 1e-6);

}  // namespace tpcal::testpieces
