#include "kinematics/jacobians.h"

#include <ceres/jet.h>

#include <Eigen/Geometry>
#include <bitset>
#include <vector>

#include "kinematics/chain_eval.h"

namespace tpcal::kinematics {

namespace {

constexpr int kChunk = 8;
using Jet = ceres::Jet<double, kChunk>;

// Seeds derivative slots for active entries [begin, begin + N).
template <int N>
std::vector<ceres::Jet<double, N>> Seed(const ErrorState& errors, const ActiveSet& active, int begin) {
  std::vector<ceres::Jet<double, N>> x(active.size());
  for (int j = 0; j < active.size(); ++j) {
    x[j] = ceres::Jet<double, N>(errors.coefficient(active.coefficients[j]));
    if (j >= begin && j < begin + N) x[j].v[j - begin] = 1.0;
  }
  return x;
}

using ComponentMask = std::bitset<kNumComponents>;

Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

// d RotXYZ(a, b, c) / d a, b, c for RotXYZ = Rx(a) Ry(b) Rz(c): [x] R, Rx [y] Ry Rz, R [z].
std::array<Eigen::Matrix3d, 3> RotXYZPartials(double a, double b, double c) {
  using chain_internal::RotXYZ;
  const Eigen::Matrix3d Rx = RotXYZ(a, 0.0, 0.0), Ry = RotXYZ(0.0, b, 0.0), Rz = RotXYZ(0.0, 0.0, c);
  const Eigen::Matrix3d R = Rx * Ry * Rz;
  return {Skew(Eigen::Vector3d::UnitX()) * R, Rx * Skew(Eigen::Vector3d::UnitY()) * Ry * Rz,
          R * Skew(Eigen::Vector3d::UnitZ())};
}

// G (3 x kNumComponents, columns outside `mask` zero): d(L(e) u) / d e, the derivative of the
// link transform L (parent_from_child, R_L its rotation) applied to the fixed point u (parent
// frame of the link) in its error components, in closed form from the chain formula of
// LinkTransform (chain_eval.h). With R_e = RotXYZ(e_r) and k = RotXYZ(l_r) a the (tilted) axis:
//   rotary: L u = p + e_t + R_e (l_t + R_g(k, s q) m), m = u - p - l_t, R_g Rodrigues;
//   linear: L u = p + s q k + e_t + R_e (u - p).
// So d/d e_t = I; d/d l_t = R_e - R_L (rotary); d/d e_r = (d R_e) w with w the vector R_e acts
// on; d/d l_r = (d/d k)(d k / d l_r) with d(R_g m)/d k_i = sin e_i x m + (1 - cos)(e_i k.m + k m_i)
// (rotary, times R_e) or s q I (linear). Exact (the same derivative as forward-mode
// differentiation of LinkTransform, tested through the whole chain).
void LinkPointDerivative(const AxisLink& link, const LinkErrors& e, double q, const Eigen::Matrix3d& R_L,
                         ComponentMask mask, const Eigen::Vector3d& u, Eigen::Matrix<double, 3, kNumComponents>* G) {
  using chain_internal::RotXYZ;
  G->setZero();
  for (int c = 0; c < 3; ++c)
    if (mask[static_cast<std::size_t>(c)]) (*G)(c, c) = 1.0;
  const bool rotary = IsRotary(link.axis);
  const bool need_r = mask[3] || mask[4] || mask[5];
  const bool need_l_r = mask[9] || mask[10] || mask[11];
  const bool need_l_t = rotary && (mask[6] || mask[7] || mask[8]);
  if (!need_r && !need_l_r && !need_l_t) return;
  const bool has_r = e[3] != 0.0 || e[4] != 0.0 || e[5] != 0.0;
  const Eigen::Matrix3d re = has_r ? RotXYZ(e[3], e[4], e[5]) : Eigen::Matrix3d::Identity();
  if (need_l_t) {
    const Eigen::Matrix3d d = re - R_L;
    for (int c = 6; c < 9; ++c)
      if (mask[static_cast<std::size_t>(c)]) G->col(c) = d.col(c - 6);
  }
  if (!need_r && !need_l_r) return;
  const int dir = AxisIndex(link.axis) % 3;
  const double sq = link.motion_sign() * q;
  const bool tilted = e[9] != 0.0 || e[10] != 0.0 || e[11] != 0.0;
  const Eigen::Vector3d k = tilted ? Eigen::Vector3d(RotXYZ(e[9], e[10], e[11]).col(dir))
                                   : Eigen::Vector3d(Eigen::Vector3d::Unit(dir));
  Eigen::Vector3d w, m;
  double s = 0.0, c = 1.0;
  if (rotary) {
    const Eigen::Vector3d l_t(e[6], e[7], e[8]);
    m = u - link.pivot_mm - l_t;
    chain_internal::SinCos(sq, &s, &c);
    w = l_t + chain_internal::Rodrigues(k, sq) * m;
  } else {
    w = u - link.pivot_mm;
  }
  if (need_r) {
    const auto dR = RotXYZPartials(e[3], e[4], e[5]);
    for (int j = 0; j < 3; ++j)
      if (mask[static_cast<std::size_t>(3 + j)]) G->col(3 + j) = dR[static_cast<std::size_t>(j)] * w;
  }
  if (need_l_r) {
    const auto dK = RotXYZPartials(e[9], e[10], e[11]);
    Eigen::Matrix3d d_dk;  // d(L u) / d k
    if (rotary) {
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d ei = Eigen::Vector3d::Unit(i);
        d_dk.col(i) = s * ei.cross(m) + (1.0 - c) * (ei * k.dot(m) + k * m(i));
      }
      d_dk = re * d_dk;
    } else {
      d_dk = sq * Eigen::Matrix3d::Identity();
    }
    for (int j = 0; j < 3; ++j)
      if (mask[static_cast<std::size_t>(9 + j)]) G->col(9 + j) = d_dk * dK[static_cast<std::size_t>(j)].col(dir);
  }
}

// Per-thread scratch of ToolPointJacobian (no allocation per call once warm).
struct JacobianScratch {
  std::vector<LinkErrors> link_errors;
  std::vector<double> weights;
  std::vector<double> column_weight;  // basis weight of each active coefficient at the axes
};


// Per link, d(tool point in part) / d(error component) for the components in mask[link]
// (columns outside the mask are left unset), and the tool point. The chain is
// W = L_0 ... L_{w-1} (workpiece branch) and T = L_w ... L_{m-1} (tool branch); the tool point is
// p = W^-1 T c. For a tool link k, T = A L_k B: dp = R_W^T R_A d(L_k)(B c). For a workpiece link
// k, W = A L_k B and z = B p satisfies L_k z = A^-1 T c, so dp = -R_B^T R_k^T d(L_k)(z), with
// d(L_k)(u) = G_k de (LinkPointDerivative): exact, the derivative ToolPointInPartT<Jet> gives
// (tested), at the cost of a double chain and one narrow Jet pass per link in the mask.
Eigen::Vector3d LinkDerivatives(const MachineModel& model, const std::vector<LinkErrors>& link_errors,
                                const AxisState& axes, const Eigen::Vector3d& contact_in_tool_mm,
                                const std::array<ComponentMask, kMaxLinks>& mask,
                                std::array<Eigen::Matrix<double, 3, kNumComponents>, kMaxLinks>* D) {
  const int m = model.num_links();
  const int nw = model.num_workpiece_links;
  const double q[kNumAxes] = {axes.x_mm, axes.y_mm, axes.z_mm, axes.a_rad, axes.b_rad, axes.c_rad};
  auto qi = [&](int i) { return q[AxisIndex(model.links[static_cast<std::size_t>(i)].axis)]; };
  std::array<PoseT<double>, kMaxLinks> L;
  for (int i = 0; i < m; ++i)
    L[static_cast<std::size_t>(i)] =
        LinkTransform<double>(model.links[static_cast<std::size_t>(i)], link_errors[static_cast<std::size_t>(i)].data(), qi(i));
  // prefix[i]: product of the links before i in its branch.
  std::array<PoseT<double>, kMaxLinks> prefix;
  PoseT<double> W, T;
  for (int i = 0; i < m; ++i) {
    PoseT<double>& acc = i < nw ? W : T;
    prefix[static_cast<std::size_t>(i)] = acc;
    acc = acc * L[static_cast<std::size_t>(i)];
  }
  const Eigen::Vector3d p = W.R.transpose() * (T * contact_in_tool_mm - W.t);
  Eigen::Matrix<double, 3, kNumComponents> G;
  Eigen::Vector3d u = contact_in_tool_mm;  // tool branch: u = B c, from the tip
  for (int i = m - 1; i >= nw; --i) {
    const auto k = static_cast<std::size_t>(i);
    if (mask[k].any()) {
      LinkPointDerivative(model.links[k], link_errors[k], qi(i), L[k].R, mask[k], u, &G);
      (*D)[k] = W.R.transpose() * (prefix[k].R * G);
    }
    u = L[k] * u;
  }
  Eigen::Vector3d z = p;  // workpiece branch: z = B p and R_B, from the part
  Eigen::Matrix3d RB = Eigen::Matrix3d::Identity();
  for (int i = nw - 1; i >= 0; --i) {
    const auto k = static_cast<std::size_t>(i);
    if (mask[k].any()) {
      LinkPointDerivative(model.links[k], link_errors[k], qi(i), L[k].R, mask[k], z, &G);
      (*D)[k] = -(RB.transpose() * (L[k].R.transpose() * G));
    }
    z = L[k] * z;
    RB = L[k].R * RB;
  }
  return p;
}

}  // namespace

Eigen::Vector3d ToolPointJacobian(const MachineModel& model, const ErrorState& errors,
                                  const ActiveSet& active, const AxisState& axes,
                                  const Eigen::Vector3d& contact_in_tool_mm,
                                  Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_params) {
  thread_local JacobianScratch scratch;
  J_point_params->setZero(3, active.size());
  EvaluateLinkErrors(errors, axes, &scratch.link_errors);
  // Basis weight of each active coefficient and the components it moves, per link; de/dx_j =
  // gain * weight for every slot coefficient j writes (ChainInputsT).
  std::array<ComponentMask, kMaxLinks> mask{};
  scratch.column_weight.assign(static_cast<std::size_t>(active.size()), 0.0);
  int weights_term = -1;
  for (int j = 0; j < active.size(); ++j) {
    const CoefficientInfo& info = errors.coefficient_info(active.coefficients[static_cast<std::size_t>(j)]);
    const ErrorTerm& term = errors.terms()[static_cast<std::size_t>(info.term)];
    if (info.term != weights_term) {
      EvaluateTermBasis(term, axes, &scratch.weights);
      weights_term = info.term;
    }
    const double w = scratch.weights[static_cast<std::size_t>(info.index)];
    scratch.column_weight[static_cast<std::size_t>(j)] = w;
    if (w == 0.0) continue;
    for (const SlotEffect& s : term.effects)
      mask[static_cast<std::size_t>(errors.LinkIndex(s.axis))].set(static_cast<std::size_t>(ComponentIndex(s.component)));
  }
  std::array<Eigen::Matrix<double, 3, kNumComponents>, kMaxLinks> D;
  const Eigen::Vector3d p = LinkDerivatives(model, scratch.link_errors, axes, contact_in_tool_mm, mask, &D);
  for (int j = 0; j < active.size(); ++j) {
    const double w = scratch.column_weight[static_cast<std::size_t>(j)];
    if (w == 0.0) continue;
    const CoefficientInfo& info = errors.coefficient_info(active.coefficients[static_cast<std::size_t>(j)]);
    for (const SlotEffect& s : errors.terms()[static_cast<std::size_t>(info.term)].effects)
      J_point_params->col(j) +=
          (s.gain * w) * D[static_cast<std::size_t>(errors.LinkIndex(s.axis))].col(ComponentIndex(s.component));
  }
  return p;
}

Eigen::Vector3d ToolPointSlotJacobian(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                                      const Eigen::Vector3d& contact_in_tool_mm, std::span<const ErrorSlot> slots,
                                      Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_slots) {
  thread_local JacobianScratch scratch;
  EvaluateLinkErrors(errors, axes, &scratch.link_errors);
  std::array<ComponentMask, kMaxLinks> mask{};
  for (const ErrorSlot& s : slots)
    mask[static_cast<std::size_t>(errors.LinkIndex(s.axis))].set(static_cast<std::size_t>(ComponentIndex(s.component)));
  std::array<Eigen::Matrix<double, 3, kNumComponents>, kMaxLinks> D;
  const Eigen::Vector3d p = LinkDerivatives(model, scratch.link_errors, axes, contact_in_tool_mm, mask, &D);
  J_point_slots->resize(3, static_cast<Eigen::Index>(slots.size()));
  for (std::size_t k = 0; k < slots.size(); ++k)
    J_point_slots->col(static_cast<Eigen::Index>(k)) =
        D[static_cast<std::size_t>(errors.LinkIndex(slots[k].axis))].col(ComponentIndex(slots[k].component));
  return p;
}

void PartFromToolJacobian(const MachineModel& model, const ErrorState& errors,
                          const ActiveSet& active, const AxisState& axes,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>* J_pose_params) {
  ChainScratch scratch;
  J_pose_params->setZero(6, active.size());
  for (int begin = 0; begin < active.size(); begin += kChunk) {
    const std::vector<Jet> x = Seed<kChunk>(errors, active, begin);
    const PoseT<Jet> pose = PartFromToolT<Jet>(model, errors, active, x.data(), axes, &scratch);
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R(r, c) = pose.R(r, c).a;
    }
    for (int j = begin; j < std::min(begin + kChunk, active.size()); ++j) {
      Eigen::Matrix3d dR;
      for (int r = 0; r < 3; ++r) {
        (*J_pose_params)(r, j) = pose.t(r).v[j - begin];
        for (int c = 0; c < 3; ++c) dR(r, c) = pose.R(r, c).v[j - begin];
      }
      const Eigen::Matrix3d W = dR * R.transpose();  // skew: [w]x
      (*J_pose_params)(3, j) = 0.5 * (W(2, 1) - W(1, 2));
      (*J_pose_params)(4, j) = 0.5 * (W(0, 2) - W(2, 0));
      (*J_pose_params)(5, j) = 0.5 * (W(1, 0) - W(0, 1));
    }
  }
}

}  // namespace tpcal::kinematics
