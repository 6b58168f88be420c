#include "gdt/inspection.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <set>

#include "fitting/circle_fit.h"
#include "fitting/line_fit.h"
#include "fitting/plane_fit.h"
#include "fitting/sphere_fit.h"
#include "gdt/datum_frame.h"

namespace tpcal::gdt {
namespace {

struct FeaturePoints {
  std::vector<std::size_t> indices;
  std::size_t first_line = 0;
};

using PointsByFeature = std::map<std::string, FeaturePoints>;

Status PlanError(const InspectionPlan& plan, std::size_t line, const std::string& msg) {
  return Status(StatusCode::kInvalidArgument, msg, plan.source, line);
}

// Adds a location unless the status already carries one.
Status Locate(const Status& s, const std::string& file, std::size_t line) {
  return s.file().empty() ? s.WithLocation(file, line) : s;
}

std::string Plural(std::size_t n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// A feature of the plan without points: cited at its plan line when the plan is a file, else at
// the point file (the plan of a test piece has no lines).
Status NoPointsOf(const InspectionPlan& plan, const FeatureSpec& f, const PointSet& ps) {
  const std::string expected = "; expected at least " + Plural(MinPoints(f.kind), "point") + " labelled '" + f.name +
                               "' (a " + FeatureKindName(f.kind) + ")";
  const std::string points = ps.source.empty() ? std::string("the point set") : ps.source;
  if (f.line != 0 || ps.source.empty())
    return PlanError(plan, f.line, "feature '" + f.name + "' has no points in " + points + expected);
  return Status(StatusCode::kInvalidArgument,
                "feature '" + f.name + "' of the inspection plan of the " + plan.name + " has no points" + expected,
                ps.source);
}

Result<PointsByFeature> CollectPoints(const InspectionPlan& plan, const PointSet& ps) {
  PointsByFeature out;
  for (const FeatureSpec& f : plan.features) {
    if (f.kind == FeatureKind::kPitchCircle) continue;
    FeaturePoints fp;
    fp.indices = ps.IndicesOf(f.name);
    if (fp.indices.empty()) return NoPointsOf(plan, f, ps);
    fp.first_line = ps.LineOf(fp.indices.front());
    if (fp.indices.size() < MinPoints(f.kind))
      return Status(StatusCode::kTooFewPoints,
                    "feature '" + f.name + "' has " + Plural(fp.indices.size(), "point") + " (its first point is here)"
                        ", a " + FeatureKindName(f.kind) + " fit needs at least " + std::to_string(MinPoints(f.kind)),
                    ps.source, fp.first_line);
    out.emplace(f.name, std::move(fp));
  }
  return out;
}

std::vector<Eigen::Vector3d> Coords(const PointSet& ps, const std::vector<std::size_t>& idx) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(idx.size());
  for (std::size_t i : idx) out.push_back(ps.xyz_mm[i]);
  return out;
}

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p;
  return pts.empty() ? c : Eigen::Vector3d(c / static_cast<double>(pts.size()));
}

// Frame-building context: CMM-frame points of the plan's features.
class FrameBuilder {
 public:
  FrameBuilder(const InspectionPlan& plan, const PointSet& ps, const PointsByFeature& pts,
               const fitting::FitOptions& options)
      : plan_(plan), ps_(ps), pts_(pts), options_(options), spec_(*plan.datum_frame) {}

  Result<Rigid3> Build() {
    if (spec_.type == DatumFrameType::kTargets) return BuildTargets();
    auto primary = FitPrimary();
    if (!primary.ok()) return primary.status();
    if (spec_.type == DatumFrameType::kTurning) {
      auto center = ProjectedCircleCenter(Points(spec_.center), *primary, options_);
      if (!center.ok()) return FitError(center.status(), spec_.center, "the centre circle");
      auto target = CentreOf(spec_.x_toward, &*primary);
      if (!target.ok()) return target.status();
      auto frame = TurningDatumFromCmm(*primary, *center, *target);
      if (!frame.ok()) return PlanError(plan_, spec_.line, frame.status().message());
      return frame;
    }
    auto line = fitting::FitLine3(Points(spec_.secondary), options_);
    if (!line.ok()) return FitError(line.status(), spec_.secondary, "the secondary line");
    auto sense = Sense(spec_.x_sense, line->feature.point_mm, spec_.secondary);
    if (!sense.ok()) return sense.status();
    auto x = OrientAlong(line->feature.direction, *sense, "datum X (secondary line direction)");
    if (!x.ok()) return PlanError(plan_, spec_.line, x.status().message());
    fitting::Line3 secondary = line->feature;
    secondary.direction = *x;
    auto tertiary = CentreOf(spec_.tertiary, nullptr);
    if (!tertiary.ok()) return tertiary.status();
    auto frame = ThreeTwoOneDatumFromCmm(*primary, secondary, *tertiary);
    if (!frame.ok()) return PlanError(plan_, spec_.line, frame.status().message());
    return frame;
  }

 private:
  std::vector<Eigen::Vector3d> Points(const std::string& name) const { return Coords(ps_, pts_.at(name).indices); }

  Status FitError(const Status& s, const std::string& feature, const std::string& role) const {
    return Locate(s.WithContext("datum frame: " + role + " '" + feature + "'"), ps_.source,
                  pts_.at(feature).first_line);
  }

  // Plan type `targets` (gdt/plan.h DatumFrameType::kTargets).
  Result<Rigid3> BuildTargets() {
    fitting::Plane primary;
    if (plan_.FindFeature(spec_.primary)->kind == FeatureKind::kCircle) {
      auto circle = fitting::FitCircle3(Points(spec_.primary), options_);
      if (!circle.ok()) return FitError(circle.status(), spec_.primary, "the primary circle");
      primary.point_mm = circle->feature.center_mm;
      primary.normal = circle->feature.axis;
      auto sense = Sense(spec_.z_sense, primary.point_mm, spec_.primary);
      if (!sense.ok()) return sense.status();
      auto z = OrientAlong(primary.normal, *sense, "datum Z (primary circle axis)");
      if (!z.ok()) return PlanError(plan_, spec_.line, z.status().message());
      primary.normal = *z;
    } else {
      auto plane = FitPrimary();
      if (!plane.ok()) return plane.status();
      primary = *plane;
    }
    auto center = TargetOf(spec_.center, primary, false);
    if (!center.ok()) return center.status();
    const bool sets_y = spec_.x_toward.empty();
    auto target = TargetOf(sets_y ? spec_.y_toward : spec_.x_toward, primary, spec_.toward_first_point);
    if (!target.ok()) return target.status();
    auto frame = TargetsDatumFromCmm(primary, *center, *target, sets_y);
    if (!frame.ok()) return PlanError(plan_, spec_.line, frame.status().message());
    return frame;
  }

  // A datum target (CMM frame): the first probed point of `name`, or its centre (circles
  // projected into `primary`, spheres and points by CentreOf), else the centroid of its points.
  Result<Eigen::Vector3d> TargetOf(const std::string& name, const fitting::Plane& primary, bool first_point) const {
    const auto pts = Points(name);
    if (first_point) return pts.front();
    switch (plan_.FindFeature(name)->kind) {
      case FeatureKind::kCircle:
      case FeatureKind::kSphere:
      case FeatureKind::kPoint: return CentreOf(name, &primary);
      default: return Centroid(pts);
    }
  }

  Result<fitting::Plane> FitPrimary() {
    auto plane = fitting::FitPlane(Points(spec_.primary), options_);
    if (!plane.ok()) return FitError(plane.status(), spec_.primary, "the primary plane");
    auto sense = Sense(spec_.z_sense, plane->feature.point_mm, spec_.primary);
    if (!sense.ok()) return sense.status();
    auto z = OrientAlong(plane->feature.normal, *sense, "datum Z (primary plane normal)");
    if (!z.ok()) return PlanError(plan_, spec_.line, z.status().message());
    fitting::Plane p = plane->feature;
    p.normal = *z;
    return p;
  }

  // The sense vector (CMM frame) of an axis anchored at `anchor` on feature `own`.
  Result<Eigen::Vector3d> Sense(const AxisSense& s, const Eigen::Vector3d& anchor, const std::string& own) const {
    switch (s.rule) {
      case AxisSense::Rule::kPointNormals: {
        if (!ps_.has_normals())
          return PlanError(plan_, spec_.line, "datum frame: the point_normals sense rule needs normals (i,j,k) in " +
                                                  ps_.source + "; give away_from or toward a feature instead");
        Eigen::Vector3d m = Eigen::Vector3d::Zero();
        for (std::size_t i : pts_.at(own).indices) m += ps_.normal[i];
        return m;
      }
      case AxisSense::Rule::kAwayFrom: return Eigen::Vector3d(anchor - Centroid(Points(s.feature)));
      case AxisSense::Rule::kToward: return Eigen::Vector3d(Centroid(Points(s.feature)) - anchor);
      case AxisSense::Rule::kPointOrder: {
        const auto p = Points(own);
        return Eigen::Vector3d(p.back() - p.front());
      }
    }
    return Eigen::Vector3d(Eigen::Vector3d::Zero());
  }

  // Centre (CMM frame) of a circle, sphere or point feature; circles are projected into
  // `plane` when given (turning frame), else fitted as 3D circles.
  Result<Eigen::Vector3d> CentreOf(const std::string& name, const fitting::Plane* plane) const {
    const FeatureSpec* f = plan_.FindFeature(name);
    const auto pts = Points(name);
    switch (f->kind) {
      case FeatureKind::kPoint: return Centroid(pts);
      case FeatureKind::kSphere: {
        auto s = fitting::FitSphere(pts, options_);
        if (!s.ok()) return FitError(s.status(), name, "the sphere");
        return s->feature.center_mm;
      }
      case FeatureKind::kCircle: {
        if (plane != nullptr) {
          auto c = ProjectedCircleCenter(pts, *plane, options_);
          if (!c.ok()) return FitError(c.status(), name, "the circle");
          return *c;
        }
        auto c = fitting::FitCircle3(pts, options_);
        if (!c.ok()) return FitError(c.status(), name, "the circle");
        return c->feature.center_mm;
      }
      default: break;
    }
    return PlanError(plan_, spec_.line, "datum frame: feature '" + name + "' has no centre");
  }

  const InspectionPlan& plan_;
  const PointSet& ps_;
  const PointsByFeature& pts_;
  const fitting::FitOptions& options_;
  const DatumFrameSpec& spec_;
};

// Kind of a feature from its point normals (AdHocOptions::kinds).
Result<FeatureKind> InferKind(const PointSet& ps, const std::string& name, const std::vector<std::size_t>& idx) {
  constexpr double kPlaneMeanNormal = 0.996;  // |mean normal| >= cos(5 deg): all normals alike
  constexpr double kRadialSpread = 0.05;      // normals within ~3 deg of one plane: surface of revolution
  constexpr double kCoplanarRatio = 0.01;     // extent along the axis / radial extent: a circle
  if (idx.size() < 3)
    return Status(StatusCode::kInvalidArgument, "feature '" + name + "': too few points to infer its kind; give it");
  Eigen::MatrixXd n(static_cast<Eigen::Index>(idx.size()), 3);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < idx.size(); ++k) {
    n.row(static_cast<Eigen::Index>(k)) = ps.normal[idx[k]].transpose();
    mean += ps.normal[idx[k]];
  }
  mean /= static_cast<double>(idx.size());
  if (mean.norm() >= kPlaneMeanNormal) return FeatureKind::kPlane;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(n, Eigen::ComputeFullV);
  const double s_min = svd.singularValues()(2) / std::sqrt(static_cast<double>(idx.size()));
  if (s_min > kRadialSpread) return FeatureKind::kSphere;
  const Eigen::Vector3d axis = svd.matrixV().col(2);
  std::vector<Eigen::Vector3d> pts = Coords(ps, idx);
  const Eigen::Vector3d c = Centroid(pts);
  double lo = 0, hi = 0, radial = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double t = axis.dot(pts[k] - c);
    lo = k == 0 ? t : std::min(lo, t);
    hi = k == 0 ? t : std::max(hi, t);
    radial = std::max(radial, (pts[k] - c - axis * t).norm());
  }
  return hi - lo <= kCoplanarRatio * radial ? FeatureKind::kCircle : FeatureKind::kCylinder;
}

}  // namespace

const FittedFeature* InspectionResult::Feature(const std::string& name) const {
  for (const FittedFeature& f : features)
    if (f.name == name) return &f;
  return nullptr;
}

const CharacteristicResult* InspectionResult::Characteristic(const std::string& name) const {
  for (const CharacteristicResult& c : characteristics)
    if (c.name == name) return &c;
  return nullptr;
}

Result<InspectionResult> EvaluatePlan(const InspectionPlan& plan, const PointSet& ps, const EvaluateOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(ValidatePlan(plan));
  if (ps.feature.size() != ps.size())
    return Status(StatusCode::kInvalidArgument, "point set has " + std::to_string(ps.size()) + " points but " +
                                                    std::to_string(ps.feature.size()) + " labels", ps.source);
  auto points = CollectPoints(plan, ps);
  if (!points.ok()) return points.status();

  InspectionResult out;
  out.plan_name = plan.name;
  out.plan_source = plan.source;
  out.points_source = ps.source;
  if (plan.datum_frame) {
    FrameBuilder builder(plan, ps, *points, options.fit);
    auto frame = builder.Build();
    if (!frame.ok()) return frame.status();
    out.frame_type = plan.datum_frame->type;
    out.datum_from_cmm = *frame;
  }

  std::vector<Eigen::Vector3d> points_datum;
  points_datum.reserve(ps.size());
  for (const auto& p : ps.xyz_mm) points_datum.push_back(out.datum_from_cmm * p);

  for (const FeatureSpec& spec : plan.features) {
    if (spec.kind == FeatureKind::kPitchCircle) continue;
    const FeaturePoints& fp = points->at(spec.name);
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(fp.indices.size());
    for (std::size_t i : fp.indices) pts.push_back(points_datum[i]);
    auto fitted = FitFeature(spec, pts, fp.indices, fp.first_line, options.fit);
    if (!fitted.ok()) return Locate(fitted.status(), ps.source, fp.first_line);
    out.features.push_back(std::move(*fitted));
  }
  for (const FeatureSpec& spec : plan.features) {
    if (spec.kind != FeatureKind::kPitchCircle) continue;
    std::vector<const FittedFeature*> members;
    for (const std::string& m : spec.members) members.push_back(out.Feature(m));
    auto fitted = FitPitchCircle(spec, members, options.fit);
    if (!fitted.ok()) return Locate(fitted.status(), plan.source, spec.line);
    out.features.push_back(std::move(*fitted));
  }

  std::map<std::string, const FittedFeature*> by_name;
  for (const FittedFeature& f : out.features) by_name[f.name] = &f;
  for (const CharacteristicSpec& spec : plan.characteristics) {
    auto c = EvaluateCharacteristic(spec, by_name, points_datum);
    if (!c.ok()) return Locate(c.status(), plan.source, spec.line);
    out.characteristics.push_back(std::move(*c));
  }
  return out;
}

Result<InspectionPlan> AdHocPlan(const PointSet& ps, const AdHocOptions& options) {
  InspectionPlan plan;
  plan.source = "ad-hoc plan";
  plan.name = "ad-hoc: every labelled feature of " + ps.source;
  plan.datum_frame = options.datum_frame;
  for (const auto& [name, kind] : options.kinds) {
    if (ps.IndicesOf(name).empty())
      return Status(StatusCode::kInvalidArgument, "a kind is given for feature '" + name + "', which has no points in " +
                                                      ps.source);
    if (kind == FeatureKind::kPitchCircle)
      return Status(StatusCode::kInvalidArgument, "feature '" + name + "': pitch_circle needs a plan (members)");
  }
  std::vector<std::string> unknown;
  for (const std::string& name : ps.feature_names) {
    const auto idx = ps.IndicesOf(name);
    if (idx.empty()) continue;
    FeatureSpec f;
    f.name = name;
    if (auto it = options.kinds.find(name); it != options.kinds.end()) {
      f.kind = it->second;
    } else if (ps.has_normals()) {
      auto k = InferKind(ps, name, idx);
      if (!k.ok()) return k.status();
      f.kind = *k;
    } else {
      unknown.push_back(name);
      continue;
    }
    if (f.kind == FeatureKind::kLine2) f.projection = Projection::kDatumXY;
    plan.features.push_back(std::move(f));
  }
  if (!unknown.empty()) {
    std::string list;
    for (const auto& n : unknown) list += (list.empty() ? "" : ", ") + n;
    return Status(StatusCode::kInvalidArgument,
                  "no kind for feature(s) " + list + ": " + ps.source + " has no normals to infer them from; give their kinds");
  }
  TPCAL_RETURN_IF_ERROR(ValidatePlan(plan));
  return plan;
}

Result<InspectionResult> EvaluateAdHoc(const PointSet& ps, const AdHocOptions& options) {
  auto plan = AdHocPlan(ps, options);
  if (!plan.ok()) return plan.status();
  return EvaluatePlan(*plan, ps, options.evaluate);
}

}  // namespace tpcal::gdt
