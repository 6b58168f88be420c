#include "kinematics/simulate.h"

#include <ceres/jet.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "kinematics/chain_eval.h"
#include "kinematics/internal/memo_chain.h"
#include "kinematics/jacobians.h"

namespace tpcal::kinematics {

namespace {

using Jet2 = ceres::Jet<double, 2>;

Eigen::Vector3d ContactAt(const CutPoint& cut, double u, double v) {
  return cut.contact_in_tool_mm + u * cut.du.contact_in_tool_mm + v * cut.dv.contact_in_tool_mm;
}

AxisState AxesAt(const CutPoint& cut, double u, double v) {
  return Advance(Advance(cut.axes, cut.du.axes, u), cut.dv.axes, v);
}

// S(u, v) (double).
Eigen::Vector3d SurfaceAt(const MachineModel& model, const ErrorState& errors, const CutPoint& cut,
                          double u, double v, Workspace* ws) {
  return ToolPointInPart(model, errors, AxesAt(cut, u, v), ContactAt(cut, u, v), ws);
}

// S(u, v) and its tangents S_u, S_v by forward-mode differentiation through the chain. With
// `error_slopes`, the error terms enter through their values and their slopes along the two
// sweeps (central differences of the evaluated link errors, step 1e-6 of the sweep parameter);
// without, through their values only: the slopes (um per mm at most) then only slow the
// quasi-Newton iteration a little, the residual being always exact.
Eigen::Vector3d SurfaceAndTangents(const MachineModel& model, const ErrorState& errors,
                                   const CutPoint& cut, double u, double v, bool error_slopes,
                                   Workspace* ws, Eigen::Vector3d* S_u, Eigen::Vector3d* S_v) {
  const AxisState axes = AxesAt(cut, u, v);
  EvaluateLinkErrors(errors, axes, &ws->link_errors);
  std::array<LinkErrorsT<Jet2>, kMaxLinks> e;
  for (int l = 0; l < model.num_links(); ++l) {
    for (int c = 0; c < kNumComponents; ++c) e[l][c] = Jet2(ws->link_errors[l][c]);
  }
  if (error_slopes && !errors.dynamic_terms().empty()) {
    constexpr double h = 1e-6;
    std::vector<LinkErrors> plus, minus;
    for (int k = 0; k < 2; ++k) {
      const double du = k == 0 ? h : 0.0, dv = k == 1 ? h : 0.0;
      EvaluateLinkErrors(errors, AxesAt(cut, u + du, v + dv), &plus);
      EvaluateLinkErrors(errors, AxesAt(cut, u - du, v - dv), &minus);
      for (int l = 0; l < model.num_links(); ++l) {
        for (int c = 0; c < kNumComponents; ++c) e[l][c].v[k] = (plus[l][c] - minus[l][c]) / (2 * h);
      }
    }
  }
  const Jet2 du(0.0, 0), dv(0.0, 1);
  const double q0[kNumAxes] = {axes.x_mm, axes.y_mm, axes.z_mm, axes.a_rad, axes.b_rad, axes.c_rad};
  std::array<Jet2, kNumAxes> q;
  for (int i = 0; i < kNumAxes; ++i) {
    const Axis a = AxisFromIndex(i);
    q[i] = Jet2(q0[i]) + du * Increment(cut.du.axes, a) + dv * Increment(cut.dv.axes, a);
  }
  const Eigen::Vector3d c0 = ContactAt(cut, u, v);
  Eigen::Matrix<Jet2, 3, 1> c;
  for (int r = 0; r < 3; ++r) {
    c(r) = Jet2(c0(r)) + du * cut.du.contact_in_tool_mm(r) + dv * cut.dv.contact_in_tool_mm(r);
  }
  const PoseT<Jet2> pose = PartFromToolT<Jet2>(model, e.data(), q.data());
  const Eigen::Matrix<Jet2, 3, 1> s = pose * c;
  Eigen::Vector3d out;
  for (int r = 0; r < 3; ++r) {
    out(r) = s(r).a;
    (*S_u)(r) = s(r).v[0];
    (*S_v)(r) = s(r).v[1];
  }
  return out;
}

// Axes a term's value depends on (bit AxisIndex); time and operation do not change along a sweep.
unsigned TermAxisMask(const ErrorTerm& t) {
  unsigned m = 0;
  if (t.condition.axis) m |= 1u << AxisIndex(*t.condition.axis);
  if (t.kind == TermKind::kPolynomial || t.kind == TermKind::kFourier || t.kind == TermKind::kTable) {
    m |= 1u << AxisIndex(t.argument);
    if (t.second_argument) m |= 1u << AxisIndex(*t.second_argument);
  }
  return m;
}

// The error terms of one solve, split into those that the sweeps cannot change (evaluated once at
// the cut state, exactly) and those that depend on a swept axis (re-evaluated at each iterate).
struct SweepErrors {
  std::vector<LinkErrors> base;
  std::vector<int> varying;

  void Prepare(const ErrorState& errors, const CutPoint& cut) {
    unsigned swept = 0;
    for (int i = 0; i < kNumAxes; ++i) {
      const Axis a = AxisFromIndex(i);
      if (Increment(cut.du.axes, a) != 0.0 || Increment(cut.dv.axes, a) != 0.0) swept |= 1u << i;
    }
    base = errors.static_errors();
    varying.clear();
    for (int ti : errors.dynamic_terms()) {
      const ErrorTerm& t = errors.terms()[ti];
      if (TermAxisMask(t) & swept) {
        varying.push_back(ti);
        continue;
      }
      Add(errors, t, TermValue(t, cut.axes), &base);
    }
  }
  static void Add(const ErrorState& errors, const ErrorTerm& t, double value, std::vector<LinkErrors>* e) {
    if (value == 0.0) return;
    for (const SlotEffect& s : t.effects) {
      (*e)[errors.LinkIndex(s.axis)][ComponentIndex(s.component)] += s.gain * value;
    }
  }
  void Evaluate(const ErrorState& errors, const AxisState& axes, std::vector<LinkErrors>* e) const {
    *e = base;
    for (int ti : varying) {
      const ErrorTerm& t = errors.terms()[ti];
      Add(errors, t, TermValue(t, axes), e);
    }
  }
};

// S(u, v) in double; with S_u / S_v non-null also the sweep tangents, from the actual motion
// axes of the links (screw velocities: w x (m - o) for a rotary axis, its direction for a
// linear one; minus for the workpiece branch). The error terms' own slopes along the sweep are
// not included (they only slow the quasi-Newton iteration; the residual is exact).
Eigen::Vector3d SurfaceFast(const MachineModel& model, const ErrorState& errors,
                            const SweepErrors& sweep, const CutPoint& cut, double u, double v,
                            Workspace* ws, Eigen::Vector3d* S_u, Eigen::Vector3d* S_v) {
  const AxisState axes = AxesAt(cut, u, v);
  sweep.Evaluate(errors, axes, &ws->link_errors);
  const Eigen::Vector3d contact = ContactAt(cut, u, v);
  PoseT<double> w, t;
  if (!S_u) {
    internal::MemoBranchPoses(model, ws->link_errors, axes, ws, &w, &t, nullptr);
    return w.R.transpose() * (t * contact - w.t);
  }
  std::array<LinkAxisT<double>, kMaxLinks> ax;
  internal::MemoBranchPoses(model, ws->link_errors, axes, ws, &w, &t, ax.data());
  const Eigen::Vector3d m = t * contact;
  Eigen::Vector3d vu = t.R * cut.du.contact_in_tool_mm, vv = t.R * cut.dv.contact_in_tool_mm;
  for (int i = 0; i < model.num_links(); ++i) {
    const Axis a = model.links[i].axis;
    const double iu = Increment(cut.du.axes, a), iv = Increment(cut.dv.axes, a);
    if (iu == 0.0 && iv == 0.0) continue;
    const Eigen::Vector3d vel =
        IsRotary(a) ? Eigen::Vector3d(ax[i].direction.cross(m - ax[i].point)) : ax[i].direction;
    const double sign = i < model.num_workpiece_links ? -1.0 : 1.0;
    vu += sign * iu * vel;
    vv += sign * iv * vel;
  }
  *S_u = w.R.transpose() * vu;
  *S_v = w.R.transpose() * vv;
  return w.R.transpose() * (m - w.t);
}

Status CheckCut(const CutPoint& cut) {
  const double n = cut.nominal_normal.norm();
  if (!(std::abs(n - 1.0) < 1e-9)) {
    return Status(StatusCode::kInvalidArgument, "cut point: nominal normal is not a unit vector");
  }
  if (!cut.nominal_point_mm.allFinite() || !cut.contact_in_tool_mm.allFinite()) {
    return Status(StatusCode::kInvalidArgument, "cut point: non-finite point or contact");
  }
  return Status::Ok();
}

// [S_u S_v -n0] and whether it is well conditioned (columns normalised).
bool SweepMatrix(const Eigen::Vector3d& S_u, const Eigen::Vector3d& S_v, const Eigen::Vector3d& n0,
                 Eigen::Matrix3d* J) {
  J->col(0) = S_u;
  J->col(1) = S_v;
  J->col(2) = -n0;
  const double nu = S_u.norm(), nv = S_v.norm();
  if (!(nu > 0.0) || !(nv > 0.0)) return false;
  const double det = std::abs(J->determinant()) / (nu * nv);
  return det > 1e-9;
}

// Why the iteration stopped short: the last step, the rounding level of the chain at the last
// iterate (2^-52 x the largest coordinate or link error translation, mm) and the largest link
// errors. When a tenth of the tolerance is below that rounding level the steps are rounding
// noise: the errors are far outside the small-error range (km: not a machine), the iteration is
// not slow.
std::string NotConvergedMessage(const MachineModel& model, const ErrorState& errors, const CutPoint& cut,
                                const SimulateOptions& options, double u, double v, double step_mm,
                                Workspace* ws) {
  EvaluateLinkErrors(errors, AxesAt(cut, u, v), &ws->link_errors);
  double max_mm = 0.0, max_rad = 0.0;
  for (int l = 0; l < model.num_links(); ++l) {
    for (int c = 0; c < kNumComponents; ++c) {
      const double e = std::abs(ws->link_errors[l][c]);
      if (IsAngular(static_cast<Component>(c))) {
        max_rad = std::max(max_rad, e);
      } else {
        max_mm = std::max(max_mm, e);
      }
    }
  }
  const Eigen::Vector3d S = SurfaceAt(model, errors, cut, u, v, ws);
  const double scale_mm = std::max({S.norm(), cut.nominal_point_mm.norm(), max_mm});
  const double rounding_mm = std::numeric_limits<double>::epsilon() * scale_mm;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "surface point did not converge in %d iterations (last step %.3g mm, tolerance %.3g mm, rounding "
                "level of the chain %.3g mm; largest link error %.3g mm, %.3g rad: %s)",
                options.max_iterations, step_mm, options.tolerance_mm, rounding_mm, max_mm, max_rad,
                10.0 * rounding_mm > options.tolerance_mm
                    ? "the tolerance is below the rounding of coordinates this large: errors far outside the small-error range"
                    : "errors too large for the sweep, or a sweep tangent to the probing line");
  return buf;
}

}  // namespace

Status SimulateOptions::Validate() const {
  if (max_iterations < 1) return Status(StatusCode::kInvalidArgument, "max_iterations must be >= 1");
  if (!(tolerance_mm > 0.0)) return Status(StatusCode::kInvalidArgument, "tolerance_mm must be > 0");
  return Status::Ok();
}

Result<SurfacePoint> SimulateSurfacePoint(const MachineModel& model, const ErrorState& errors,
                                          const CutPoint& cut, Workspace* ws,
                                          const SimulateOptions& options) {
  TPCAL_RETURN_IF_ERROR(CheckCut(cut));
  const Eigen::Vector3d& p0 = cut.nominal_point_mm;
  const Eigen::Vector3d& n0 = cut.nominal_normal;
  double u = 0.0, v = 0.0, s = 0.0;
  SweepErrors sweep;
  sweep.Prepare(errors, cut);
  Eigen::Vector3d S_u, S_v;
  Eigen::Vector3d S = SurfaceFast(model, errors, sweep, cut, u, v, ws, &S_u, &S_v);
  Eigen::Matrix3d J;
  if (!SweepMatrix(S_u, S_v, n0, &J)) {
    return Status(StatusCode::kDegenerate,
                  "cut point: the sweep directions and the normal do not span space");
  }
  // Newton iteration with the tangents of each iterate. First without the error terms' own
  // slopes along the sweep (SurfaceFast): the rate is then |error slope| / |net sweep speed|,
  // ~1e-5 per step for um-size errors, the residual being exact. In simultaneous five-axis
  // motion the net tangent can be a small difference of large axis motions (cone flank: C table
  // ~140 mm/rad at the point, X -93 mm/rad, net 34 mm/rad), so a rotary error whose slope is
  // small against one axis's motion (E_CC of 40 mrad at order 3: 0.1 rad/rad) is not small
  // against the net speed (rate 0.3 per step, 20 iterations not enough). When a step contracts
  // by less than kSlowContraction, the tangents include the error slopes from then on
  // (SurfaceAndTangents: Newton proper). Converged when the last step, or the next one
  // predicted from the observed contraction (step_k^2 / step_{k-1}), is below the tolerance.
  constexpr double kSlowContraction = 1e-2;
  SurfacePoint out;
  double last_step_mm = std::numeric_limits<double>::infinity();
  double step_mm = std::numeric_limits<double>::infinity();
  bool error_slopes = false;
  for (int it = 1; it <= options.max_iterations; ++it) {
    const Eigen::Vector3d F = S - p0 - s * n0;
    const Eigen::Vector3d step = -(J.inverse() * F);
    u += step(0);
    v += step(1);
    s += step(2);
    step_mm = std::abs(step(0)) * S_u.norm() + std::abs(step(1)) * S_v.norm() + std::abs(step(2));
    const bool contracting = std::isfinite(last_step_mm) && step_mm < kSlowContraction * last_step_mm;
    if (step_mm <= options.tolerance_mm ||
        (contracting && step_mm * (step_mm / last_step_mm) <= options.tolerance_mm)) {
      out.deviation_mm = s;
      out.point_mm = p0 + s * n0;
      out.u = u;
      out.v = v;
      out.iterations = it;
      return out;
    }
    if (std::isfinite(last_step_mm) && !contracting) error_slopes = true;
    last_step_mm = step_mm;
    if (error_slopes) {  // the residual stays SurfaceFast's, the tangents gain the error slopes
      S = SurfaceFast(model, errors, sweep, cut, u, v, ws, nullptr, nullptr);
      SurfaceAndTangents(model, errors, cut, u, v, true, ws, &S_u, &S_v);
    } else {
      S = SurfaceFast(model, errors, sweep, cut, u, v, ws, &S_u, &S_v);
    }
    if (!SweepMatrix(S_u, S_v, n0, &J)) {
      return Status(StatusCode::kDegenerate,
                    "cut point: the sweep became tangent to the probing line during the solve");
    }
  }
  return Status(StatusCode::kNotConverged, NotConvergedMessage(model, errors, cut, options, u, v, step_mm, ws));
}

SurfacePoint SimulateSurfacePointFirstOrder(const MachineModel& model, const ErrorState& errors,
                                            const CutPoint& cut, Workspace* ws) {
  const Eigen::Vector3d S = SurfaceAt(model, errors, cut, 0.0, 0.0, ws);
  SurfacePoint out;
  out.deviation_mm = cut.nominal_normal.dot(S - cut.nominal_point_mm);
  out.point_mm = cut.nominal_point_mm + out.deviation_mm * cut.nominal_normal;
  out.iterations = 0;
  return out;
}

double CutPointMismatch(const MachineModel& model, const CutPoint& cut) {
  return (NominalToolPointInPart(model, cut.axes, cut.contact_in_tool_mm) - cut.nominal_point_mm)
      .norm();
}

Status SimulateSurfacePoints(const MachineModel& model, const ErrorState& errors,
                             const std::vector<CutPoint>& cuts, std::vector<SurfacePoint>* out,
                             const SimulateOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  out->clear();
  out->reserve(cuts.size());
  Workspace ws;
  for (size_t i = 0; i < cuts.size(); ++i) {
    Result<SurfacePoint> r = SimulateSurfacePoint(model, errors, cuts[i], &ws, options);
    if (!r.ok()) return r.status().WithContext("cut point " + std::to_string(i));
    out->push_back(*r);
  }
  return Status::Ok();
}

// r = -e3^T [S_u S_v -n0]^-1 at the exact solution `solved`: d s = r dS (implicit function theorem).
static Result<Eigen::RowVector3d> DeviationRow(const MachineModel& model, const ErrorState& errors,
                                               const CutPoint& cut, const SurfacePoint& solved) {
  TPCAL_RETURN_IF_ERROR(CheckCut(cut));
  Workspace ws;
  Eigen::Vector3d S_u, S_v;
  SurfaceAndTangents(model, errors, cut, solved.u, solved.v, true, &ws, &S_u, &S_v);
  Eigen::Matrix3d J;
  if (!SweepMatrix(S_u, S_v, cut.nominal_normal, &J)) {
    return Status(StatusCode::kDegenerate,
                  "cut point: the sweep directions and the normal do not span space");
  }
  return Eigen::RowVector3d(-J.inverse().row(2));
}

Result<Eigen::RowVectorXd> SurfaceDeviationJacobian(const MachineModel& model,
                                                   const ErrorState& errors,
                                                   const ActiveSet& active, const CutPoint& cut,
                                                   const SurfacePoint& solved) {
  auto r = DeviationRow(model, errors, cut, solved);
  if (!r.ok()) return r.status();
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_point;
  ToolPointJacobian(model, errors, active, AxesAt(cut, solved.u, solved.v),
                    ContactAt(cut, solved.u, solved.v), &J_point);
  return Eigen::RowVectorXd(*r * J_point);
}

Result<Eigen::RowVectorXd> SurfaceDeviationSlotJacobian(const MachineModel& model, const ErrorState& errors,
                                                       std::span<const ErrorSlot> slots, const CutPoint& cut,
                                                       const SurfacePoint& solved) {
  auto r = DeviationRow(model, errors, cut, solved);
  if (!r.ok()) return r.status();
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_point;
  ToolPointSlotJacobian(model, errors, AxesAt(cut, solved.u, solved.v), ContactAt(cut, solved.u, solved.v), slots,
                        &J_point);
  return Eigen::RowVectorXd(*r * J_point);
}

}  // namespace tpcal::kinematics
