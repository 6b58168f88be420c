#include "kinematics/forward_kinematics.h"

#include <array>
#include <cassert>

#include "kinematics/chain_eval.h"

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

void Evaluate(const MachineModel& model, const ErrorState& errors, const AxisState& axes,
              Workspace* ws) {
  assert(errors.num_links() == model.num_links() && errors.machine_type() == model.type);
  EvaluateLinkErrors(errors, axes, &ws->link_errors, &ws->scratch);
}

}  // namespace

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
  return PartFromToolWithLinkErrors(model, ws->link_errors, axes);
}

Rigid3 NominalPartFromTool(const MachineModel& model, const AxisState& axes) {
  std::vector<LinkErrors> buf;
  return PartFromToolWithLinkErrors(model, ZeroErrors(model, &buf), axes);
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
  Branches(model, ws->link_errors, axes, &w, &t);
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
