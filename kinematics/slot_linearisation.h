// Linearisation of observations per error slot, and coefficient columns from it by the chain rule.
// One slot design (d deviation / d slot, kinematics::LineariseSlotObservations) serves any set of
// coefficients writing those slots: each coefficient's column is its term's gain and basis value
// at the cut's nominal axis state times its slots' columns. A handful of slots thus replaces a
// Jacobian pass per coefficient (the diagnosis linearises its base model and every candidate
// coefficient from one slot design; tpcal run shares that design with the identification).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/status.h"
#include "kinematics/error_state.h"
#include "kinematics/identification.h"
#include "kinematics/jacobians.h"
#include "kinematics/machine_model.h"

namespace tpcal::kinematics {

// The deviation of every observation linearised per error slot at a state of the errors:
// dslot_um(i, k) = d deviation (um) / d slot k (mm or rad), and the alignment columns, measured
// and predicted deviations of LineariseObservations (lin.J_dev_params is empty).
struct SlotDesign {
  std::vector<ErrorSlot> slots;
  Eigen::MatrixXd dslot_um;
  LinearDesign lin;
};

// The slots the coefficients `coefficients` of `errors` write (first-use order, no repeats).
std::vector<ErrorSlot> SlotsOf(const ErrorState& errors, const std::vector<int>& coefficients);
// Appends the slots of `more` that `slots` lacks.
void AddSlots(const std::vector<ErrorSlot>& more, std::vector<ErrorSlot>* slots);

// LineariseSlotObservations at the state `errors` (its zero-valued terms left out: they add
// nothing). Errors: those of LineariseSlotObservations (a surface point that does not converge).
Result<SlotDesign> LineariseSlots(const MachineModel& machine, const ErrorState& errors,
                                  const std::vector<ErrorSlot>& slots, std::span<const Observation> observations);

// d deviation / d coefficient (um per display unit, n x coefficients.size()) of coefficients of
// `errors` from a slot design of the same observations: each coefficient's gain and basis value
// at the cut's nominal axis state (EvaluateTermBasis, conditions included) times its slots'
// columns. kInvalidArgument when a coefficient writes a slot the design lacks or the design has
// another number of observations.
Result<Eigen::MatrixXd> CoefficientColumns(const SlotDesign& design, const ErrorState& errors,
                                           const std::vector<int>& coefficients,
                                           std::span<const Observation> observations);

// d deviation / d coefficient (um per display unit) of the coefficients `coefficients` of `errors`
// at the state `errors`, by the chain rule through the error slots they write: LineariseSlots
// over the slots used (a handful instead of every coefficient), then CoefficientColumns. Equal to
// the direct Jacobian at zero errors; at non-zero errors the basis is taken at the nominal instead
// of the solved sweep position, a relative change of order (error / tangent speed) (~1e-4 for
// tens of um). Returns the LinearDesign with J_dev_params holding these columns (alignment,
// measured and predicted deviations as LineariseObservations gives them).
Result<LinearDesign> LineariseBySlots(const MachineModel& machine, const ErrorState& errors,
                                      const std::vector<int>& coefficients, std::span<const Observation> observations);

// The rows `rows` (indices into the design's observations, in the order given) of a design: the
// design of that subset of the observations (e.g. without the points an outlier screen left out).
LinearDesign RowsOf(const LinearDesign& design, std::span<const int> rows);
SlotDesign RowsOf(const SlotDesign& design, std::span<const int> rows);

// Machine-frame outward normal of an observation (nominal kinematics at its cut state).
Eigen::Vector3d MachineNormal(const MachineModel& machine, const Observation& o);

}  // namespace tpcal::kinematics
