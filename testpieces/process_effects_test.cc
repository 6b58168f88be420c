#include "testpieces/process_effects.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "kinematics/error_state.h"
#include "testpieces/simulate_piece.h"

namespace tpcal::testpieces {
namespace {

// Exact data in double precision: deviations are sums of a few products.
constexpr double kExactTol_um = 1e-9;

struct Fixture {
  kinematics::MachineModel machine;
  TestPiece piece;
  ProbingPlan plan;
};

Fixture MakeProcessPiece() {
  auto m = kinematics::MakeMachine(kinematics::MachineType::kAcTable);
  EXPECT_TRUE(m.ok());
  auto piece = MakeTestPiece(PieceConfig{}, *m);
  EXPECT_TRUE(piece.ok()) << piece.status().message();
  auto plan = MakeProbingPlan(*piece);
  EXPECT_TRUE(plan.ok());
  return {*m, *piece, *plan};
}

const PlanPoint* FindPoint(const ProbingPlan& plan, const std::string& feature, double azimuth_deg) {
  for (const auto& pp : plan.points) {
    if (pp.feature != feature) continue;
    const double az = RadToDeg(std::atan2(pp.point_part_mm.y(), pp.point_part_mm.x()));
    if (std::abs(std::remainder(az - azimuth_deg, 360.0)) < 1e-6) return &pp;
  }
  return nullptr;
}

TEST(ProcessEffects, NoEffectsNoDeviation) {
  const Fixture f = MakeProcessPiece();
  for (const auto& pp : f.plan.points) {
    auto d = ProcessDeviationMm(f.piece, f.machine, pp, ProcessEffects{});
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(*d, 0.0);
  }
}

// A turning tool pushed away from the part leaves material: every turned face gets s > 0 with a
// positive compliance; the reamer's radial forces balance (holes unchanged).
TEST(ProcessEffects, DeflectionLeavesMaterialOnTurnedFacesNotInHoles) {
  const Fixture f = MakeProcessPiece();
  ProcessEffects e;
  e.deflection = ToolDeflectionModel{};
  for (const auto& pp : f.plan.points) {
    auto d = ProcessDeviationMm(f.piece, f.machine, pp, e);
    ASSERT_TRUE(d.ok()) << d.status().message();
    const FeatureCut* fc = f.piece.Cut(pp.feature);
    ASSERT_NE(fc, nullptr);
    if (std::holds_alternative<PlungeCut>(fc->model)) {
      EXPECT_EQ(*d, 0.0) << pp.feature;
    }
    // Side faces: passive force along +n dominates the tangential one's projection (diagonal compliance).
    if (const auto* t = std::get_if<TurnedCut>(&fc->model); t && !t->radial_feed) {
      EXPECT_GT(*d, 0.0) << pp.feature;
    }
  }
  // S1 at azimuth 0 (tool at +X, A = 0): the normal is machine +X, the force on the tool
  // Fc (tangent +Y) + Fp (+X) + Ff (+Z); s = n . C F = c_x Fp.
  const PlanPoint* s1 = FindPoint(f.plan, "S1", 0.0);
  ASSERT_NE(s1, nullptr);
  auto d = ProcessDeviationMm(f.piece, f.machine, *s1, e);
  ASSERT_TRUE(d.ok());
  const ToolDeflectionModel m;
  const double fc = m.specific_force_n_per_mm2 * 0.8 * 0.2;
  EXPECT_NEAR(MmToUm(*d), m.compliance_um_per_n.x() * m.passive_ratio * fc, kExactTol_um);
}

// The quadrant glitch of the groove wall S_R (CCW climb pass at A = C = 0): at the X reversal at
// azimuth 0 the tool path protrudes +X by h, cutting into the wall whose normal points to the
// axis (-X): s = -h. It decays with the travelled angle, and the points before the first
// crossing of the pass see nothing.
TEST(ProcessEffects, ServoGlitchAtQuadrantCrossingOfTheGroove) {
  const Fixture f = MakeProcessPiece();
  ProcessEffects e;
  ServoReversalModel m;
  m.spike_x_um = 2.0;
  m.spike_y_um = 0.0;
  m.decay_deg = 5.0;
  e.servo = m;
  double max_abs_um = 0.0;
  std::string feature_of_max;
  for (const auto& pp : f.plan.points) {
    auto d = ProcessDeviationMm(f.piece, f.machine, pp, e);
    ASSERT_TRUE(d.ok());
    if (std::abs(MmToUm(*d)) > max_abs_um) max_abs_um = std::abs(MmToUm(*d)), feature_of_max = pp.feature;
    const FeatureCut* fc = f.piece.Cut(pp.feature);
    if (!std::holds_alternative<PathMillCut>(fc->model)) {
      EXPECT_EQ(*d, 0.0) << pp.feature;
    }
  }
  EXPECT_EQ(feature_of_max, "S_R");
  EXPECT_LE(max_abs_um, 2.0 + kExactTol_um);
  // The wall point whose tool-centre azimuth is just past a reversal carries (nearly) the full glitch.
  EXPECT_GT(max_abs_um, 2.0 * std::exp(-22.5 / 5.0) - kExactTol_um);
}

TEST(ProcessEffects, SimulatePieceAddsProcessDeviationAlongTheNormal) {
  const Fixture f = MakeProcessPiece();
  PieceSimOptions o;
  o.process.deflection = ToolDeflectionModel{};
  const kinematics::ErrorState zero(f.machine);
  auto sim = SimulatePiece(f.piece, f.machine, zero, o);
  ASSERT_TRUE(sim.ok()) << sim.status().message();
  for (std::size_t i = 0; i < f.plan.points.size(); ++i) {
    auto d = ProcessDeviationMm(f.piece, f.machine, f.plan.points[i], o.process);
    ASSERT_TRUE(d.ok());
    EXPECT_NEAR(MmToUm(sim->truth.deviation_mm[i]), MmToUm(*d), 1e-6);  // exact solve tolerance 1e-10 mm
  }
}

TEST(ProcessEffects, InvalidModelsAreRejected) {
  ProcessEffects e;
  e.servo = ServoReversalModel{};
  e.servo->decay_deg = 0.0;
  EXPECT_FALSE(e.Validate().ok());
  ProcessEffects d;
  d.deflection = ToolDeflectionModel{};
  d.deflection->compliance_um_per_n.x() = -1.0;
  EXPECT_FALSE(d.Validate().ok());
}

}  // namespace
}  // namespace tpcal::testpieces
