// The kinematic chain templated on the scalar type (double, ceres::Jet, ...), for automatic
// differentiation through the exact homogeneous transforms of conventions.h. Eigen only; the
// caller brings the Jet type (e.g. a ceres::AutoDiffCostFunction functor in identification).
//
//   ToolPointInPartT<T>(model, errors, active, x, axes, contact): tool point in the part frame
//   where the active coefficients take the values x[0..active.size()) (internal units) and all
//   other coefficients their values in `errors`. At x = current values it equals
//   ToolPointInPart() to rounding (1e-10 mm, tested); its derivative in x is exact.
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

// sin and cos; for double error angles below 1e-2 rad by their Taylor series to the 9th/8th
// power, exact to double precision (remainder < 3e-22 relative) and several times faster.
template <typename T>
[[gnu::always_inline]] inline void SinCos(const T& a, T* s, T* c) {
  using std::abs;
  using std::cos;
  using std::sin;
  if constexpr (std::is_same_v<T, double>) {
    if (abs(a) < 1e-2) {
      const double a2 = a * a;
      *s = a * (1.0 - a2 / 6.0 * (1.0 - a2 / 20.0 * (1.0 - a2 / 42.0 * (1.0 - a2 / 72.0))));
      *c = 1.0 - a2 / 2.0 * (1.0 - a2 / 12.0 * (1.0 - a2 / 30.0 * (1.0 - a2 / 56.0)));
      return;
    }
  }
  *s = sin(a);
  *c = cos(a);
}

// RotX(rx) * RotY(ry) * RotZ(rz).
template <typename T>
Eigen::Matrix<T, 3, 3> RotXYZ(const T& rx, const T& ry, const T& rz) {
  T cx, sx, cy, sy, cz, sz;
  SinCos(rx, &sx, &cx);
  SinCos(ry, &sy, &cy);
  SinCos(rz, &sz, &cz);
  Eigen::Matrix<T, 3, 3> m;
  m(0, 0) = cy * cz;                 m(0, 1) = -cy * sz;                m(0, 2) = sy;
  m(1, 0) = sx * sy * cz + cx * sz;  m(1, 1) = -sx * sy * sz + cx * cz; m(1, 2) = -sx * cy;
  m(2, 0) = -cx * sy * cz + sx * sz; m(2, 1) = cx * sy * sz + sx * cz;  m(2, 2) = cx * cy;
  return m;
}

// Rotation by angle `a` about the unit axis k (Rodrigues): c I + s [k]x + (1 - c) k k^T.
template <typename T>
Eigen::Matrix<T, 3, 3> Rodrigues(const Eigen::Matrix<T, 3, 1>& k, const T& a) {
  T s, c;
  SinCos(a, &s, &c);
  const T one_c = T(1.0) - c;
  Eigen::Matrix<T, 3, 3> rg;
  rg(0, 0) = c + one_c * k(0) * k(0);
  rg(1, 1) = c + one_c * k(1) * k(1);
  rg(2, 2) = c + one_c * k(2) * k(2);
  rg(0, 1) = one_c * k(0) * k(1) - s * k(2);
  rg(1, 0) = one_c * k(0) * k(1) + s * k(2);
  rg(0, 2) = one_c * k(0) * k(2) + s * k(1);
  rg(2, 0) = one_c * k(0) * k(2) - s * k(1);
  rg(1, 2) = one_c * k(1) * k(2) - s * k(0);
  rg(2, 1) = one_c * k(1) * k(2) + s * k(0);
  return rg;
}

// True when `a` is exactly zero: a double equal to 0, or a Jet (members `a` and `v`) whose value
// and every derivative part are 0. Then it contributes nothing to a value or a derivative, and a
// rotation by it may be skipped exactly.
template <typename T>
[[gnu::always_inline]] inline bool IsExactZero(const T& a) {
  if constexpr (std::is_arithmetic_v<T>) {
    return a == 0.0;
  } else {
    return a.a == 0.0 && (a.v.array() == 0.0).all();
  }
}

// True when `a` carries no derivative (always for double).
template <typename T>
[[gnu::always_inline]] inline bool IsConstant(const T& a) {
  if constexpr (std::is_arithmetic_v<T>) {
    return true;
  } else {
    return (a.v.array() == 0.0).all();
  }
}

// The value of `a` (a itself for double).
template <typename T>
[[gnu::always_inline]] inline double ValueOf(const T& a) {
  if constexpr (std::is_arithmetic_v<T>) {
    return a;
  } else {
    return a.a;
  }
}

// True when all three are exactly zero (IsExactZero): the rotation RotXYZ(a, b, c) is then the
// identity with no derivative, and skipping it is exact for double and Jet alike.
template <typename T>
bool AllZero(const T& a, const T& b, const T& c) {
  return IsExactZero(a) && IsExactZero(b) && IsExactZero(c);
}

}  // namespace chain_internal

// The motion axis of a link in its parent frame, after the link's errors: unit direction
// (before the motion sign) and, for a rotary axis, a point of the actual axis line.
template <typename T>
struct LinkAxisT {
  Eigen::Matrix<T, 3, 1> direction;
  Eigen::Matrix<T, 3, 1> point;
};

// parent_from_child of one link (conventions.h chain formula). `e` has kNumComponents entries.
// Optionally returns the actual motion axis in the parent frame (for sweep tangents).
template <typename T>
PoseT<T> LinkTransform(const AxisLink& link, const T* e, const T& q, LinkAxisT<T>* axis = nullptr) {
  using chain_internal::AllZero;
  using chain_internal::IsConstant;
  using chain_internal::Rodrigues;
  using chain_internal::RotXYZ;
  using chain_internal::ValueOf;
  const int dir = AxisIndex(link.axis) % 3;
  const Eigen::Matrix<T, 3, 1> p = link.pivot_mm.cast<T>();
  const T sq = T(link.motion_sign()) * q;
  const Eigen::Matrix<T, 3, 1> e_t(e[0], e[1], e[2]);
  const bool has_r = !AllZero(e[3], e[4], e[5]);
  // k = R(l_r) a: the (tilted) axis / travel direction before the pose error.
  Eigen::Matrix<T, 3, 1> k = Eigen::Matrix<T, 3, 1>::Zero();
  const bool tilted = !AllZero(e[9], e[10], e[11]);
  if (!tilted) {
    k(dir) = T(1.0);
  } else {
    k = RotXYZ(e[9], e[10], e[11]).col(dir);
  }
  PoseT<T> out;
  if (IsRotary(link.axis)) {
    // G = T(l_t) R(l_r) Rot_a(sq) R(l_r)^-1 T(-l_t) = rotation by sq about the line (l_t, k):
    // Rodrigues, R_g = c I + s [k]x + (1 - c) k k^T.
    const Eigen::Matrix<T, 3, 1> l_t(e[6], e[7], e[8]);
    // L = T(p) T(e_t) R(e_r) G T(-p). `rg` is a double matrix when it carries no derivative, and
    // the pivot is a constant: a Jet times a double costs half a Jet times a Jet, same bits.
    const auto finish = [&](const auto& rg) {
      const Eigen::Matrix<T, 3, 1> t_g = l_t - rg * l_t;
      if (has_r) {
        const Eigen::Matrix<T, 3, 3> re = RotXYZ(e[3], e[4], e[5]);
        out.R = re * rg;
        out.t = p + e_t + re * t_g - out.R * link.pivot_mm;
        if (axis) {
          axis->direction = re * k;
          axis->point = p + e_t + re * l_t;
        }
      } else {
        out.R = rg.template cast<T>();
        out.t = p + e_t + t_g - rg * link.pivot_mm;
        if (axis) {
          axis->direction = k;
          axis->point = p + e_t + l_t;
        }
      }
    };
    if constexpr (!std::is_arithmetic_v<T>) {
      if (!tilted && IsConstant(sq)) {
        // Neither the axis nor the angle carries a derivative: the same formula in double.
        finish(Rodrigues(Eigen::Vector3d(Eigen::Vector3d::Unit(dir)), ValueOf(sq)));
      } else {
        finish(Rodrigues(k, sq));
      }
    } else {
      finish(Rodrigues(k, sq));
    }
  } else {
    // L = T(p) T(sq R(l_r) a) T(e_t) R(e_r) T(-p)
    const Eigen::Matrix<T, 3, 1> v = sq * k;
    if (has_r) {
      out.R = RotXYZ(e[3], e[4], e[5]);
      out.t = p + v + e_t - out.R * link.pivot_mm;
    } else {
      out.t = v + e_t;
    }
    if (axis) {
      axis->direction = k;
      axis->point = p;
    }
  }
  return out;
}

// machine_from_part and machine_from_tool: products over each branch. `q` holds the six axis
// positions (mm, rad) indexed by AxisIndex; `e[link]` the error components of each link.
// Optionally returns each link's actual motion axis in the MACHINE frame (`axes_out`,
// num_links() entries): direction (times the motion sign: the velocity direction of a unit
// command) and a point of the line.
template <typename T>
void BranchPosesT(const MachineModel& model, const LinkErrorsT<T>* e, const T* q,
                  PoseT<T>* machine_from_part, PoseT<T>* machine_from_tool,
                  LinkAxisT<T>* axes_out = nullptr) {
  using chain_internal::AllZero;
  PoseT<T> w, tool;
  for (int i = 0; i < model.num_links(); ++i) {
    const AxisLink& link = model.links[i];
    const T* ei = e[i].data();
    PoseT<T>& acc = i < model.num_workpiece_links ? w : tool;
    if (!axes_out && !IsRotary(link.axis) && AllZero(ei[3], ei[4], ei[5])) {
      // A linear link without pose rotation is a pure translation (exact shortcut; for a Jet when
      // the rotation components have zero value and no derivative).
      const int dir = AxisIndex(link.axis);
      Eigen::Matrix<T, 3, 1> v(ei[0], ei[1], ei[2]);
      const T sq = T(link.motion_sign()) * q[dir];
      if (AllZero(ei[9], ei[10], ei[11])) {
        v(dir) += sq;
      } else {
        v += sq * chain_internal::RotXYZ(ei[9], ei[10], ei[11]).col(dir);
      }
      acc.t += acc.R * v;
      continue;
    }
    if (axes_out) {
      LinkAxisT<T> a;
      const PoseT<T> l = LinkTransform<T>(link, ei, q[AxisIndex(link.axis)], &a);
      axes_out[i].direction = T(link.motion_sign()) * (acc.R * a.direction);
      axes_out[i].point = acc * a.point;
      acc = acc * l;
    } else {
      acc = acc * LinkTransform<T>(link, ei, q[AxisIndex(link.axis)]);
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
  std::vector<double> weights;
};

// The link errors and axis positions of the chain with the active coefficients at x (see the
// file comment). `active` must index coefficients of `errors`. A component that no active
// coefficient moves at `axes` carries no derivative.
template <typename T>
void ChainInputsT(const MachineModel& model, const ErrorState& errors, const ActiveSet& active,
                  const T* x, const AxisState& axes, ChainScratch* scratch,
                  std::array<LinkErrorsT<T>, kMaxLinks>* e, std::array<T, kNumAxes>* q) {
  EvaluateLinkErrors(errors, axes, &scratch->link_errors);
  for (int l = 0; l < model.num_links(); ++l) {
    for (int c = 0; c < kNumComponents; ++c) (*e)[l][c] = T(scratch->link_errors[l][c]);
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
      (*e)[l][ComponentIndex(s.component)] += T(s.gain) * delta;
    }
  }
  *q = {T(axes.x_mm), T(axes.y_mm), T(axes.z_mm), T(axes.a_rad), T(axes.b_rad), T(axes.c_rad)};
}

// part_from_tool with the active coefficients at x (see the file comment). `active` must index
// coefficients of `errors`.
template <typename T>
PoseT<T> PartFromToolT(const MachineModel& model, const ErrorState& errors,
                       const ActiveSet& active, const T* x, const AxisState& axes,
                       ChainScratch* scratch) {
  std::array<LinkErrorsT<T>, kMaxLinks> e;
  std::array<T, kNumAxes> q;
  ChainInputsT<T>(model, errors, active, x, axes, scratch, &e, &q);
  return PartFromToolT<T>(model, e.data(), q.data());
}

// The tool point `contact_in_tool_mm` in the part frame, active coefficients at x:
// R_w^T (R_t c + t_t - t_w), as ToolPointInPart (without forming part_from_tool).
template <typename T>
Eigen::Matrix<T, 3, 1> ToolPointInPartT(const MachineModel& model, const ErrorState& errors,
                                        const ActiveSet& active, const T* x,
                                        const AxisState& axes,
                                        const Eigen::Vector3d& contact_in_tool_mm,
                                        ChainScratch* scratch) {
  std::array<LinkErrorsT<T>, kMaxLinks> e;
  std::array<T, kNumAxes> q;
  ChainInputsT<T>(model, errors, active, x, axes, scratch, &e, &q);
  PoseT<T> w, tool;
  BranchPosesT<T>(model, e.data(), q.data(), &w, &tool);
  return w.R.transpose() * (tool.R * contact_in_tool_mm + tool.t - w.t);
}

}  // namespace tpcal::kinematics
