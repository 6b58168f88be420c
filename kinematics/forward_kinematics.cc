#include "kinematics/forward_kinematics.h"

#include <array>
#include <cassert>
#include <bit>
#include <cstdint>

#include "kinematics/chain_eval.h"
#include "kinematics/internal/memo_chain.h"

namespace tpcal::kinematics {

namespace {

std::array<double, kNumAxes> Positions(const AxisState& s) {
  return {s.x_mm, s.y_mm, s.z_mm, s.a_rad, s.b_rad, s.c_rad};
}

Rigid3 ToRigid(const PoseT<double>& p) {
  Rigid3 out = Rigid3::Identity();
  out.linear() = p.R;
  out.translation() = p.t;
  return out;
}

const std::vector<LinkErrors>& ZeroErrors(const MachineModel& model, std::vector<LinkErrors>* buf) {
  LinkErrors zero;
  zero.fill(0.0);
  buf->assign(model.num_links(), zero);
  return *buf;
}

void Branches(const MachineModel& model, const std::vector<LinkErrors>& e, const AxisState& axes,
              PoseT<double>* w, PoseT<double>* t) {
  assert(static_cast<int>(e.size()) == model.num_links());
  const std::array<double, kNumAxes> q = Positions(axes);
  BranchPosesT<double>(model, e.data(), q.data(), w, t);
}

bool SameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

void Evaluate(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
              Workspace* ws) {
  assert(errors.num_links() == model.num_links() && errors.machine_type() == model.type);
  EvaluateLinkErrors(errors, axes, &ws->link_errors);
}

}  // namespace

namespace internal {

namespace {

// The conventions.h link formula in double precision, reusing `m`'s error rotations.
void UpdateLink(const AxisLink& link, const LinkErrors& e, double q, LinkMemo* m) {
  // A Workspace may be reused with another model: the memo holds only for the same link.
  if (m->link.axis != link.axis || m->link.branch != link.branch ||
      !SameBits(m->link.pivot_mm.x(), link.pivot_mm.x()) ||
      !SameBits(m->link.pivot_mm.y(), link.pivot_mm.y()) ||
      !SameBits(m->link.pivot_mm.z(), link.pivot_mm.z())) {
    m->link = link;
    m->valid_e = false;
    m->valid_q = false;
  }
  // Error rotations: recomputed only when their own components changed.
  const int dir = AxisIndex(link.axis) % 3;
  auto same3 = [&](int first) {
    return SameBits(m->e[first], e[first]) && SameBits(m->e[first + 1], e[first + 1]) &&
           SameBits(m->e[first + 2], e[first + 2]);
  };
  bool same_e = m->valid_e;
  if (!m->valid_e || !same3(3)) {
    m->has_r = !(e[3] == 0.0 && e[4] == 0.0 && e[5] == 0.0);
    m->re = m->has_r ? chain_internal::RotXYZ(e[3], e[4], e[5]) : Eigen::Matrix3d::Identity();
    same_e = false;
  }
  if (!m->valid_e || !same3(9)) {
    if (e[9] == 0.0 && e[10] == 0.0 && e[11] == 0.0) {
      m->k = Eigen::Vector3d::Unit(dir);
    } else {
      m->k = chain_internal::RotXYZ(e[9], e[10], e[11]).col(dir);
    }
    same_e = false;
  }
  if (same_e && !(same3(0) && same3(6))) same_e = false;
  if (same_e && m->valid_q && SameBits(m->q, q)) return;
  m->valid_e = true;
  m->e = e;
  m->valid_q = true;
  m->q = q;
  const Eigen::Vector3d& p = link.pivot_mm;
  const Eigen::Vector3d e_t(e[0], e[1], e[2]);
  const Eigen::Vector3d& k = m->k;
  const double sq = link.motion_sign() * q;
  if (IsRotary(link.axis)) {
    const Eigen::Matrix3d rg = chain_internal::Rodrigues<double>(k, sq);  // the templated chain's formula
    const Eigen::Vector3d l_t(e[6], e[7], e[8]);
    const Eigen::Vector3d t_g = l_t - rg * l_t;
    if (m->has_r) {
      m->R = m->re * rg;
      m->t = p + e_t + m->re * t_g - m->R * p;
      m->axis_direction = m->re * k;
      m->axis_point = p + e_t + m->re * l_t;
    } else {
      m->R = rg;
      m->t = p + e_t + t_g - rg * p;
      m->axis_direction = k;
      m->axis_point = p + e_t + l_t;
    }
  } else {
    const Eigen::Vector3d v = sq * k;
    if (m->has_r) {
      m->R = m->re;
      m->t = p + v + e_t - m->re * p;
    } else {
      m->R.setIdentity();
      m->t = v + e_t;
    }
    m->axis_direction = k;
    m->axis_point = p;
  }
}

}  // namespace

void MemoBranchPoses(const MachineModel& model, const std::vector<LinkErrors>& e,
                     const AxisState& axes, Workspace* ws, PoseT<double>* machine_from_part,
                     PoseT<double>* machine_from_tool, LinkAxisT<double>* axes_out) {
  assert(static_cast<int>(e.size()) == model.num_links());
  if (static_cast<int>(ws->memo.size()) != model.num_links()) ws->memo.assign(model.num_links(), LinkMemo{});
  const std::array<double, kNumAxes> q = Positions(axes);
  PoseT<double> w, tool;
  for (int i = 0; i < model.num_links(); ++i) {
    const AxisLink& link = model.links[i];
    LinkMemo& m = ws->memo[i];
    UpdateLink(link, e[i], q[AxisIndex(link.axis)], &m);
    PoseT<double>& acc = i < model.num_workpiece_links ? w : tool;
    if (axes_out) {
      axes_out[i].direction = link.motion_sign() * (acc.R * m.axis_direction);
      axes_out[i].point = acc * Eigen::Vector3d(m.axis_point);
    }
    if (IsRotary(link.axis) || m.has_r) {
      acc.t += acc.R * m.t;
      acc.R = acc.R * m.R;
    } else {
      acc.t += acc.R * m.t;
    }
  }
  *machine_from_part = w;
  *machine_from_tool = tool;
}

}  // namespace internal

Rigid3 PartFromToolWithLinkErrors(const MachineModel& model,
                                  const std::vector<LinkErrors>& link_errors,
                                  const AxisState& axes) {
  PoseT<double> w, t;
  Branches(model, link_errors, axes, &w, &t);
  return ToRigid(w.inverse() * t);
}

Rigid3 PartFromTool(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                    Workspace* ws) {
  Evaluate(model, errors, axes, ws);
  PoseT<double> w, t;
  internal::MemoBranchPoses(model, ws->link_errors, axes, ws, &w, &t, nullptr);
  return ToRigid(w.inverse() * t);
}

Rigid3 NominalPartFromTool(const MachineModel& model, const AxisState& axes) {
  std::vector<LinkErrors> buf;
  return PartFromToolWithLinkErrors(model, ZeroErrors(model, &buf), axes);
}

Rigid3 NominalPartFromTool(const MachineModel& model, const AxisState& axes, Workspace* ws) {
  ZeroErrors(model, &ws->link_errors);
  PoseT<double> w, t;
  internal::MemoBranchPoses(model, ws->link_errors, axes, ws, &w, &t, nullptr);
  return ToRigid(w.inverse() * t);
}

Rigid3 MachineFromPart(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                       Workspace* ws) {
  Evaluate(model, errors, axes, ws);
  PoseT<double> w, t;
  Branches(model, ws->link_errors, axes, &w, &t);
  return ToRigid(w);
}

Rigid3 MachineFromTool(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
                       Workspace* ws) {
  Evaluate(model, errors, axes, ws);
  PoseT<double> w, t;
  Branches(model, ws->link_errors, axes, &w, &t);
  return ToRigid(t);
}

Eigen::Vector3d ToolPointInPart(const MachineModel& model, const ErrorState& errors,
                                const AxisState& axes, const Eigen::Vector3d& contact_in_tool_mm,
                                Workspace* ws) {
  Evaluate(model, errors, axes, ws);
  PoseT<double> w, t;
  internal::MemoBranchPoses(model, ws->link_errors, axes, ws, &w, &t, nullptr);
  // part point = R_w^T (R_t c + t_t - t_w)
  return w.R.transpose() * (t.R * contact_in_tool_mm + t.t - w.t);
}

Eigen::Vector3d NominalToolPointInPart(const MachineModel& model, const AxisState& axes,
                                       const Eigen::Vector3d& contact_in_tool_mm) {
  return NominalPartFromTool(model, axes) * contact_in_tool_mm;
}

Eigen::Vector3d NominalToolAxisInPart(const MachineModel& model, const AxisState& axes) {
  return NominalPartFromTool(model, axes).linear().col(2);
}

}  // namespace tpcal::kinematics
