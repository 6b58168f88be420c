// Characteristics of cylinders (bores) in the turning frame: orientation of their axes to the
// datum plane and to each other, the location of their axis, their size. Truth in P = D (the
// hole pattern is not shifted).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/units.h"
#include "gdt/inspection.h"
#include "gdt/plan_yaml.h"
#include "gdt/synthetic.h"
#include "gdt/testing/turning_piece.h"

namespace tpcal::gdt {
namespace {

constexpr double kCylinderTol_um = 1e-6;    // exact data, see inspection_test.cc
constexpr double kCylinderTol_urad = 1e-3;

// A bore of radius r whose axis passes through `mid` along `axis`, probed on two rings of 12
// points 10 mm either side of `mid` (so the points' centroid is `mid`).
void AppendBore(PointSet* ps, const std::string& name, const Eigen::Vector3d& mid, const Eigen::Vector3d& axis,
                double r) {
  for (double s : {-10.0, 10.0})
    AppendCircle(ps, name, {.center_mm = mid + s * axis, .axis = axis, .radius_mm = r, .n_points = 12, .hole = true});
}

TEST(CylinderCharacteristics, AxisOrientationLocationAndSize) {
  auto loaded = LoadInspectionPlan(std::string(TPCAL_SOURCE_DIR) + "/samples/plans/turning.yaml");
  ASSERT_TRUE(loaded.ok()) << loaded.status().ToString();
  InspectionPlan plan = *loaded;
  plan.features.push_back({.name = "BORE1", .kind = FeatureKind::kCylinder});
  plan.features.push_back({.name = "BORE2", .kind = FeatureKind::kCylinder});
  plan.characteristics.push_back({.name = "sq1", .type = CharacteristicType::kSquareness, .feature = "BORE1",
                                  .datum = "B_R"});
  plan.characteristics.push_back({.name = "par21", .type = CharacteristicType::kParallelism, .feature = "BORE2",
                                  .datum = "BORE1"});
  plan.characteristics.push_back({.name = "conc1", .type = CharacteristicType::kConcentricity, .feature = "BORE1",
                                  .datum = "S_R"});
  plan.characteristics.push_back({.name = "size1", .type = CharacteristicType::kSize, .feature = "BORE1",
                                  .nominal_diameter_mm = 40.0});
  ASSERT_TRUE(ValidatePlan(plan).ok()) << ValidatePlan(plan).ToString();

  testing::TurningTruth t;
  t.holes_shift_mm.setZero();
  t.rotated_hole_rad = 0;
  PointSet part = testing::MakeTurningPiece(t);
  const double a1 = 5e-6, b1 = -3e-6, a2 = 9e-6, b2 = 1e-6;
  const Eigen::Vector3d axis1 = RotX(a1) * RotY(b1) * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d axis2 = RotX(a2) * RotY(b2) * Eigen::Vector3d::UnitZ();
  AppendBore(&part, "BORE1", {30.0, -40.0, -20.0}, axis1, 20.0 + 0.004);
  AppendBore(&part, "BORE2", {-50.0, 10.0, -60.0}, axis2, 12.0);

  std::mt19937_64 rng(77);
  auto r = EvaluatePlan(plan, Transformed(part, RandomPlacement(rng, 1000.0)));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  auto value = [&](const char* c, const char* v) { return r->Characteristic(c)->Value(v).value_or(std::nan("")); };

  // Squareness of an axis to a plane: the tilt of the axis from the datum normal, split as for
  // parallelism: about X = atan2(-u_y, u_z), about Y = atan2(u_x, u_z).
  EXPECT_NEAR(value("sq1", "da_urad"), RadToUrad(std::atan2(-axis1.y(), axis1.z())), kCylinderTol_urad);
  EXPECT_NEAR(value("sq1", "db_urad"), RadToUrad(std::atan2(axis1.x(), axis1.z())), kCylinderTol_urad);
  const double tilt1 = std::atan2(axis1.head<2>().norm(), axis1.z());
  EXPECT_NEAR(value("sq1", "tilt_urad"), RadToUrad(tilt1), kCylinderTol_urad);
  // Zone: the 20 mm of axis between the probed rings, projected: 20 sin(tilt).
  EXPECT_NEAR(value("sq1", "zone_um"), MmToUm(20.0 * std::sin(tilt1)), kCylinderTol_um);

  // Parallelism of BORE2 to BORE1: differences of the angles.
  EXPECT_NEAR(value("par21", "da_urad"),
              RadToUrad(std::atan2(-axis2.y(), axis2.z()) - std::atan2(-axis1.y(), axis1.z())), kCylinderTol_urad);
  EXPECT_NEAR(value("par21", "db_urad"),
              RadToUrad(std::atan2(axis2.x(), axis2.z()) - std::atan2(axis1.x(), axis1.z())), kCylinderTol_urad);

  // The axis point at the centroid of the points, in datum XY, minus S_R's centre (the origin).
  EXPECT_NEAR(value("conc1", "dx_um"), 30000.0, kCylinderTol_um);
  EXPECT_NEAR(value("conc1", "dy_um"), -40000.0, kCylinderTol_um);
  EXPECT_NEAR(value("size1", "radius_error_um"), 4.0, kCylinderTol_um);
  EXPECT_NEAR(value("size1", "diameter_error_um"), 8.0, kCylinderTol_um);
}

}  // namespace
}  // namespace tpcal::gdt
