// The stdout text of `tpcal run` from results built by hand.
#include "pipeline/report/run_summary.h"

#include <gtest/gtest.h>

#include "kinematics/machine_model.h"

namespace tpcal::pipeline {
namespace {

kinematics::ParameterEstimate Estimate(const std::string& name, const std::string& unit, bool identifiable) {
  return {.name = name, .iso_symbol = "", .unit = unit, .identifiable = identifiable, .value = 1.23456,
          .u = 0.5, .ci95_low = 0.25, .ci95_high = 2.25, .uncertainties = {}};
}

TEST(RunSummary, ParameterRowsByUnitAndIdentifiability) {
  auto machine = kinematics::MakeMachine(kinematics::MachineType::kXyz);
  kinematics::IdentificationResult id{kinematics::ErrorState(*machine)};
  id.parameters = {Estimate("dx_CR(0)", "um", true), Estimate("E_XX.c2", "um/mm^2", true),
                   Estimate("dy_AR(-90)", "um", false)};
  id.identifiability.rank = 2;
  id.identifiability.num_parameters = 3;
  id.identifiability.condition_number = 12.5;
  id.rms_before_um = 10.0;
  id.rms_after_um = 0.5;
  EXPECT_EQ(RunParameterTable(id),
            "parameter        ISO 230-1                   value   u (k=1)           95 % interval  unit\n"
            "dx_CR(0)                                      1.23     0.500 [     0.25,      2.25]  um\n"
            "E_XX.c2                                      1.235       0.5 [     0.25,      2.25]  um/mm^2\n"
            "dy_AR(-90)                                     n/a         -        not identifiable  um\n"
            "rank 2 of 3, condition number 12.5; residual RMS 10.000 um -> 0.500 um\n");
}

// The identification's screen: nothing flagged, no line; 8 points of which 6 in 3 patches.
TEST(RunSummary, IdentificationScreenLineCountsTheFlaggedPoints) {
  EXPECT_EQ(IdentificationScreenLine({}, {}), "");
  std::vector<ScreenedPoint> flagged(8, ScreenedPoint{.point_index = 0, .line = 0, .feature = "H1", .kind = "local_defect",
                                                      .deviation_um = 2.0, .reason = "", .left_out = true});
  LocalDefect two;
  two.feature = "H1";
  two.n_points = 2;
  const std::vector<LocalDefect> patches(3, two);
  EXPECT_EQ(IdentificationScreenLine(flagged, patches),
            "identification: 8 point(s) left out by the outlier screen (6 in 3 local defect(s); result.json: "
            "identification.outliers)\n");
  flagged[0].left_out = false;
  EXPECT_NE(IdentificationScreenLine(flagged, patches).find("flagged and kept"), std::string::npos);
}

TEST(RunSummary, GapDiagnosisLineMadeNotMadeAndNotAsked) {
  DiagnosisResult d;
  d.verdict.family = "thermal_drift";
  d.verdict.name = "drift";
  d.verdict.shrink_pct = 42.04;
  d.verdict.cv_shrink_pct = 40.0;
  EXPECT_EQ(GapDiagnosisLine(d, true, Status::Ok()),
            "gap diagnosis: thermal_drift (drift), shrink 42.0 % (cross-validated 40.0 %)\n");
  const Status why(StatusCode::kInvalidArgument, "no residual degrees of freedom");
  EXPECT_EQ(GapDiagnosisLine(std::nullopt, true, why), "gap diagnosis: not made: " + why.ToString() + "\n");
  EXPECT_EQ(GapDiagnosisLine(std::nullopt, false, why), "");
}

TEST(RunSummary, InstrumentLineAfterTheGapLineNamesTheDisagreeing) {
  DiagnosisResult d;
  d.verdict.family = "thermal_drift";
  d.verdict.name = "drift";
  ReferenceAgreement a;
  a.compared = 3;
  a.disagreeing = 1;
  AgreementRow agrees;
  agrees.name = "E_Y0A";
  AgreementRow differs;
  differs.name = "E_X0C";
  differs.agree = false;
  a.rows = {agrees, differs};
  d.reference_agreement = a;
  EXPECT_EQ(GapDiagnosisLine(d, true, Status::Ok()),
            "gap diagnosis: thermal_drift (drift), shrink 0.0 % (cross-validated 0.0 %)\n"
            "instrument vs piece: 1 of 3 compared parameters disagree (E_X0C)\n");
  a.disagreeing = 0;
  a.rows = {agrees};
  EXPECT_EQ(InstrumentAgreementLine(a), "instrument vs piece: 0 of 3 compared parameters disagree\n");
  EXPECT_EQ(InstrumentAgreementLine(std::nullopt), "");
}

}  // namespace
}  // namespace tpcal::pipeline
