// Plan-driven inspection: from CMM points (CMM frame, any placement of the part) to the datum
// frame, the fitted features and the characteristics of an InspectionPlan.
//
// Steps of EvaluatePlan:
//  1. ValidatePlan; every point feature of the plan must have points in the PointSet, at
//     least MinPoints(kind) of them (else kTooFewPoints citing the PointSet source and the
//     line of the feature's first point).
//  2. The datum frame, from the datum features fitted in the CMM frame (gdt/datum_frame.h);
//     identity (the CMM frame) when the plan has none.
//  3. Every point is moved into the datum frame; every feature is fitted there (so results
//     do not depend on where the part sat on the CMM), then pitch circles from their members.
//  4. Characteristics in plan order (gdt/characteristic.h).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/frames.h"
#include "core/point_set.h"
#include "core/status.h"
#include "fitting/fit_result.h"
#include "gdt/characteristic.h"
#include "gdt/fitted_feature.h"
#include "gdt/plan.h"

namespace tpcal::gdt {

struct EvaluateOptions {
  fitting::FitOptions fit;  // passed to every fit (defaults of fitting/fit_result.h)
  Status Validate() const { return fit.Validate(); }
};

struct InspectionResult {
  std::string plan_name;
  std::string plan_source;
  std::string points_source;
  std::optional<DatumFrameType> frame_type;    // nullopt: no datum frame, datum = CMM frame
  Rigid3 datum_from_cmm = Rigid3::Identity();  // p_in_datum = datum_from_cmm * p_in_cmm
  std::vector<FittedFeature> features;         // plan order, then pitch circles; datum frame
  std::vector<CharacteristicResult> characteristics;  // plan order

  const FittedFeature* Feature(const std::string& name) const;
  const CharacteristicResult* Characteristic(const std::string& name) const;
};

// Errors: ValidatePlan's; kInvalidArgument citing the plan line when a feature has no points;
// kTooFewPoints citing the point file line of its first point; fit errors (feature named,
// point file location); datum frame errors (kDegenerate: an axis sense that does not decide,
// a frame axis that cannot be built); characteristic errors citing the plan line.
Result<InspectionResult> EvaluatePlan(const InspectionPlan& plan, const PointSet& points,
                                      const EvaluateOptions& options = {});

struct AdHocOptions {
  // Kind of named features. A feature not listed gets its kind from the point normals when
  // the PointSet has them (plane: normals all alike; circle: normals radial in one plane with
  // coplanar points; cylinder: radial, points not coplanar; sphere otherwise); without
  // normals a kind must be given.
  std::map<std::string, FeatureKind> kinds;
  // Optional datum frame (its features need kinds too); without it everything stays in the
  // CMM frame, circles are fitted as 3D circles and line2 in the CMM XY plane.
  std::optional<DatumFrameSpec> datum_frame;
  EvaluateOptions evaluate;
};

// Fits every labelled feature of `points` (ad-hoc evaluation, no characteristics).
// Errors: kInvalidArgument for a kind given for a feature without points, or a feature whose
// kind can be neither found nor inferred; then EvaluatePlan's.
Result<InspectionResult> EvaluateAdHoc(const PointSet& points, const AdHocOptions& options);

// The plan EvaluateAdHoc runs (for reports and the CLI to print).
Result<InspectionPlan> AdHocPlan(const PointSet& points, const AdHocOptions& options);

}  // namespace tpcal::gdt
