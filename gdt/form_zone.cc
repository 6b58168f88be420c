#include "gdt/form_zone.h"

// The minimum-zone evaluations belong to the fitting layer (fitting/minimum_zone.h). A build
// without that header reports the criterion as unavailable instead of returning a number: no
// least-squares value is ever passed off as minimum zone.
#if __has_include("fitting/minimum_zone.h")
#include "fitting/minimum_zone.h"
#define TPCAL_GDT_HAVE_MINIMUM_ZONE 1
#else
#define TPCAL_GDT_HAVE_MINIMUM_ZONE 0
#endif

namespace tpcal::gdt {
namespace {

#if TPCAL_GDT_HAVE_MINIMUM_ZONE
template <typename Zone>
MinimumZoneValue FromZone(const Zone& z, double width_mm) {
  MinimumZoneValue v;
  v.width_mm = width_mm;
  v.verified_optimal = z.certificate.verified_optimal;
  v.note = z.certificate.method + (z.certificate.message.empty() ? "" : ": " + z.certificate.message);
  return v;
}

template <typename Zone>
Result<MinimumZoneValue> Wrap(const Result<Zone>& r) {
  if (!r.ok()) return r.status();
  if constexpr (requires { r->diameter_mm; }) {
    return FromZone(*r, r->diameter_mm);
  } else {
    return FromZone(*r, r->width_mm);
  }
}
#else
Status Unavailable(const char* what) {
  return Status(StatusCode::kInternal, std::string("minimum-zone ") + what +
                                           " is not available in this build (fitting/minimum_zone.h missing); "
                                           "use criterion ls");
}
#endif

}  // namespace

bool MinimumZoneAvailable() { return TPCAL_GDT_HAVE_MINIMUM_ZONE != 0; }

#if TPCAL_GDT_HAVE_MINIMUM_ZONE
Result<MinimumZoneValue> MinimumZoneCircularity(std::span<const Eigen::Vector2d> p) {
  return Wrap(fitting::MinimumZoneCircularity(p));
}
Result<MinimumZoneValue> MinimumZoneFlatness(std::span<const Eigen::Vector3d> p) {
  return Wrap(fitting::MinimumZoneFlatness(p));
}
Result<MinimumZoneValue> MinimumZoneStraightness2(std::span<const Eigen::Vector2d> p) {
  return Wrap(fitting::MinimumZoneStraightness2(p));
}
Result<MinimumZoneValue> MinimumZoneStraightness3(std::span<const Eigen::Vector3d> p) {
  return Wrap(fitting::MinimumZoneStraightness3(p));
}
Result<MinimumZoneValue> MinimumZoneCylindricity(std::span<const Eigen::Vector3d> p,
                                                 std::optional<fitting::Cylinder> start) {
  return Wrap(fitting::MinimumZoneCylindricity(p, {}, start));
}
#else
Result<MinimumZoneValue> MinimumZoneCircularity(std::span<const Eigen::Vector2d>) {
  return Unavailable("circularity");
}
Result<MinimumZoneValue> MinimumZoneFlatness(std::span<const Eigen::Vector3d>) { return Unavailable("flatness"); }
Result<MinimumZoneValue> MinimumZoneStraightness2(std::span<const Eigen::Vector2d>) {
  return Unavailable("straightness (2D)");
}
Result<MinimumZoneValue> MinimumZoneStraightness3(std::span<const Eigen::Vector3d>) {
  return Unavailable("straightness (3D)");
}
Result<MinimumZoneValue> MinimumZoneCylindricity(std::span<const Eigen::Vector3d>, std::optional<fitting::Cylinder>) {
  return Unavailable("cylindricity");
}
#endif

}  // namespace tpcal::gdt
