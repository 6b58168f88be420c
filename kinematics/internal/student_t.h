// Student t quantiles for coverage intervals (Boost.Math, a Debian header package already
// pulled in by PCL; kept out of public headers).
#pragma once

namespace tpcal::kinematics::internal {

// The 0.975 quantile of Student's t with nu > 0 degrees of freedom (k of a 95 % two-sided
// interval); nu = inf gives 1.959964. nu may be fractional.
double StudentTQuantile975(double nu);

}  // namespace tpcal::kinematics::internal
