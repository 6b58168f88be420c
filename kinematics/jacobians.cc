#include "kinematics/jacobians.h"

#include <ceres/jet.h>

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

// Columns [begin, begin + N) of J_point_params (clipped to active.size()) by one pass with
// Jet<double, N>. Every derivative part is computed by the same operations whatever N, so the
// columns do not depend on how the active set is chunked.
// Flattened: every call inlined (the Jet arithmetic otherwise stays in out-of-line Eigen loops;
// 2.7x faster, same operations, so the same bits: result.json of the turning sample unchanged).
template <int N>
[[gnu::flatten]] Eigen::Vector3d ToolPointColumns(const MachineModel& model, const ErrorState& errors,
                                 const ActiveSet& active, const AxisState& axes,
                                 const Eigen::Vector3d& contact_in_tool_mm, int begin,
                                 ChainScratch* scratch,
                                 Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_params) {
  const std::vector<ceres::Jet<double, N>> x = Seed<N>(errors, active, begin);
  const Eigen::Matrix<ceres::Jet<double, N>, 3, 1> p = ToolPointInPartT<ceres::Jet<double, N>>(
      model, errors, active, x.data(), axes, contact_in_tool_mm, scratch);
  Eigen::Vector3d point;
  for (int r = 0; r < 3; ++r) {
    point(r) = p(r).a;
    for (int j = begin; j < std::min(begin + N, active.size()); ++j) {
      (*J_point_params)(r, j) = p(r).v[j - begin];
    }
  }
  return point;
}

}  // namespace

Eigen::Vector3d ToolPointJacobian(const MachineModel& model, const ErrorState& errors,
                                  const ActiveSet& active, const AxisState& axes,
                                  const Eigen::Vector3d& contact_in_tool_mm,
                                  Eigen::Matrix<double, 3, Eigen::Dynamic>* J_point_params) {
  ChainScratch scratch;
  J_point_params->setZero(3, active.size());
  // Only the coefficients whose basis weight at `axes` is non-zero act on the chain (a
  // conditional parameter whose condition fails, a table node out of reach): the others'
  // columns are exactly zero and get no derivative slot.
  ActiveSet live;
  std::vector<int> column_of_live;
  int weights_term = -1;
  for (int j = 0; j < active.size(); ++j) {
    const CoefficientInfo& info = errors.coefficient_info(active.coefficients[j]);
    if (info.term != weights_term) {
      EvaluateTermBasis(errors.terms()[info.term], axes, &scratch.weights);
      weights_term = info.term;
    }
    if (scratch.weights[info.index] == 0.0) continue;
    live.coefficients.push_back(active.coefficients[j]);
    column_of_live.push_back(j);
  }
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  if (live.size() == 0) {
    const double* none = nullptr;
    point = ToolPointInPartT<double>(model, errors, live, none, axes, contact_in_tool_mm, &scratch);
    return point;
  }
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_live(3, live.size());
  // One pass per 24 columns, each with the narrowest Jet that holds its columns (the cost of a
  // pass grows with the Jet width; the value part is computed once per pass).
  for (int begin = 0; begin < live.size(); begin += 24) {
    const int width = live.size() - begin;
    auto columns = [&]<int N>() {
      point = ToolPointColumns<N>(model, errors, live, axes, contact_in_tool_mm, begin, &scratch, &J_live);
    };
    if (width <= 4) {
      columns.template operator()<4>();
    } else if (width <= 8) {
      columns.template operator()<8>();
    } else if (width <= 12) {
      columns.template operator()<12>();
    } else if (width <= 16) {
      columns.template operator()<16>();
    } else if (width <= 20) {
      columns.template operator()<20>();
    } else {
      columns.template operator()<24>();
    }
  }
  for (int k = 0; k < live.size(); ++k) J_point_params->col(column_of_live[k]) = J_live.col(k);
  return point;
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
