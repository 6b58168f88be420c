// Process effects of the virtual machining that are not machine geometry: where the cut surface
// ends up because of cutting forces (tool / spindle compliance) and servo behaviour at axis
// reversals of circular interpolation. They complement the kinematic simulation
// (kinematics/simulate.h, machine errors through the chain) in SimulatePiece, so the diagnosis
// of the sim-to-real gap can be validated on effects it is not told about.
//
// Sign convention: the result is the normal deviation s (along the nominal OUTWARD normal n0,
// part frame, + = material left outside the nominal surface). A tool displaced by d relative to
// the part while cutting leaves the surface displaced by d too, so s = n0 . d (d in the part
// frame). Compliance and servo errors are defined in the MACHINE frame (the frame of the linear
// axes); d_part = part_from_machine rotation * d_machine at the cut's nominal axis state.
//
// Tool deflection (static, per cut): the cutting force on the tool (from the part), in the part
// frame, F = Fc t + Fp n0 + Ff f with
//  - turned faces (TurnedCut): chip area = depth_of_cut * feed_per_rev (the piece's parameters),
//    Fc = Kc * area, Fp = passive_ratio Fc, Ff = feed_ratio Fc; t = surface velocity of the
//    spinning part at the contact (+C table rotation: t = z x radial), f = opposite to the feed
//    (side faces fed toward the shoulder: +z; bottom faces fed toward the axis: +radial);
//  - side-milled walls (PathMillCut, !end_face): radial engagement = finish stock, mean chip
//    thickness h_m = f_z sqrt(a_e / D), Fc = Kc * a_p * h_m, Fp (radial, away from the wall)
//    = passive_ratio Fc, Ff opposes the path tangent (feed_ratio Fc);
//  - end-milled floors: axial force only (passive_ratio * Kc * floor_axial_area_mm2);
//  - reamed holes and flank-milled cones: balanced radial forces, no deflection.
// The tool displacement is d_machine = diag(compliance_um_per_n) F_machine (um), times `scale`.
//
// Servo reversal (circular interpolation in the machine X-Y plane, PathMillCut arcs): when an
// axis reverses (X at the arc's +-X extremes, Y at +-Y), static friction makes it stall: the
// path protrudes outward along that axis by h_axis exp(-phi / decay), phi = angle travelled since
// the crossing (crossings before the arc start are not traversed); plus a lost-motion step
// (backlash): after the reversal of an axis its position lags by backlash_axis / 2 against the
// new direction of motion until the next reversal. Only crossings within the arc count.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/status.h"
#include "kinematics/machine_model.h"
#include "testpieces/probing_plan.h"
#include "testpieces/test_piece.h"

namespace tpcal::testpieces {

struct ToolDeflectionModel {
  double specific_force_n_per_mm2 = 2000.0;  // Kc, steel
  double passive_ratio = 0.4;                // Fp / Fc
  double feed_ratio = 0.3;                   // Ff / Fc
  double floor_axial_area_mm2 = 0.02;        // end-milled floors: equivalent chip area
  // Tool-side compliance along machine X, Y, Z (um per N), > 0.
  Eigen::Vector3d compliance_um_per_n = Eigen::Vector3d(0.02, 0.025, 0.01);
  double scale = 1.0;                        // multiplies the deflection (validation sweeps)
  Status Validate() const;
};

struct ServoReversalModel {
  double spike_x_um = 0.0;     // quadrant glitch height when X reverses, >= 0 outward
  double spike_y_um = 0.0;     // ... when Y reverses
  double decay_deg = 4.0;      // exponential decay of the glitch with travelled angle, > 0
  double backlash_x_um = 0.0;  // lost motion of X (full value)
  double backlash_y_um = 0.0;
  Status Validate() const;
};

struct ProcessEffects {
  std::optional<ToolDeflectionModel> deflection;
  std::optional<ServoReversalModel> servo;
  bool empty() const { return !deflection && !servo; }
  Status Validate() const;
};

// Where a point of a side-milled circular path lies on its arc, seen from machine +Z: the
// machine-frame azimuth of the tool centre (theta, rad), the arc start azimuth, the direction of
// travel (+1 counter-clockwise from +Z, -1 clockwise), the swept angle. nullopt when the feature is
// not side-milled on an arc in the machine X-Y plane. Shared geometry of the servo model and the
// diagnosis's servo candidate.
struct ArcTravel {
  double theta_rad = 0.0, theta_start_rad = 0.0, direction = 1.0, sweep_rad = 0.0;
};
std::optional<ArcTravel> ArcTravelAt(const FeatureCut& cut, const Eigen::Vector3d& point_part_mm,
                                     const Eigen::Matrix3d& machine_from_part);

// The normal deviation (mm, along the point's nominal outward normal) that `effects` add to the
// plan point `pp` of `piece` cut on `machine` (nominal kinematics for the part/machine rotation).
// Errors: kInvalidArgument for an invalid model or a feature without a cut.
Result<double> ProcessDeviationMm(const TestPiece& piece, const kinematics::MachineModel& machine,
                                  const PlanPoint& pp, const ProcessEffects& effects);

}  // namespace tpcal::testpieces
