// The CSV tables of a run from an identification result built by hand.
#include "pipeline/report/run_tables.h"

#include <gtest/gtest.h>

#include "kinematics/machine_model.h"

namespace tpcal::pipeline {
namespace {

kinematics::IdentificationResult TwoParameters() {
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kXyz);
  kinematics::IdentificationResult id{kinematics::ErrorState(*machine)};
  kinematics::ParameterEstimate a{.name = "E_C0X", .iso_symbol = "E_C(0X)Y", .unit = "urad", .identifiable = true,
                                  .value = 1.5, .u = 0.25, .ci95_low = 1.0, .ci95_high = 2.0, .uncertainties = {}};
  kinematics::Uncertainty analytic;
  analytic.available = true;
  analytic.u = 0.25;
  a.uncertainties.push_back(analytic);
  const kinematics::ParameterEstimate b{.name = "dx, odd", .iso_symbol = "", .unit = "um", .identifiable = false,
                                        .value = 0.0, .u = 0.0, .ci95_low = 0.0, .ci95_high = 0.0, .uncertainties = {}};
  id.parameters = {a, b};
  id.identifiability.num_parameters = 2;
  id.identifiability.rank = 1;
  id.identifiability.condition_number = 3.0;
  id.identifiability.singular_values = {2.0, 0.0};
  return id;
}

TEST(RunTables, IdentificationCsvWithAndWithoutTruth) {
  const auto id = TwoParameters();
  EXPECT_EQ(IdentificationCsv(id, {}),
            "name,iso_symbol,unit,identifiable,value,u,ci95_low,ci95_high,u_analytic,u_jackknife_points,"
            "u_jackknife_groups,u_monte_carlo\n"
            "E_C0X,E_C(0X)Y,urad,true,1.5,0.25,1,2,0.25,,,\n"
            "\"dx, odd\",,um,false,,,,,,,,\n");
  const std::string with_truth = IdentificationCsv(id, {{"E_C0X", 1.25}});
  EXPECT_NE(with_truth.find("u_monte_carlo,truth\n"), std::string::npos) << with_truth;
  EXPECT_NE(with_truth.find("1,2,0.25,,,,1.25\n"), std::string::npos) << with_truth;
  EXPECT_NE(with_truth.find("false,,,,,,,,,\n"), std::string::npos) << with_truth;
}

TEST(RunTables, IdentifiabilityCsvSummaryAndSingularValues) {
  EXPECT_EQ(IdentifiabilityCsv(TwoParameters()),
            "kind,text,value,u\nsummary,num_parameters,2,\nsummary,rank,1,\nsummary,condition_number,3,\n"
            "singular_value,s1,2,\nsingular_value,s2,0,\n");
}

}  // namespace
}  // namespace tpcal::pipeline
