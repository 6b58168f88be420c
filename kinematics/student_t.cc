#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics::internal {

double StudentTQuantile975(double nu) {
  if (!(nu > 0.0) || !std::isfinite(nu) || nu > 1e7) return 1.959963984540054;
  return boost::math::quantile(boost::math::students_t_distribution<double>(nu), 0.975);
}

}  // namespace tpcal::kinematics::internal
