#include "pipeline/seed002_items.h"

#include <variant>

namespace tpcal::pipeline {

Result<kinematics::Seed002Geometry> Seed002GeometryOf(const testpieces::TestPiece& piece) {
  const auto* p = std::get_if<testpieces::TurningPieceParams>(&piece.config.params);
  if (p == nullptr)
    return Status(StatusCode::kInvalidArgument, "the seed 002 equations apply to the turning piece, not the " + piece.name);
  kinematics::Seed002Geometry g;
  g.z_R = p->groove_bottom_z_mm + p->groove_wall_lift_mm;  // Z of the S_R wall pass
  g.z_h = p->hole_probe_z_mm();
  g.z1 = p->steps[0].probe_z_mm;
  g.z2 = p->steps[1].probe_z_mm;
  g.z3 = p->steps[2].probe_z_mm;
  g.z4 = p->steps[3].probe_z_mm;
  g.z5 = p->steps[4].probe_z_mm;
  g.z6 = p->steps[5].probe_z_mm;
  g.rho_B3 = p->steps[2].radius_mm + p->bottom_probe_fraction * (p->BottomOuterRadius(2) - p->steps[2].radius_mm);
  return g;
}

Result<kinematics::Seed002Items> Seed002ItemsFromInspection(const gdt::InspectionResult& inspection) {
  kinematics::Seed002Items items;
  auto take = [&](const std::string& characteristic, const std::string& value, const std::string& item,
                  bool required, double sign = 1.0) -> Status {
    const gdt::CharacteristicResult* c = inspection.Characteristic(characteristic);
    const std::optional<double> v = c ? c->Value(value) : std::nullopt;
    if (!v) {
      if (!required) return Status();
      return Status(StatusCode::kInvalidArgument, "the inspection has no " + characteristic + "/" + value +
                                                      " (seed 002 Table 1 item " + item + ")");
    }
    items[item] = sign * *v;
    return Status();
  };
  TPCAL_RETURN_IF_ERROR(take("t1_concentricity_Ch_SR", "dx_um", "dx_Ch_SR_um", true));
  TPCAL_RETURN_IF_ERROR(take("t1_concentricity_Ch_SR", "dy_um", "dy_Ch_SR_um", true));
  TPCAL_RETURN_IF_ERROR(take("t2_parallelism_B1_BR", "da_urad", "da_B1_BR_urad", true));
  TPCAL_RETURN_IF_ERROR(take("t2_parallelism_B1_BR", "db_urad", "db_B1_BR_urad", true));
  TPCAL_RETURN_IF_ERROR(take("t3_distance_B3_BR", "separation_error_um", "dd_B3_BR_um", true));
  TPCAL_RETURN_IF_ERROR(take("t4_size_S3", "radius_error_um", "dr_S3_um", true));
  TPCAL_RETURN_IF_ERROR(take("t5_concentricity_S4_SR", "dx_um", "dx_S4_SR_um", true));
  TPCAL_RETURN_IF_ERROR(take("t5_concentricity_S4_SR", "dy_um", "dy_S4_SR_um", true));
  TPCAL_RETURN_IF_ERROR(take("t6_concentricity_S4_S1", "dx_um", "dx_S4_S1_um", true));
  TPCAL_RETURN_IF_ERROR(take("t6_concentricity_S4_S1", "dy_um", "dy_S4_S1_um", true));
  TPCAL_RETURN_IF_ERROR(take("t7_concentricity_S6_S3", "dx_um", "dx_S6_S3_um", true));
  TPCAL_RETURN_IF_ERROR(take("t7_concentricity_S6_S3", "dy_um", "dy_S6_S3_um", true));
  TPCAL_RETURN_IF_ERROR(take("concentricity_S3_SR", "dx_um", "dx_S3_SR_um", false));
  TPCAL_RETURN_IF_ERROR(take("concentricity_S3_SR", "dy_um", "dy_S3_SR_um", false));
  auto radius = [&](const char* s) -> std::optional<double> {
    const gdt::CharacteristicResult* c = inspection.Characteristic(std::string(s));
    return c ? c->Value("radius_error_um") : std::nullopt;
  };
  if (auto r1 = radius("size_S1"), r4 = radius("size_S4"); r1 && r4) items["dr_S1_S4_um"] = *r1 - *r4;
  if (auto r2 = radius("size_S2"), r5 = radius("size_S5"); r2 && r5) items["dr_S2_S5_um"] = *r2 - *r5;
  return items;
}

}  // namespace tpcal::pipeline
