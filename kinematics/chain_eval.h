// The kinematic chain templated on the scalar type (double, ceres::Jet, ...), for automatic
// differentiation through the exact homogeneous transforms of conventions.h. Eigen only; the
// caller brings the Jet type (e.g. a ceres::AutoDiffCostFunction functor in identification).
//
//   ToolPointInPartT<T>(model, errors, active, x, axes, contact): tool point in the part frame
//   where the active coefficients take the values x[0..active.size()) (internal units) and all
//   other coefficients their values in `errors`. At x = current values it equals
//   ToolPointInPart() bit for bit up to rounding; its derivative in x is exact.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "kinematics/conventions.h"
#include "kinematics/error_state.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// Rigid transform x_parent = R x_child + t over scalar T.
template <typename T>
struct PoseT {
  Eigen::Matrix<T, 3, 3> R = Eigen::Matrix<T, 3, 3>::Identity();
  Eigen::Matrix<T, 3, 1> t = Eigen::Matrix<T, 3, 1>::Zero();

  PoseT operator*(const PoseT& b) const { return PoseT{R * b.R, R * b.t + t}; }
  Eigen::Matrix<T, 3, 1> operator*(const Eigen::Matrix<T, 3, 1>& p) const { return R * p + t; }
  PoseT inverse() const {
    PoseT out;
    out.R = R.transpose();
    out.t = -(out.R * t);
    return out;
  }
};

template <typename T>
using LinkErrorsT = std::array<T, kNumComponents>;

// Up to one link per axis.
inline constexpr int kMaxLinks = kNumAxes;

namespace chain_internal {

// RotX(rx) * RotY(ry) * RotZ(rz).
template <typename T>
Eigen::Matrix<T, 3, 3> RotXYZ(const T& rx, const T& ry, const T& rz) {
  using std::cos;
  using std::sin;
  const T cx = cos(rx), sx = sin(rx), cy = cos(ry), sy = sin(ry), cz = cos(rz), sz = sin(rz);
  Eigen::Matrix<T, 3, 3> m;
  m(0, 0) = cy * cz;                 m(0, 1) = -cy * sz;                m(0, 2) = sy;
  m(1, 0) = sx * sy * cz + cx * sz;  m(1, 1) = -sx * sy * sz + cx * cz; m(1, 2) = -sx * cy;
  m(2, 0) = -cx * sy * cz + sx * sz; m(2, 1) = cx * sy * sz + sx * cz;  m(2, 2) = cx * cy;
  return m;
}

// True when all three are exactly zero, for double only: a Jet with a zero value may still carry
// derivatives, so it is never skipped.
template <typename T>
bool AllZero(const T& a, const T& b, const T& c) {
  if constexpr (std::is_same_v<T, double>) {
    return a == 0.0 && b == 0.0 && c == 0.0;
  } else {
    return false;
  }
}

// Rotation by `angle` about coordinate axis `dir` (0 = x, 1 = y, 2 = z).
template <typename T>
Eigen::Matrix<T, 3, 3> RotAxis(int dir, const T& angle) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  Eigen::Matrix<T, 3, 3> m = Eigen::Matrix<T, 3, 3>::Identity();
  const int i = (dir + 1) % 3, j = (dir + 2) % 3;
  m(i, i) = c;
  m(i, j) = -s;
  m(j, i) = s;
  m(j, j) = c;
  return m;
}

}  // namespace chain_internal

// parent_from_child of one link (conventions.h chain formula). `e` has kNumComponents entries.
template <typename T>
PoseT<T> LinkTransform(const AxisLink& link, const T* e, const T& q) {
  using chain_internal::AllZero;
  using chain_internal::RotAxis;
  using chain_internal::RotXYZ;
  const int dir = AxisIndex(link.axis) % 3;
  const Eigen::Matrix<T, 3, 1> p = link.pivot_mm.cast<T>();
  const T sq = T(link.motion_sign()) * q;
  const Eigen::Matrix<T, 3, 1> e_t(e[0], e[1], e[2]);
  const bool has_r = !AllZero(e[3], e[4], e[5]);
  PoseT<T> out;
  if (IsRotary(link.axis)) {
    // G = T(l_t) R(l_r) Rot_a(sq) R(l_r)^-1 T(-l_t)
    Eigen::Matrix<T, 3, 3> rg = RotAxis(dir, sq);
    const Eigen::Matrix<T, 3, 1> l_t(e[6], e[7], e[8]);
    if (!AllZero(e[9], e[10], e[11])) {
      const Eigen::Matrix<T, 3, 3> rl = RotXYZ(e[9], e[10], e[11]);
      rg = rl * rg * rl.transpose();
    }
    const Eigen::Matrix<T, 3, 1> t_g = l_t - rg * l_t;
    // L = T(p) T(e_t) R(e_r) G T(-p)
    if (has_r) {
      const Eigen::Matrix<T, 3, 3> re = RotXYZ(e[3], e[4], e[5]);
      out.R = re * rg;
      out.t = p + e_t + re * t_g - out.R * p;
    } else {
      out.R = rg;
      out.t = p + e_t + t_g - rg * p;
    }
  } else {
    // L = T(p) T(sq R(l_r) a) T(e_t) R(e_r) T(-p)
    Eigen::Matrix<T, 3, 1> a = Eigen::Matrix<T, 3, 1>::Zero();
    a(dir) = T(1.0);
    if (!AllZero(e[9], e[10], e[11])) a = RotXYZ(e[9], e[10], e[11]) * a;
    const Eigen::Matrix<T, 3, 1> v = sq * a;
    if (has_r) {
      out.R = RotXYZ(e[3], e[4], e[5]);
      out.t = p + v + e_t - out.R * p;
    } else {
      out.t = v + e_t;
    }
  }
  return out;
}

// machine_from_part and machine_from_tool: products over each branch. `q` holds the six axis
// positions (mm, rad) indexed by AxisIndex; `e[link]` the error components of each link.
template <typename T>
void BranchPosesT(const MachineModel& model, const LinkErrorsT<T>* e, const T* q,
                  PoseT<T>* machine_from_part, PoseT<T>* machine_from_tool) {
  PoseT<T> w, tool;
  for (int i = 0; i < model.num_links(); ++i) {
    const AxisLink& link = model.links[i];
    const PoseT<T> l = LinkTransform<T>(link, e[i].data(), q[AxisIndex(link.axis)]);
    if (i < model.num_workpiece_links) {
      w = w * l;
    } else {
      tool = tool * l;
    }
  }
  *machine_from_part = w;
  *machine_from_tool = tool;
}

template <typename T>
PoseT<T> PartFromToolT(const MachineModel& model, const LinkErrorsT<T>* e, const T* q) {
  PoseT<T> w, tool;
  BranchPosesT<T>(model, e, q, &w, &tool);
  return w.inverse() * tool;
}

// Scratch for ToolPointInPartT (reuse to avoid allocation).
struct ChainScratch {
  std::vector<LinkErrors> link_errors;
  std::vector<double> basis;
  std::vector<double> weights;
};

// part_from_tool with the active coefficients at x (see the file comment). `active` must index
// coefficients of `errors`.
template <typename T>
PoseT<T> PartFromToolT(const MachineModel& model, const ErrorState& errors,
                       const ActiveSet& active, const T* x, const AxisState& axes,
                       ChainScratch* scratch) {
  EvaluateLinkErrors(errors, axes, &scratch->link_errors, &scratch->basis);
  std::array<LinkErrorsT<T>, kMaxLinks> e;
  for (int l = 0; l < model.num_links(); ++l) {
    for (int c = 0; c < kNumComponents; ++c) e[l][c] = T(scratch->link_errors[l][c]);
  }
  int weights_term = -1;
  for (int j = 0; j < active.size(); ++j) {
    const int i = active.coefficients[j];
    const CoefficientInfo& info = errors.coefficient_info(i);
    const ErrorTerm& term = errors.terms()[info.term];
    if (info.term != weights_term) {
      EvaluateTermBasis(term, axes, &scratch->weights);
      weights_term = info.term;
    }
    const double w = scratch->weights[info.index];
    if (w == 0.0) continue;
    const T delta = (x[j] - T(errors.coefficient(i))) * T(w);
    for (const SlotEffect& s : term.effects) {
      const int l = errors.LinkIndex(s.axis);
      e[l][ComponentIndex(s.component)] += T(s.gain) * delta;
    }
  }
  const std::array<T, kNumAxes> q = {T(axes.x_mm),  T(axes.y_mm),  T(axes.z_mm),
                                     T(axes.a_rad), T(axes.b_rad), T(axes.c_rad)};
  return PartFromToolT<T>(model, e.data(), q.data());
}

// The tool point `contact_in_tool_mm` in the part frame, active coefficients at x.
template <typename T>
Eigen::Matrix<T, 3, 1> ToolPointInPartT(const MachineModel& model, const ErrorState& errors,
                                        const ActiveSet& active, const T* x,
                                        const AxisState& axes,
                                        const Eigen::Vector3d& contact_in_tool_mm,
                                        ChainScratch* scratch) {
  return PartFromToolT<T>(model, errors, active, x, axes, scratch) *
         Eigen::Matrix<T, 3, 1>(contact_in_tool_mm.cast<T>());
}

}  // namespace tpcal::kinematics
