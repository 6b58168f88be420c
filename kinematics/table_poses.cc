#include "kinematics/table_poses.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "kinematics/forward_kinematics.h"
#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics {
namespace {

constexpr double kPoseDeg = 180.0 / std::numbers::pi;

double PoseWrapC(double c_deg) {
  double c = std::fmod(c_deg, 360.0);
  if (c < 0.0) c += 360.0;
  return c >= 360.0 - 1e-9 ? 0.0 : c;
}

AxisState PoseRotary(double a_deg, double c_deg) {
  AxisState s;
  s.a_rad = a_deg / kPoseDeg;
  s.c_rad = c_deg / kPoseDeg;
  return s;
}

Vector6d PoseVee(const Rigid3& d) {
  const Eigen::Matrix3d w = 0.5 * (d.linear() - d.linear().transpose());
  Vector6d v;
  v << d.translation() * 1e3, Eigen::Vector3d(w(2, 1), w(0, 2), w(1, 0)) * 1e6;
  return v;
}

// Index of `v` in the sorted distinct values `grid` (within tol), or -1.
int PoseGridIndex(const std::vector<double>& grid, double v, double tol) {
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (std::abs(grid[i] - v) <= tol) return static_cast<int>(i);
  }
  return -1;
}

void PoseAddDistinct(std::vector<double>* grid, double v, double tol) {
  if (PoseGridIndex(*grid, v, tol) < 0) grid->push_back(v);
}

Status PoseTouchError(const ProbeTouch& t, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, what, {}, t.line);
}

Status CheckPoseTouches(const ArtifactSet& artifacts, std::span<const ProbeTouch> touches) {
  const bool any_u = std::any_of(touches.begin(), touches.end(), [](const ProbeTouch& t) { return t.u_um > 0.0; });
  for (const ProbeTouch& t : touches) {
    if (t.artifact < 0 || t.artifact >= static_cast<int>(artifacts.boxes.size())) {
      return PoseTouchError(t, "artifact index out of range");
    }
    if (!t.contact_mm.allFinite() || !t.approach.allFinite() || std::abs(t.approach.norm() - 1.0) > 1e-6) {
      return PoseTouchError(t, "contact point not finite or approach not a unit vector");
    }
    if (!std::isfinite(t.u_um) || t.u_um < 0.0 || (any_u && t.u_um == 0.0)) {
      return PoseTouchError(t, "u_um must be > 0 for every touch or for none");
    }
  }
  return Status::Ok();
}

// d(probe centre in the part frame)/d(linear-axis error `c`) at touch `t`'s linear command (its
// contact minus radius x approach), mm per rad, by central differences on the exact chain.
Eigen::Vector3d PoseLinearColumn(const MachineModel& model, ErrorState* e, int c, const ProbeTouch& t,
                                 double radius_mm) {
  AxisState s = t.rotary;
  const Eigen::Vector3d command = t.contact_mm - radius_mm * t.approach;
  s.x_mm = command.x(), s.y_mm = command.y(), s.z_mm = command.z();
  const double h = 1e-6;
  Workspace ws;
  e->set_coefficient(c, h);
  const Eigen::Vector3d plus = ToolPointInPart(model, *e, s, Eigen::Vector3d::Zero(), &ws);
  e->set_coefficient(c, -h);
  const Eigen::Vector3d minus = ToolPointInPart(model, *e, s, Eigen::Vector3d::Zero(), &ws);
  e->set_coefficient(c, 0.0);
  return (plus - minus) / (2.0 * h);
}

// The fit with the linear axes error-free, its linear errors named and not identifiable.
Result<TablePoseFit> PoseWithoutLinearErrors(const MachineModel& model, const ArtifactSet& artifacts,
                                             std::span<const ProbeTouch> touches, const TablePoseOptions& options) {
  TablePoseOptions without = options;
  without.linear_errors.clear();
  auto fit = FitTablePoses(model, artifacts, touches, without);
  if (!fit.ok()) return fit;
  ErrorState linear(model);
  auto active = ActivateParameters(model, &linear, options.linear_errors);
  for (std::size_t l = 0; l < options.linear_errors.size(); ++l) {
    ParameterEstimate e;
    e.name = options.linear_errors[l];
    e.unit = active.ok() ? linear.coefficient_info(active->coefficients[l]).unit : "";
    fit->linear_errors.push_back(std::move(e));
  }
  return fit;
}

}  // namespace

Vector6d AbsoluteTablePoseError(const MachineModel& model, const ErrorState& errors, const AxisState& rotary) {
  Workspace ws;
  const AxisState s = PoseRotary(rotary.a_rad * kPoseDeg, rotary.c_rad * kPoseDeg);
  const Rigid3 actual = MachineFromPart(model, errors, s, &ws);
  return PoseVee(actual * NominalMachineFromTable(model, s).inverse());
}

Vector6d TablePoseError(const MachineModel& model, const ErrorState& errors, const AxisState& rotary,
                        const AxisState& reference) {
  Workspace ws;
  const Rigid3 t_p = MachineFromPart(model, errors, rotary, &ws);
  const Rigid3 t_ref = MachineFromPart(model, errors, reference, &ws);
  return PoseVee(t_p * t_ref.inverse() * NominalMachineFromTable(model, reference) *
                 NominalMachineFromTable(model, rotary).inverse());
}

Result<TablePoseFit> FitTablePoses(const MachineModel& model, const ArtifactSet& artifacts,
                                   std::span<const ProbeTouch> touches, const TablePoseOptions& options) {
  TPCAL_RETURN_IF_ERROR(CheckPoseTouches(artifacts, touches));
  const double tol = options.position_tolerance_deg;
  TablePoseFit fit;
  for (const ProbeTouch& t : touches) {
    PoseAddDistinct(&fit.a_deg, t.rotary.a_rad * kPoseDeg, tol);
    PoseAddDistinct(&fit.c_deg, PoseWrapC(t.rotary.c_rad * kPoseDeg), tol);
  }
  std::sort(fit.a_deg.begin(), fit.a_deg.end());
  std::sort(fit.c_deg.begin(), fit.c_deg.end());
  // Poses (A-major) and faces that have touches, and each touch's pose and face.
  const int na = static_cast<int>(fit.a_deg.size()), nc = static_cast<int>(fit.c_deg.size());
  std::vector<int> pose_of_cell(na * nc, -1), touch_pose(touches.size()), touch_face(touches.size());
  std::map<std::pair<int, int>, int> face_index;
  for (std::size_t k = 0; k < touches.size(); ++k) {
    const int i = PoseGridIndex(fit.a_deg, touches[k].rotary.a_rad * kPoseDeg, tol);
    const int j = PoseGridIndex(fit.c_deg, PoseWrapC(touches[k].rotary.c_rad * kPoseDeg), tol);
    pose_of_cell[i * nc + j] = 0;
    face_index[{touches[k].artifact, static_cast<int>(touches[k].face)}] = 0;
  }
  for (int cell = 0; cell < na * nc; ++cell) {
    if (pose_of_cell[cell] < 0) continue;
    pose_of_cell[cell] = static_cast<int>(fit.poses.size());
    TablePose p;
    p.a_deg = fit.a_deg[cell / nc];
    p.c_deg = fit.c_deg[cell % nc];
    p.reference = std::abs(p.a_deg - options.reference_a_deg) <= tol &&
                  std::abs(p.c_deg - PoseWrapC(options.reference_c_deg)) <= tol;
    fit.poses.push_back(p);
  }
  const auto ref = std::find_if(fit.poses.begin(), fit.poses.end(), [](const TablePose& p) { return p.reference; });
  if (ref == fit.poses.end()) {
    return Status(StatusCode::kInvalidArgument,
                  "the reference position (A " + std::to_string(options.reference_a_deg) + " deg, C " +
                      std::to_string(options.reference_c_deg) + " deg) has no touches");
  }
  int nf = 0;
  for (auto& [key, index] : face_index) {
    index = nf++;
    FaceOffsetEstimate f;
    f.artifact = key.first;
    f.face = static_cast<BoxFace>(key.second);
    fit.faces.push_back(f);
  }
  const int np = static_cast<int>(fit.poses.size());
  const int ref_index = static_cast<int>(ref - fit.poses.begin());
  ErrorState linear(model);
  auto linear_active = ActivateParameters(model, &linear, options.linear_errors);
  if (!linear_active.ok()) return linear_active.status();
  const int nl = linear_active->size();
  // Columns: 6 per pose (the reference's stay zero), one per face, one per linear-axis error.
  const int nx = 6 * np + nf + nl, n = static_cast<int>(touches.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, nx);
  Eigen::VectorXd y(n), w = Eigen::VectorXd::Ones(n);
  for (int k = 0; k < n; ++k) {
    const ProbeTouch& t = touches[k];
    const int i = PoseGridIndex(fit.a_deg, t.rotary.a_rad * kPoseDeg, tol);
    const int j = PoseGridIndex(fit.c_deg, PoseWrapC(t.rotary.c_rad * kPoseDeg), tol);
    const int p = pose_of_cell[i * nc + j];
    touch_pose[k] = p;
    touch_face[k] = face_index[{t.artifact, static_cast<int>(t.face)}];
    ++fit.poses[p].touches;
    ++fit.faces[touch_face[k]].touches;
    const FaceGeometry g = FaceOf(artifacts.boxes[t.artifact], t.face);
    const Rigid3 t0 = NominalMachineFromTable(model, PoseRotary(fit.poses[p].a_deg, fit.poses[p].c_deg));
    const Eigen::Vector3d nm = t0.linear() * g.normal;
    y(k) = 1e3 * (g.normal.dot(t0.inverse() * t.contact_mm) - g.offset_mm());
    if (p != ref_index) {
      a.block<1, 3>(k, 6 * p) = nm.transpose();
      a.block<1, 3>(k, 6 * p + 3) = 1e-3 * t.contact_mm.cross(nm).transpose();
    }
    a(k, 6 * np + touch_face[k]) = 1.0;
    for (int l = 0; l < nl; ++l) {  // um per display unit of the error (urad for squareness)
      const int c = linear_active->coefficients[l];
      a(k, 6 * np + nf + l) = -1e3 / linear.coefficient_info(c).display_per_internal *
                              g.normal.dot(PoseLinearColumn(model, &linear, c, t, options.probe_radius_mm));
    }
    if (t.u_um > 0.0) w(k) = 1.0 / t.u_um;
  }
  fit.weighted = touches.size() > 0 && touches[0].u_um > 0.0;
  fit.num_touches = n;
  // Scaled, weighted SVD; zero columns (the reference pose) are left out by their zero scale.
  Eigen::VectorXd scale(nx);
  for (int c = 0; c < nx; ++c) {
    const double norm = (w.asDiagonal() * a.col(c)).norm();
    scale(c) = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  const Eigen::MatrixXd as = w.asDiagonal() * a * scale.asDiagonal();
  Eigen::BDCSVD<Eigen::MatrixXd> svd(as, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double cut = options.rank_tolerance * (sv.size() ? sv(0) : 0.0);
  int rank = 0;
  while (rank < sv.size() && sv(rank) > cut) ++rank;
  fit.rank = rank;
  fit.dof = n - rank;
  if (fit.dof <= 0 && nl > 0) return PoseWithoutLinearErrors(model, artifacts, touches, options);
  if (fit.dof <= 0) {
    return Status(StatusCode::kTooFewPoints, std::to_string(n) + " touches determine only " +
                                                 std::to_string(rank) + " pose and face unknowns");
  }
  const Eigen::MatrixXd v = svd.matrixV().leftCols(rank);
  const Eigen::VectorXd inv_s = sv.head(rank).cwiseInverse();
  const Eigen::VectorXd xs = v * inv_s.asDiagonal() * svd.matrixU().leftCols(rank).transpose() * (w.asDiagonal() * y);
  const Eigen::VectorXd x = scale.asDiagonal() * xs;
  const Eigen::VectorXd r = y - a * x;
  fit.residuals_um.assign(r.data(), r.data() + n);
  fit.sigma_um = std::sqrt(r.squaredNorm() / fit.dof);
  const double s2 = fit.weighted ? (w.asDiagonal() * r).squaredNorm() / fit.dof : fit.sigma_um * fit.sigma_um;
  if (fit.weighted) fit.chi_scale = std::sqrt(s2);
  const Eigen::MatrixXd vs = scale.asDiagonal() * v * inv_s.asDiagonal();
  const Eigen::MatrixXd cov = s2 * vs * vs.transpose();
  // A column is determined when its unit vector lies in the row space: |V_r^T e_c| = 1.
  auto determined = [&](int c) { return scale(c) > 0.0 && std::abs(v.row(c).squaredNorm() - 1.0) < 1e-6; };
  fit.covariance = Eigen::MatrixXd::Zero(6 * np, 6 * np);
  std::vector<int> keep;
  for (int c = 0; c < 6 * np; ++c) {
    if (determined(c)) keep.push_back(c);
  }
  for (int c1 : keep) {
    for (int c2 : keep) fit.covariance(c1, c2) = cov(c1, c2);
  }
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 6; ++c) {
      const bool ok = p == ref_index || determined(6 * p + c);
      fit.poses[p].identifiable[c] = ok;
      fit.poses[p].value(c) = ok && p != ref_index ? x(6 * p + c) : 0.0;
    }
  }
  for (int f = 0; f < nf; ++f) {
    const int c = 6 * np + f;
    fit.faces[f].identifiable = determined(c);
    fit.faces[f].value_um = fit.faces[f].identifiable ? x(c) : 0.0;
    fit.faces[f].u_um = fit.faces[f].identifiable ? std::sqrt(cov(c, c)) : 0.0;
  }
  for (int l = 0; l < nl; ++l) {
    const int c = 6 * np + nf + l;
    if (!determined(c)) return PoseWithoutLinearErrors(model, artifacts, touches, options);
    ParameterEstimate e;
    e.name = options.linear_errors[l];
    e.unit = linear.coefficient_info(linear_active->coefficients[l]).unit;
    e.identifiable = true;
    e.value = x(c);
    e.u = std::sqrt(cov(c, c));
    e.ci95_low = e.value - internal::StudentTQuantile975(fit.dof) * e.u;  // as the maps' (t, the fit's dof)
    e.ci95_high = e.value + internal::StudentTQuantile975(fit.dof) * e.u;
    fit.linear_errors.push_back(std::move(e));
  }
  return fit;
}

}  // namespace tpcal::kinematics
