// The validation against an instrument reference (issue 22) in small (fixed seed 22): the turning
// piece on the nominal A/C table, random cold base errors (+-20 um / urad), each trial's cold
// machine measured by a datum-ball test, the piece cut with one withheld effect at 10x the 0.5 um
// CMM noise (peak of the part the base model cannot absorb) and diagnosed against the test.
// Truth: the withheld family, none on effect-free pieces. Tolerances from the targets of issue 22:
// false alarms <= 5 % (a verdict other than none, or a disagreeing parameter): with 20 trials a
// true 5 % rate gives more than 2 alarms with probability 7.5 %, so the test allows 2 (measured
// 0 of 100 tight and 2 of 100 loose on the CLI's larger run, README "Piece against instrument").
// Tool deflection is named in 98 % of the larger run, servo reversal in 98 % and the withheld
// drift in 96 % (100 % at 10x; a true 96 % gives fewer than 17 of 20 with probability 0.7 %: the
// test asks 85 % of each), the drift named as the verdict or as its alias in 100 %.
#include "pipeline/instrument_validation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "pipeline/testing/turning_fixture.h"

namespace tpcal::pipeline {
namespace {

ValidationOptions SmallInstrumentStudy(std::vector<std::string> families, int trials) {
  ValidationOptions v;
  v.families = std::move(families);
  v.magnitudes = {10.0};
  v.noise_um = {0.5};
  v.trials = trials;
  v.seed = 22;
  return v;
}

// The trials of a straightness withheld at 5x against `instrument` (`trials` at `seed`, on the
// turning piece of the A/C table); empty, with a failure, when the study fails.
std::vector<ValidationTrial> StraightnessAt5x(const InstrumentValidationOptions& instrument, int trials,
                                              std::uint64_t seed) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  ValidationOptions v = SmallInstrumentStudy({"linear_straightness"}, trials);
  v.magnitudes = {5.0};
  v.seed = seed;
  auto s = RunInstrumentValidation(setup, v, instrument);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return s.ok() ? s->trials : std::vector<ValidationTrial>{};
}

int NoneAlarms(const ValidationSummary& s) {
  return static_cast<int>(std::count_if(s.trials.begin(), s.trials.end(), [](const ValidationTrial& t) {
    return t.true_family == "none" && (t.verdict != "none" || t.reference_disagreeing > 0);
  }));
}

TEST(InstrumentValidation, TightDatumBallNamesTheEffectsAndRaisesNoAlarm) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto s = RunInstrumentValidation(setup, SmallInstrumentStudy({"tool_deflection", "servo_reversal", "thermal_drift", "none"}, 20),
                                   {.instrument = "datum_ball", .noise_um = 0.5});
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  EXPECT_TRUE(s->against_reference);
  for (const ValidationTrial& t : s->trials) {
    EXPECT_NE(t.verdict, "error") << t.true_detail;
    EXPECT_GE(t.reference_compared, 6) << t.true_family << ": the piece is compared with the instrument";
  }
  EXPECT_EQ(s->none_trials, 20);
  EXPECT_LE(s->none_alarms, 2);
  EXPECT_EQ(NoneAlarms(*s), s->none_alarms);
  EXPECT_GE(s->top1_rate.at("tool_deflection"), 0.9);
  EXPECT_GE(s->top1_rate.at("servo_reversal"), 0.85);
  EXPECT_GE(s->top1_rate.at("thermal_drift"), 0.85);
  EXPECT_GE(s->top1_or_alias_rate.at("thermal_drift"), 0.9);
  EXPECT_GT(s->median_cv_shrink_pct, 50.0);
  const std::string md = ValidationMarkdown(*s);
  EXPECT_NE(md.find("| location_errors |"), std::string::npos) << md;
  EXPECT_NE(md.find("Against the reference: false alarms on effect-free pieces"), std::string::npos) << md;
}

// A loose instrument (20 um readings: its u lets the piece decide) raises no alarm either.
TEST(InstrumentValidation, LooseDatumBallRaisesNoAlarm) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto s = RunInstrumentValidation(setup, SmallInstrumentStudy({"none"}, 20), {.instrument = "datum_ball", .noise_um = 20.0});
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  EXPECT_EQ(s->none_trials, 20);
  EXPECT_LE(s->none_alarms, 2);
}

// Against a probing test of artifacts (0.05 um touches, C every 15 deg): every trial is diagnosed
// against the maps and compared through their parameter equivalent (the nine seed 002 parameters
// of A and C) and the squareness the probing test fits with its poses (three): twelve rows. The
// validation's cold machines carry location errors and squareness of the linear axes (+-20 um /
// urad); before the probing test fitted the squareness its maps took the shear in and every
// effect-free piece read location_errors (10 of 10, README). Two effect-free pieces read none,
// and a withheld tool deflection and a drift at 10x are named (the CLI's matrix: 10 of 10 each).
TEST(InstrumentValidation, ProbingTestOfArtifactsIsTheReference) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto s = RunInstrumentValidation(setup, SmallInstrumentStudy({"none", "tool_deflection", "thermal_drift"}, 2),
                                   {.instrument = "probe_artifacts", .noise_um = 0.05});
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_EQ(s->trials.size(), 6u);
  for (const ValidationTrial& t : s->trials) {
    EXPECT_EQ(t.reference_compared, 12) << t.true_detail;
    EXPECT_EQ(t.verdict, t.true_family) << t.true_detail;
    if (t.true_family == "none") {
      EXPECT_EQ(t.reference_disagreeing, 0) << t.true_detail;
    }
  }
}

// A drift of the table in Z (E_Z0C, exponential) whose part the 1 um maps do not cover peaks on
// one point of each of four shoulder faces, B1, B2, B4, B5 (5.6 to 6.7 um beside 0.5 um of noise): the screen
// flagged them point by point as outliers, left them out, and the piece read none. The diagnosis
// of every point names the drift, whose model leaves no point to flag (FlagsAsEffect in
// diagnosis.cc). Truth: the drift withheld at 10x (seed 3's first trial); no point listed as an
// outlier. The CLI's run (`--reference-noise-um 1 --families thermal_drift --magnitudes 5,10
// --trials 20 --seed 3`): 32 -> 38 of 40, each of the 6 gained had read none with 4 points flagged.
TEST(InstrumentValidation, ADriftPeakingOnAFewPointsIsNotLeftOutAsOutliers) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  ValidationOptions v = SmallInstrumentStudy({"thermal_drift"}, 1);
  v.seed = 3;
  auto s = RunInstrumentValidation(setup, v, {.instrument = "probe_artifacts", .noise_um = 1.0});
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_EQ(s->trials.size(), 1u);
  const ValidationTrial& t = s->trials[0];
  ASSERT_NE(t.true_detail.find("E_Z0C"), std::string::npos) << t.true_detail;
  EXPECT_EQ(t.verdict, "thermal_drift") << t.true_detail;
  EXPECT_EQ(t.found_points + t.false_flags, 0) << t.true_detail;
}

// A straightness whose visible part the base leaves on one feature (S_R or B_R: the axis range
// only that feature spans) was flagged as patches on both sides of the model and read
// `local_defect`; the diagnosis of every point now names the effect when its model leaves no patch
// (PatchAsEffect in diagnosis.cc). Truth: straightness withheld, 5x, against a 0.05 um probing test
// (seed 4, 8 trials; before, one read local_defect and 6 straightness; the CLI's 100-trial run,
// README: 6 local_defect of 100 before, 1 after). No trial may read local_defect.
TEST(InstrumentValidation, StraightnessLeftOnOneFeatureIsNotALocalDefect) {
  int straightness = 0;
  for (const ValidationTrial& t : StraightnessAt5x({.instrument = "probe_artifacts", .noise_um = 0.05}, 8, 4)) {
    EXPECT_NE(t.verdict, "local_defect") << t.true_detail;
    straightness += t.verdict == "linear_straightness";
  }
  EXPECT_GE(straightness, 7);
}

// A straightness of one axis the cold datum ball never saw leaves part of itself in the piece's
// squareness, where the piece disagrees with the instrument; with candidates bending all three axes
// at once (rank 18 to 24) changed location errors explained it about as well. Truth: 20 single-axis
// straightness errors at 5x; with a candidate per axis and direction 17 are named (the CLI's
// `--reference-instrument datum_ball --families linear_straightness --trials 20 --magnitudes 5
// --seed 1`: 89 % of the observable; 79 % without those candidates, 15 named).
TEST(InstrumentValidation, AStraightnessOfOneAxisIsNotReadAsChangedLocationErrors) {
  int straightness = 0;
  for (const ValidationTrial& t : StraightnessAt5x({.instrument = "datum_ball", .noise_um = 0.5}, 20, 1))
    straightness += t.verdict == "linear_straightness";
  EXPECT_GE(straightness, 17);
}

// Against a ball bar round C holding A at 0 (seven installations, 0.1 um readings): its maps give
// no parameter equivalent (they carry no component along C's location errors and see nothing of
// A), so nothing is compared and the piece's own parameters are fitted from the piece; the
// directions the squareness of the cold machine, folded into C's maps, moves them along are
// fitted with the re-alignment. Truth: four effect-free pieces read none (with the folded share
// left in the maps 43 of 100 raised an alarm, 42 of them rotary_error_motion or
// rotary_positioning; README), and four
// drifts at 10x are named (the CLI's runs: 2 alarms in 100 pieces, the drift 90 %).
TEST(InstrumentValidation, BallbarIsTheReference) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto s = RunInstrumentValidation(setup, SmallInstrumentStudy({"none", "thermal_drift"}, 4),
                                   {.instrument = "ballbar", .noise_um = 0.1});
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  ASSERT_EQ(s->trials.size(), 8u);
  for (const ValidationTrial& t : s->trials) {
    EXPECT_EQ(t.reference_compared, 0) << t.true_detail;
    EXPECT_EQ(t.verdict, t.true_family) << t.true_detail;
  }
}

TEST(InstrumentValidation, UnknownInstrumentAndBadNoiseAreNamed) {
  const LoadedPiece setup{test_support::AcTable(), test_support::Turning()};
  auto laser = RunInstrumentValidation(setup, SmallInstrumentStudy({"none"}, 1), {.instrument = "laser", .noise_um = 0.5});
  ASSERT_FALSE(laser.ok());
  EXPECT_NE(laser.status().message().find("expected datum_ball, probe_artifacts or ballbar"), std::string::npos)
      << laser.status().ToString();
  auto noise = RunInstrumentValidation(setup, SmallInstrumentStudy({"none"}, 1), {.instrument = "datum_ball", .noise_um = -1});
  ASSERT_FALSE(noise.ok());
  EXPECT_NE(noise.status().message().find("--reference-noise-um"), std::string::npos) << noise.status().ToString();
}

}  // namespace
}  // namespace tpcal::pipeline
