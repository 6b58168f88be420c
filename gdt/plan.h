// InspectionPlan: what to fit and what to evaluate, as value types (no YAML here; the YAML
// schema that fills these is gdt/PLAN_FORMAT.md, loaded by gdt/plan_yaml.h).
//
// A plan names features (labels of the point file, docs/formats/points.md), says which
// primitive each is fitted as, how the datum reference frame is built from some of them, and
// lists the characteristics (ISO 1101 concentricity, parallelism, ...) with their nominals.
// Every spec keeps the 1-based line of the plan file it came from (0 when built in code), so
// evaluation errors can cite "plan.yaml:LINE".
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace tpcal::gdt {

// Primitive a feature's points are fitted as. kPoint is the centroid of the points (a probed
// point, or the tertiary datum of a 3-2-1 frame). kPitchCircle is derived, not probed: the
// least-squares circle through the centres of its member circle features (a hole pattern).
enum class FeatureKind { kLine2, kLine3, kPlane, kCircle, kCylinder, kSphere, kCone, kPoint, kPitchCircle };

// Where a 2D primitive (line2, circle, pitch_circle) is fitted. kDatumXY: points projected
// into the datum frame's XY plane (their datum z is dropped), kDatumYZ into YZ, kDatumZX into
// ZX; in-plane coordinates (u, v) are (x, y), (y, z), (z, x) respectively (right-handed with
// the plane normal +Z, +X, +Y). kNone (circle only): a 3D circle in the points' own LS plane.
enum class Projection { kNone, kDatumXY, kDatumYZ, kDatumZX };

// Form criterion of a form value: least squares (Gaussian, max - min residual about the LS
// feature) or minimum zone (Chebyshev, ISO 1101 default), from fitting/minimum_zone*.
enum class FormCriterion { kLeastSquares, kMinimumZone };

enum class CharacteristicType {
  kConcentricity,   // ISO 1101 concentricity / coaxiality of a centre point to a datum centre
  kParallelism,     // orientation of a plane (line) to a datum plane (line)
  kSquareness,      // ISO 1101 perpendicularity
  kCircularity,     // roundness, with the profile dr(theta)
  kFlatness,
  kStraightness,
  kPosition,        // of a centre versus its nominal location in the datum frame
  kPlaneDistance,   // signed distance of a plane from a datum plane, error versus nominal
  kSize,            // radius / diameter error versus nominal
  kHolePattern,     // pitch circle of a pattern: centre, radius, angular position of each hole
};

const char* FeatureKindName(FeatureKind k);          // "line2", "plane", "pitch_circle", ...
const char* ProjectionName(Projection p);            // "none", "datum_xy", ...
const char* FormCriterionName(FormCriterion c);      // "ls", "mz"
const char* CharacteristicTypeName(CharacteristicType t);  // "concentricity", "plane_distance", ...
std::optional<FeatureKind> ParseFeatureKind(std::string_view s);
std::optional<Projection> ParseProjection(std::string_view s);
std::optional<FormCriterion> ParseFormCriterion(std::string_view s);
std::optional<CharacteristicType> ParseCharacteristicType(std::string_view s);

// Minimum number of points (members for kPitchCircle) a feature kind needs to be fitted.
std::size_t MinPoints(FeatureKind k);

struct FeatureSpec {
  std::string name{};  // the point file's feature label (for kPitchCircle: a new name)
  FeatureKind kind = FeatureKind::kPlane;
  // Line2 / circle / pitch_circle: projection plane (default datum XY). Other kinds: kNone.
  Projection projection = Projection::kNone;
  FormCriterion form_criterion = FormCriterion::kLeastSquares;
  // Sense of a plane normal, line direction or cylinder axis, in the datum frame (need not be
  // unit). Without it: plane normals, cylinder/circle axes point along the datum axis of their
  // largest component (positive); lines keep the fitter's rule (first -> last probed point).
  std::optional<Eigen::Vector3d> nominal_direction{};
  std::vector<std::string> members{};  // kPitchCircle only: the circle features whose centres it fits
  std::size_t line = 0;
};

// How the sense of a datum axis is fixed. Never from the CMM frame: the part may sit anywhere.
struct AxisSense {
  enum class Rule {
    kPointNormals,  // along the mean of the feature's point normals (i, j, k: out of the material)
    kAwayFrom,      // +axis points away from the centroid of `feature`'s points
    kToward,        // +axis points toward the centroid of `feature`'s points
    kPointOrder,    // (lines only) from the first toward the last probed point
  };
  Rule rule = Rule::kPointNormals;
  std::string feature{};  // for kAwayFrom / kToward
};

enum class DatumFrameType {
  // Seed 002 section 2.2: Z = normal of the LS plane of `primary`, z = 0 on it; XY origin at
  // the LS centre of `center` (circle projected into that plane); +X toward the centre of
  // `x_toward` (circle projected into that plane, or point / sphere centre).
  kTurning,
  // 3-2-1: Z = normal of `primary` (plane), z = 0 on it; +X along `secondary` (line3)
  // projected into the primary plane, y = 0 on it; x = 0 at the foot of `tertiary` (point,
  // sphere or circle centre) on that line.
  kThreeTwoOne,
  // Datum targets (ISO 5459 datum target areas), for pieces whose probed features alone do not
  // fix a 3-2-1 or turning frame: Z = normal of `primary` (plane) or axis of its 3D LS circle
  // (circle), z = 0 on it; origin at the centre of `center` (circle / sphere centre, else the
  // centroid of its probed points); +X (`x_toward`) or +Y (`y_toward`) toward the centre of that
  // feature, or toward its first probed point with `toward_first_point` (the azimuth of a
  // surface of revolution, which only the probing order carries).
  kTargets,
};
const char* DatumFrameTypeName(DatumFrameType t);  // "turning", "3-2-1", "targets"

struct DatumFrameSpec {
  DatumFrameType type = DatumFrameType::kTurning;
  std::string primary{};    // plane feature
  std::string center{};     // kTurning: circle feature for the XY origin
  std::string x_toward{};   // kTurning: feature whose centre sets +X
  std::string secondary{};  // kThreeTwoOne: line3 feature
  std::string tertiary{};   // kThreeTwoOne: point / sphere / circle feature
  std::string y_toward{};   // kTargets: feature whose centre (first point) sets +Y, instead of x_toward
  bool toward_first_point = false;  // kTargets: aim at the first probed point, not the centre
  AxisSense z_sense{};      // sense of +Z (primary normal)
  AxisSense x_sense{AxisSense::Rule::kPointOrder, {}};  // kThreeTwoOne: sense of +X
  std::size_t line = 0;
};

struct CharacteristicSpec {
  std::string name{};  // unique within the plan
  CharacteristicType type = CharacteristicType::kFlatness;
  std::string feature{};  // the toleranced feature
  std::string datum{};    // the datum feature (concentricity, parallelism, squareness, plane_distance)
  std::string symbol{};       // free text, e.g. the paper's symbol "dx_{S4,SR}, dy_{S4,SR}"
  std::string description{};  // free text
  Projection plane = Projection::kDatumXY;  // concentricity / position / hole_pattern plane
  std::optional<FormCriterion> criterion{};   // circularity / flatness / straightness (default: the feature's)
  // Nominals (units in the names). Which are required depends on `type` (PLAN_FORMAT.md).
  std::optional<double> nominal_radius_mm{};
  std::optional<double> nominal_diameter_mm{};
  std::optional<double> nominal_distance_mm{};
  std::optional<Eigen::Vector2d> nominal_xy_mm{};   // position in `plane` coordinates (u, v)
  std::optional<Eigen::Vector3d> nominal_xyz_mm{};  // 3D position in the datum frame
  std::optional<double> nominal_angle_deg{};        // position: polar nominal with nominal_radius_mm
  std::optional<double> first_angle_deg{};          // hole_pattern: nominal angle of the first member
  std::optional<double> pitch_deg{};                // hole_pattern: nominal angular pitch
  std::vector<double> nominal_angles_deg{};         // hole_pattern: one nominal angle per member
  std::size_t line = 0;
};

// A named nominal the plan carries for later layers (e.g. seed 002's heights z_i of the faces
// above the A axis, used by the machine-error equations 10-27). The name ends with its unit:
// _mm, _um, _deg, _rad, _urad, or _count for a pure number.
struct PlanNominal {
  std::string name{};
  double value = 0;
  std::size_t line = 0;
};

struct InspectionPlan {
  std::string source{};  // file name, for messages
  std::string name{};
  std::vector<PlanNominal> nominals{};
  std::optional<DatumFrameSpec> datum_frame{};  // none: everything is evaluated in the CMM frame
  std::vector<FeatureSpec> features{};
  std::vector<CharacteristicSpec> characteristics{};

  const FeatureSpec* FindFeature(const std::string& name) const;
  std::optional<double> Nominal(const std::string& name) const;  // nullopt if absent
};

// Checks names are unique, every reference resolves to a feature of a kind the use accepts,
// and the nominals a characteristic needs are present. Errors (kInvalidArgument) cite
// plan.source and the line of the offending spec.
Status ValidatePlan(const InspectionPlan& plan);

}  // namespace tpcal::gdt
