// The seed 002 case of issue 22 (its section 4.4): the machine errors of its probing test (Table 2,
// column "probing test") against those of its machining test, which tpcal identifies from the
// finished piece's GD&T items (Table 1) by solver (a) (kinematics/seed002_closed_form.h, the
// kinematics equations), compared parameter by parameter and through the combinations Table 1
// does determine (diagnosis/reference_agreement.h). Units: um and urad.
#pragma once

#include <span>

#include "core/status.h"
#include "kinematics/seed002_closed_form.h"
#include "pipeline/diagnosis/reference_agreement.h"

namespace tpcal::pipeline {

struct Seed002ColumnsComparison {
  kinematics::ClosedFormResult piece;  // Table 1 through solver (a)
  ReferenceAgreement agreement;        // the probing column against it
};

// `item_u`: the items' standard uncertainties (empty: none, so no row is compared: the table then
// holds the differences only); `probing`: the probing test's parameters with their u (0: unknown,
// no row compared). Errors: SolveSeed002's.
Result<Seed002ColumnsComparison> CompareSeed002Columns(const kinematics::Seed002Items& table1,
                                                       const kinematics::Seed002Items& item_u,
                                                       const kinematics::Seed002Geometry& geometry,
                                                       std::span<const kinematics::ParameterEstimate> probing,
                                                       double alpha);

}  // namespace tpcal::pipeline
