#include "testpieces/default_parameters.h"

#include "kinematics/error_parameters.h"

namespace tpcal::testpieces {

std::vector<std::string> DefaultParameterSet(const TestPiece& piece, const kinematics::MachineModel& machine) {
  // The turning piece: seed 002's Table 2 set, plus the squareness of X to Y, which the paper
  // leaves out but every machine has: the groove S_R (and S_RI) is milled by X-Y circular
  // interpolation, so E_C(0X)Y makes it elliptic (2nd harmonic at 45 deg, gamma r / 2: 1.2 um for
  // 20 urad on S_R). Without it that ellipse was left in the gap and named an unmodelled effect.
  if (piece.kind() == PieceKind::kTurning && machine.type == kinematics::MachineType::kAcTable) {
    std::vector<std::string> set = kinematics::Seed002Set(machine);
    set.push_back("E_C(0X)Y");
    return set;
  }
  // M2's strips are cut by X feeds at constant Z and datum on themselves: location and
  // squareness errors only tilt or shift them (absorbed by the datum), while the straightness of
  // X in Z bends them: its quadratic and cubic terms (offset and slope are the datum's).
  if (piece.kind() == PieceKind::kFaceMillingM2 && machine.HasAxis(kinematics::Axis::kX) &&
      machine.HasAxis(kinematics::Axis::kZ))
    return {"E_ZX.c2", "E_ZX.c3"};
  return kinematics::IsoLocationSet(machine);
}

}  // namespace tpcal::testpieces
