// The stock envelope of a test piece for the rapid-move check: the finished piece grown by its
// finishing allowances (turned faces + turning depth of cut, groove wall + finishing stock),
// with the cut voids (groove, holes, bore) removed, in the PART frame (mm). Static: the same
// envelope for the whole program (the in-process stock is not modelled), which is conservative
// for every rapid that happens before a feature is finished.
//
// Signed distance: negative inside the material. Primitive distances are exact inside and a
// lower bound outside (max of the face distances), so the check errs on the safe side near
// edges and corners.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/status.h"
#include "testpieces/test_piece.h"

namespace tpcal::gcode {

struct StockPrimitive {
  enum class Kind {
    kPrism,     // convex polygon (CCW, part XY) extruded over [z_min, z_max]
    kCylinder,  // axis along part Z through center_xy, radius (a tube when inner_radius > 0),
                // [z_min, z_max]
    kFrustum,   // cone about `axis` from `origin`: radius r0 - h tan(half_angle), h in [h_min, h_max]
  };
  Kind kind = Kind::kPrism;
  std::string name;
  std::vector<Eigen::Vector2d> polygon_xy_mm;
  Eigen::Vector2d center_xy_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0.0;
  double inner_radius_mm = 0.0;
  double z_min_mm = 0.0, z_max_mm = 0.0;
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double half_angle_rad = 0.0;
  double h_min_mm = 0.0, h_max_mm = 0.0;

  double SignedDistance(const Eigen::Vector3d& p_mm) const;
};

struct StockEnvelope {
  std::vector<StockPrimitive> solids;  // union
  std::vector<StockPrimitive> voids;   // removed from the union
  Eigen::Vector3d min_mm = Eigen::Vector3d::Zero(), max_mm = Eigen::Vector3d::Zero();  // bounding box

  // Signed distance (mm, < 0 inside) and the name of the nearest solid / void boundary.
  double SignedDistance(const Eigen::Vector3d& p_mm, std::string* nearest = nullptr) const;
};

// The envelope of `piece` from its parameters (turning: stepped raw cylinders r_i + depth of
// cut, base flange, groove / holes / bore voids; M1: base plate and layer prisms, circle boss,
// bore void; M2: the block; cone: base plate and frustum).
Result<StockEnvelope> StockOf(const testpieces::TestPiece& piece);

}  // namespace tpcal::gcode
