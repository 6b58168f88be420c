#include "kinematics/map_location_equivalent.h"

#include <cmath>

#include "kinematics/internal/scaled_solve.h"
#include "kinematics/probe_artifacts.h"
#include "kinematics/table_poses.h"

namespace tpcal::kinematics {
namespace {

constexpr double kMeStep = 1e-6;  // central-difference step, internal units (mm, rad)

// The grid of the maps' 2-D C table over A: its positions, A-major.
Result<std::vector<AxisState>> MeGrid(const ErrorState& maps) {
  for (const ErrorTerm& t : maps.terms()) {
    if (t.kind != TermKind::kTable || t.argument != Axis::kC || t.second_argument != Axis::kA) continue;
    std::vector<AxisState> grid;
    for (double a : t.second_nodes)
      for (double c : t.nodes) {
        AxisState s;
        s.a_rad = a, s.c_rad = c;
        grid.push_back(s);
      }
    return grid;
  }
  return Status(StatusCode::kInvalidArgument, "the maps have no 2-D table of C over A: no grid of table poses");
}

// The coefficients whose basis is non-zero at `s` (they move the table's pose there).
std::vector<int> MeMovers(const ErrorState& maps, const AxisState& s) {
  std::vector<int> out;
  std::vector<double> w;
  int first = 0;
  for (const ErrorTerm& t : maps.terms()) {
    EvaluateTermBasis(t, s, &w);
    for (std::size_t k = 0; k < w.size(); ++k)
      if (w[k] != 0.0) out.push_back(first + static_cast<int>(k));
    first += static_cast<int>(t.coefficients.size());
  }
  return out;
}

// d(pose at s)/d(coefficient c), per display unit of c, by central differences.
Vector6d MeColumn(const MachineModel& model, ErrorState* e, int c, const AxisState& s) {
  const double v = e->coefficient(c), per = e->coefficient_info(c).display_per_internal;
  e->set_coefficient(c, v + kMeStep);
  const Vector6d plus = AbsoluteTablePoseError(model, *e, s);
  e->set_coefficient(c, v - kMeStep);
  const Vector6d minus = AbsoluteTablePoseError(model, *e, s);
  e->set_coefficient(c, v);
  return (plus - minus) / (2.0 * kMeStep * per);
}

Status MeCheckInput(const ErrorState& maps, const MapEquivalentInput& in) {
  const Eigen::Index n = maps.num_coefficients();
  if (in.covariance.size() > 0 && (in.covariance.rows() != n || in.covariance.cols() != n))
    return Status(StatusCode::kInvalidArgument, "the maps' covariance has the wrong size");
  if (!in.u.empty() && static_cast<Eigen::Index>(in.u.size()) != n)
    return Status(StatusCode::kInvalidArgument, "the maps' u have the wrong size");
  if (!in.determined.empty() && static_cast<Eigen::Index>(in.determined.size()) != n)
    return Status(StatusCode::kInvalidArgument, "the maps' determined flags have the wrong size");
  return Status::Ok();
}

// The machine-frame pose (um, urad) of a small constant motion of the table in its own frame
// (translation um, rotation urad about the table origin): the adjoint of the nominal
// machine_from_table at `s`. The maps are relative to the table's pose at a reference position,
// i.e. up to such a motion (the artifacts' placement on the table).
Matrix6d MeTableFrameMotion(const MachineModel& model, const AxisState& s) {
  const Rigid3 t0 = NominalMachineFromTable(model, s);
  const Eigen::Matrix3d r = t0.linear();
  const Eigen::Vector3d o = t0.translation();  // mm
  Eigen::Matrix3d o_cross;
  o_cross << 0.0, -o.z(), o.y(), o.z(), 0.0, -o.x(), -o.y(), o.x(), 0.0;
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = 1e-3 * o_cross * r;  // urad x mm = 1e-3 um
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

// The linear problem: y (poses of the maps at the used positions), gy = dy/d(map entries),
// h = dy/d(parameters, then the 6 columns of a constant table-frame motion).
struct MeSystem {
  Eigen::VectorXd y;
  Eigen::MatrixXd gy, h;
  int positions = 0;
};

Result<MeSystem> MeBuild(const MachineModel& model, const ErrorState& maps, const std::vector<AxisState>& grid,
                         const MapEquivalentInput& in, ErrorState* params, const ActiveSet& act) {
  std::vector<AxisState> used;
  std::vector<std::vector<int>> movers;
  for (const AxisState& s : grid) {
    std::vector<int> m = MeMovers(maps, s);
    bool ok = true;
    for (int c : m)
      ok = ok && (in.determined.empty() || in.determined[c] ||
                  maps.terms()[maps.coefficient_info(c).term].kind != TermKind::kTable);
    if (ok) used.push_back(s), movers.push_back(std::move(m));
  }
  if (used.empty())
    return Status(StatusCode::kTooFewPoints, "no grid position of the maps has every entry determined");
  const int np = static_cast<int>(used.size()), nk = act.size();
  MeSystem sys;
  sys.positions = np;
  sys.y.resize(6 * np);
  sys.gy = Eigen::MatrixXd::Zero(6 * np, maps.num_coefficients());
  sys.h = Eigen::MatrixXd::Zero(6 * np, nk + 6);
  ErrorState e = maps;
  for (int p = 0; p < np; ++p) {
    sys.y.segment<6>(6 * p) = AbsoluteTablePoseError(model, maps, used[p]);
    for (int c : movers[p]) sys.gy.block<6, 1>(6 * p, c) = MeColumn(model, &e, c, used[p]);
    for (int k = 0; k < nk; ++k) sys.h.block<6, 1>(6 * p, k) = MeColumn(model, params, act.coefficients[k], used[p]);
    sys.h.block<6, 6>(6 * p, nk) = MeTableFrameMotion(model, used[p]);
  }
  return sys;
}

double MeRms(const Eigen::VectorXd& r, int first) {
  double s = 0.0;
  int n = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (i % 6 >= first && i % 6 < first + 3) s += r(i) * r(i), ++n;
  return n > 0 ? std::sqrt(s / n) : 0.0;
}

}  // namespace

Result<MapEquivalent> ParameterEquivalentOfMaps(const MachineModel& model, const ErrorState& maps,
                                                const std::vector<std::string>& names,
                                                const MapEquivalentInput& in) {
  if (model.type != MachineType::kAcTable)
    return Status(StatusCode::kInvalidArgument, "a parameter equivalent of error maps needs an A/C table (ac_table)");
  TPCAL_RETURN_IF_ERROR(MeCheckInput(maps, in));
  auto grid = MeGrid(maps);
  if (!grid.ok()) return grid.status();
  ErrorState params(model);
  auto act = ActivateParameters(model, &params, names);
  if (!act.ok()) return act.status();
  auto sys = MeBuild(model, maps, *grid, in, &params, *act);
  if (!sys.ok()) return sys.status();
  const int nk = act->size();
  // A column below 1e-12 (um or urad per unit) is a parameter that moves no table pose.
  const internal::ScaledSolve solve = internal::SolveScaled(sys->h, 1e-9, 1e-12);
  const Eigen::MatrixXd& m = solve.m;
  const Eigen::VectorXd x = m * sys->y;
  const Eigen::MatrixXd a = m.topRows(nk) * sys->gy;  // parameters per map entry
  MapEquivalent out;
  out.positions = sys->positions;
  out.u_known = in.covariance.size() > 0 || !in.u.empty();
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(nk, nk);
  if (in.covariance.size() > 0) {
    cov = a * in.covariance * a.transpose();
  } else if (!in.u.empty()) {
    const Eigen::Map<const Eigen::VectorXd> u(in.u.data(), static_cast<Eigen::Index>(in.u.size()));
    cov = a * u.array().square().matrix().asDiagonal() * a.transpose();
  }
  const Eigen::VectorXd r = sys->y - sys->h * x;
  out.residual_rms_um = MeRms(r, 0), out.residual_rms_urad = MeRms(r, 3);
  for (int k = 0; k < nk; ++k) {
    const CoefficientInfo& info = params.coefficient_info(act->coefficients[k]);
    ParameterEstimate p;
    p.name = names[k];
    p.unit = info.unit;
    if (auto catalog = LookupParameter(model, names[k]); catalog.ok()) p.iso_symbol = catalog->iso_symbol;
    p.identifiable = solve.Determined(k);
    if (p.identifiable) {
      p.value = x(k);
      p.u = std::sqrt(std::max(0.0, cov(k, k)));
      p.ci95_low = p.value - 1.959963984540054 * p.u;
      p.ci95_high = p.value + 1.959963984540054 * p.u;
    }
    out.parameters.push_back(std::move(p));
  }
  return out;
}

}  // namespace tpcal::kinematics
