#include "kinematics/error_map_separation.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "kinematics/internal/scaled_solve.h"
#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics {
namespace {

constexpr double kSepDeg = 180.0 / std::numbers::pi;
constexpr char kSepDirections[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};

std::vector<double> SepRadians(const std::vector<double>& deg) {
  std::vector<double> r;
  for (double d : deg) r.push_back(d / kSepDeg);
  return r;
}

ErrorTerm SepTable(Axis axis, int direction, const std::vector<double>& a_deg, const std::vector<double>& c_deg) {
  ErrorTerm t;
  t.kind = TermKind::kTable;
  t.label = std::string("E_") + kSepDirections[direction] + AxisLetter(axis);
  t.quantity = direction < 3 ? Quantity::kLength : Quantity::kAngle;
  t.effects = {SlotEffect{axis, static_cast<Component>(direction), 1.0}};
  t.argument = axis;
  if (axis == Axis::kA) {
    t.nodes = SepRadians(a_deg);
  } else {
    t.nodes = SepRadians(c_deg);
    t.periodic = true;
    t.second_argument = Axis::kA;
    t.second_nodes = SepRadians(a_deg);
  }
  t.coefficients.assign(t.ExpectedCoefficients(), 0.0);
  return t;
}

std::string SepDeg(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

Result<ErrorState> ZeroErrorMaps(const MachineModel& model, const std::vector<double>& a_deg,
                                 const std::vector<double>& c_deg) {
  if (model.type != MachineType::kAcTable) {
    return Status(StatusCode::kInvalidArgument, "error maps of the rotary axes need an A/C table (ac_table)");
  }
  if (a_deg.size() < 2 || c_deg.size() < 2) {
    return Status(StatusCode::kInvalidArgument,
                  "error maps need at least 2 A and 2 C positions (got " + std::to_string(a_deg.size()) +
                      " A, " + std::to_string(c_deg.size()) + " C)");
  }
  ErrorState maps(model);
  for (Axis axis : {Axis::kA, Axis::kC}) {
    for (int d = 0; d < 6; ++d) TPCAL_RETURN_IF_ERROR(maps.AddTerm(model, SepTable(axis, d, a_deg, c_deg)));
  }
  return maps;
}

Result<ErrorMaps> SeparateTablePoses(const MachineModel& model, const TablePoseFit& fit, int dof) {
  Result<ErrorState> zero = ZeroErrorMaps(model, fit.a_deg, fit.c_deg);
  TPCAL_RETURN_IF_ERROR(zero);
  const int np = static_cast<int>(fit.poses.size());
  if (fit.covariance.rows() != 6 * np || fit.covariance.cols() != 6 * np) {
    return Status(StatusCode::kInvalidArgument, "pose covariance has the wrong size");
  }
  ErrorMaps out(*zero);
  out.a_deg = fit.a_deg;
  out.c_deg = fit.c_deg;
  ErrorState& maps = out.maps;
  const int ne = maps.num_coefficients();
  const int na = static_cast<int>(fit.a_deg.size()), nc = static_cast<int>(fit.c_deg.size());
  // G: d(pose)/d(entry), display units per display unit, by central differences on the chain.
  Eigen::MatrixXd g(6 * np, ne);
  for (int e = 0; e < ne; ++e) {
    const double h = 1e-6;
    const double per = maps.coefficient_info(e).display_per_internal;
    for (int p = 0; p < np; ++p) {
      AxisState s;
      s.a_rad = fit.poses[p].a_deg / kSepDeg;
      s.c_rad = fit.poses[p].c_deg / kSepDeg;
      maps.set_coefficient(e, h);
      const Vector6d plus = AbsoluteTablePoseError(model, maps, s);
      maps.set_coefficient(e, -h);
      const Vector6d minus = AbsoluteTablePoseError(model, maps, s);
      g.block<6, 1>(6 * p, e) = (plus - minus) / (2.0 * h * per);
    }
    maps.set_coefficient(e, 0.0);
  }
  // Rows: determined pose components (data), the reference pose (= 0), zero mean of C maps.
  std::vector<int> data_rows;
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 6; ++c) {
      if (fit.poses[p].identifiable[c]) data_rows.push_back(6 * p + c);
    }
  }
  const int nz = 6 * na;
  const int nr = static_cast<int>(data_rows.size()) + nz;
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(nr, ne);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nr);
  Eigen::MatrixXd rhs_cov_map = Eigen::MatrixXd::Zero(nr, 6 * np);  // rhs = this * pose values
  for (std::size_t r = 0; r < data_rows.size(); ++r) {
    s.row(r) = g.row(data_rows[r]);
    const TablePose& pose = fit.poses[data_rows[r] / 6];
    rhs(r) = pose.reference ? 0.0 : pose.value(data_rows[r] % 6);
    if (!pose.reference) rhs_cov_map(r, data_rows[r]) = 1.0;
  }
  // C maps are terms 6..11; their coefficient index is j * nc + i for C node i, A node j. The mean
  // is over the C positions probed at that A (a position without touches stays undetermined
  // alone instead of leaving the whole row of its A without numbers).
  std::vector<bool> probed(na * nc, false);
  for (const TablePose& p : fit.poses) {
    for (int j = 0; j < na; ++j)
      for (int i = 0; i < nc; ++i)
        if (std::abs(fit.a_deg[j] - p.a_deg) < 1e-9 && std::abs(fit.c_deg[i] - p.c_deg) < 1e-9) probed[j * nc + i] = true;
  }
  int first_c = 0;
  while (first_c < ne && maps.coefficient_info(first_c).term < 6) ++first_c;
  for (int d = 0; d < 6; ++d) {
    for (int j = 0; j < na; ++j) {
      const int row = static_cast<int>(data_rows.size()) + d * na + j;
      for (int i = 0; i < nc; ++i) {
        if (probed[j * nc + i]) s(row, first_c + d * na * nc + j * nc + i) = 1.0;
      }
    }
  }
  // entries = m * rhs (the minimum-norm solution in scaled columns).
  const internal::ScaledSolve solve = internal::SolveScaled(s);
  const Eigen::MatrixXd& m = solve.m;
  const Eigen::VectorXd values = m * rhs;
  const Eigen::MatrixXd mp = m * rhs_cov_map;
  out.covariance = mp * fit.covariance * mp.transpose();
  const double k95 = dof > 0 ? internal::StudentTQuantile975(dof) : 1.959963984540054;
  for (int e = 0; e < ne; ++e) {
    const CoefficientInfo& info = maps.coefficient_info(e);
    const ErrorTerm& term = maps.terms()[info.term];
    ErrorMapEntry x;
    x.symbol = term.label;
    x.coefficient = info.name;
    x.unit = info.unit;
    x.c_map = term.argument == Axis::kC;
    const int i = info.index % static_cast<int>(term.nodes.size());
    const int j = info.index / static_cast<int>(term.nodes.size());
    x.a_deg = x.c_map ? fit.a_deg[j] : fit.a_deg[i];
    x.c_deg = x.c_map ? fit.c_deg[i] : 0.0;
    x.identifiable = solve.Determined(e);
    if (x.identifiable) {
      x.value = values(e);
      x.u = std::sqrt(std::max(0.0, out.covariance(e, e)));
      x.ci95_low = x.value - k95 * x.u;
      x.ci95_high = x.value + k95 * x.u;
      maps.set_coefficient(e, x.value / info.display_per_internal);
    } else {
      out.covariance.row(e).setZero();
      out.covariance.col(e).setZero();
      out.not_identifiable.push_back(x.symbol + "(A " + SepDeg(x.a_deg) +
                                     (x.c_map ? ", C " + SepDeg(x.c_deg) : std::string()) + ")");
    }
    out.entries.push_back(std::move(x));
  }
  double ref_a = 0.0, ref_c = 0.0;
  for (const TablePose& p : fit.poses) {
    if (p.reference) ref_a = p.a_deg, ref_c = p.c_deg;
  }
  out.conventions = {
      "every map is relative to the table's pose at the reference position (A " + SepDeg(ref_a) + " deg, C " +
          SepDeg(ref_c) + " deg), which is zero by definition: a "
          "constant pose of the table cannot be told from the artifacts' placement on it",
      "zero-mean constraint (seed 000 eq. 1): at every A the C-axis maps average to zero over C; their "
          "constant part (e.g. a C-axis translation along the C axis at one A) is reported in the A-axis maps",
  };
  return out;
}

}  // namespace tpcal::kinematics
