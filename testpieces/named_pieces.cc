#include "testpieces/named_pieces.h"

#include <sstream>

namespace tpcal::testpieces {
namespace {

std::string Mm(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

const std::vector<std::string>& PieceNames() {
  static const std::vector<std::string> names = {"turning",         "turning_enriched", "iso10791_m1",
                                                 "iso10791_m1_160", "iso10791_m1_320",  "iso10791_m2",
                                                 "cone_frustum",    "cone_frustum_enriched"};
  return names;
}

std::string PieceNameList() {
  std::string list;
  for (const auto& n : PieceNames()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

kinematics::MachineType UsualMachine(const PieceConfig& config) {
  const PieceKind kind = KindOf(config.params);
  return kind == PieceKind::kTurning || kind == PieceKind::kConeFrustum ? kinematics::MachineType::kAcTable
                                                                        : kinematics::MachineType::kXyz;
}

Result<NamedPiece> NamedPieceConfig(std::string_view name) {
  NamedPiece n;
  if (name == "turning") {
    n.config.params = TurningPieceParams{};
  } else if (name == "turning_enriched") {
    // samples/testpieces/turning_enriched.yaml
    TurningPieceParams p;
    p.name = "seed 002 turning piece, enriched (inner groove wall cut CW, 3 levels x 32 points per face)";
    p.groove_inner_wall_pass = true;
    n.config.params = p;
    n.config.probing.points_per_circle = 32;
    n.config.probing.levels_per_face = 3;
    n.config.probing.levels_per_hole = 2;
  } else if (name == "iso10791_m1" || name == "iso10791_m1_320" || name == "iso10791_m1_160") {
    const double size_mm = name == "iso10791_m1_160" ? 160.0 : 320.0;
    n.config.params = ContourPieceParams::ForSize(size_mm);
    if (name != "iso10791_m1") n.m1_size_mm = size_mm;
  } else if (name == "iso10791_m2") {
    n.config.params = FaceMillingPieceParams{};
  } else if (name == "cone_frustum") {
    n.config.params = ConeFrustumParams{};
  } else if (name == "cone_frustum_enriched") {
    // samples/testpieces/cone_frustum_enriched.yaml
    ConeFrustumParams p;
    p.name = "NAS 979 cone frustum, enriched (cones 130 mm along +X and +Y, 48 points per section)";
    p.base_size_mm = 380;
    p.second_cone_offset_mm = 130;
    p.third_cone_offset_mm = 130;
    n.config.params = p;
    n.config.probing.points_per_circle = 48;
  } else {
    return Status(StatusCode::kInvalidArgument,
                  "unknown test piece '" + std::string(name) + "' (expected one of: " + PieceNameList() + ")");
  }
  n.usual_machine = UsualMachine(n.config);
  return n;
}

Status CheckConfigMatchesName(const PieceConfig& config, const NamedPiece& named, std::string_view name,
                              const std::string& source) {
  const PieceKind have = KindOf(config.params), want = KindOf(named.config.params);
  if (have != want)
    return Status(StatusCode::kInvalidArgument,
                  std::string("piece: the configuration is for the ") + PieceKindName(have) +
                      " piece, but --testpiece is " + std::string(name),
                  source);
  if (const auto* m1 = std::get_if<ContourPieceParams>(&config.params);
      m1 != nullptr && named.m1_size_mm > 0 && m1->size_mm != named.m1_size_mm)
    return Status(StatusCode::kInvalidArgument,
                  "iso10791_m1.size_mm: the configuration is an M1 of size " + Mm(m1->size_mm) +
                      " mm, but --testpiece is " + std::string(name),
                  source);
  return {};
}

}  // namespace tpcal::testpieces
