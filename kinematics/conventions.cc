#include "kinematics/conventions.h"

namespace tpcal::kinematics {

const char* ComponentName(Component c) {
  static const char* const kNames[kNumComponents] = {"Tx",     "Ty",     "Tz",     "Rx",
                                                     "Ry",     "Rz",     "LineTx", "LineTy",
                                                     "LineTz", "LineRx", "LineRy", "LineRz"};
  return kNames[ComponentIndex(c)];
}

}  // namespace tpcal::kinematics
