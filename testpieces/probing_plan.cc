#include "testpieces/probing_plan.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"

namespace tpcal::testpieces {
namespace {

constexpr double kPlanPointTol_mm = 1e-9;  // association must return the plan point itself

// `count` levels: the design levels for one, else evenly spread over the band shrunk by margin.
Result<std::vector<double>> Levels(const NominalFeature& f, int count, double margin) {
  if ((count == 1 || f.fixed_levels) && !f.design_levels_mm.empty()) return f.design_levels_mm;
  const double lo = f.level_min_mm + margin, hi = f.level_max_mm - margin;
  if (count == 1) return std::vector<double>{0.5 * (lo + hi)};
  if (!(hi > lo)) {
    return Status(StatusCode::kInvalidArgument, "feature " + f.name + ": probing band too narrow for " +
                                                    std::to_string(count) + " levels with the edge margin");
  }
  std::vector<double> out;
  for (int k = 0; k < count; ++k) out.push_back(lo + (hi - lo) * k / (count - 1));
  return out;
}

Status AddPoint(const TestPiece& piece, const NominalFeature& f, const Eigen::Vector3d& p, double level,
                ProbingPlan* plan) {
  auto cut = CutPointAt(piece, f.name, p);
  if (!cut.ok()) return cut.status();
  if ((cut->nominal_point_mm - p).norm() > kPlanPointTol_mm) {
    return {StatusCode::kInternal, "feature " + f.name + ": association moved a plan point"};
  }
  PlanPoint pp;
  pp.feature = f.name;
  pp.point_part_mm = cut->nominal_point_mm;
  pp.normal_part = cut->nominal_normal;
  pp.level_mm = level;
  pp.cut = *cut;
  plan->points.push_back(std::move(pp));
  return Status::Ok();
}

Status SampleFeature(const TestPiece& piece, const NominalFeature& f, const ProbingOptions& o, ProbingPlan* plan) {
  switch (f.pattern) {
    case ProbePattern::kCircles: {
      const int n = f.hole ? o.points_per_hole : o.points_per_circle;
      const int levels = f.hole ? o.levels_per_hole : o.levels_per_face;
      auto lv = Levels(f, levels, o.edge_margin_mm);
      if (!lv.ok()) return lv.status();
      for (double level : *lv) {
        for (int k = 0; k < n; ++k) {
          const double theta = 2.0 * kPi * k / n;
          Eigen::Vector3d p;
          if (f.type == SurfaceType::kPlane) {
            p = PointAt(f, {level * std::cos(theta), level * std::sin(theta)});
          } else {
            p = PointAt(f, {theta, level});
          }
          TPCAL_RETURN_IF_ERROR(AddPoint(piece, f, p, level, plan));
        }
      }
      return Status::Ok();
    }
    case ProbePattern::kLines: {
      auto lv = Levels(f, o.levels_per_face, o.edge_margin_mm);
      if (!lv.ok()) return lv.status();
      const double u0 = f.line_u_min_mm + o.edge_margin_mm, u1 = f.line_u_max_mm - o.edge_margin_mm;
      if (!(u1 > u0)) return {StatusCode::kInvalidArgument, "feature " + f.name + ": line too short for the margin"};
      for (double level : *lv) {
        for (int k = 0; k < o.points_per_line; ++k) {
          const double u = u0 + (u1 - u0) * k / (o.points_per_line - 1);
          TPCAL_RETURN_IF_ERROR(AddPoint(piece, f, PointAt(f, {u, level}), level, plan));
        }
      }
      return Status::Ok();
    }
    case ProbePattern::kGrid: {
      Eigen::Vector2d lo = f.polygon_uv_mm.front(), hi = lo;
      for (const auto& q : f.polygon_uv_mm) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      const int n = o.grid_per_side;
      const std::size_t before = plan->points.size();
      // Frame-shaped patches: a denser raster so each strip gets points.
      const int raster = f.hole_uv_mm.empty() ? n : 4 * n;
      for (int i = 0; i < raster; ++i) {
        for (int j = 0; j < raster; ++j) {
          const Eigen::Vector2d uv(lo.x() + o.edge_margin_mm + (hi.x() - lo.x() - 2 * o.edge_margin_mm) * i / (raster - 1),
                                   lo.y() + o.edge_margin_mm + (hi.y() - lo.y() - 2 * o.edge_margin_mm) * j / (raster - 1));
          if (!InPlanePatch(f, uv, o.edge_margin_mm)) continue;
          TPCAL_RETURN_IF_ERROR(AddPoint(piece, f, PointAt(f, {uv.x(), uv.y()}), 0.0, plan));
        }
      }
      if (plan->points.size() - before < 3) {
        return {StatusCode::kInvalidArgument, "feature " + f.name + ": grid leaves fewer than 3 points in the patch"};
      }
      return Status::Ok();
    }
  }
  return Status::Ok();
}

// a * b for counts >= 0, saturated at kPlanCountCap (no overflow for any int inputs).
constexpr std::int64_t kPlanCountCap = std::int64_t{1} << 62;
std::int64_t CappedProduct(std::int64_t a, std::int64_t b) {
  if (a == 0 || b == 0) return 0;
  return a > kPlanCountCap / b ? kPlanCountCap : a * b;
}

// The number of levels Levels() returns for `count`.
std::int64_t LevelCount(const NominalFeature& f, int count) {
  if ((count == 1 || f.fixed_levels) && !f.design_levels_mm.empty())
    return static_cast<std::int64_t>(f.design_levels_mm.size());
  return std::max(count, 0);
}

std::int64_t FeaturePointCount(const NominalFeature& f, const ProbingOptions& o) {
  switch (f.pattern) {
    case ProbePattern::kCircles:
      return f.hole ? CappedProduct(std::max(o.points_per_hole, 0), LevelCount(f, o.levels_per_hole))
                    : CappedProduct(std::max(o.points_per_circle, 0), LevelCount(f, o.levels_per_face));
    case ProbePattern::kLines: return CappedProduct(std::max(o.points_per_line, 0), LevelCount(f, o.levels_per_face));
    case ProbePattern::kGrid: {
      const std::int64_t raster = std::int64_t{std::max(o.grid_per_side, 0)} * (f.hole_uv_mm.empty() ? 1 : 4);
      return CappedProduct(raster, raster);
    }
  }
  return 0;
}

}  // namespace

std::int64_t PlannedPointCount(const TestPiece& piece, const ProbingOptions& options) {
  std::int64_t total = 0;
  for (const NominalFeature& f : piece.features) total = std::min(kPlanCountCap, total + FeaturePointCount(f, options));
  return total;
}

Status CheckPlanSize(const TestPiece& piece, const ProbingOptions& options) {
  const std::int64_t n = PlannedPointCount(piece, options);
  if (n <= kMaxPlanPoints) return Status::Ok();
  const std::string count = n == kPlanCountCap ? "more than 4e18" : std::to_string(n);
  return Status(StatusCode::kInvalidArgument,
                "the probing plan of the " + piece.name + " would hold " + count + " points; expected at most " +
                    std::to_string(kMaxPlanPoints) + " (about 1 kB of memory each, within a 4 GB budget)");
}

Result<ProbingPlan> MakeProbingPlan(const TestPiece& piece, const ProbingOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  TPCAL_RETURN_IF_ERROR(CheckPlanSize(piece, options));
  ProbingPlan plan;
  plan.piece_name = piece.name;
  plan.part_from_datum = piece.part_from_datum;
  for (const NominalFeature& f : piece.features) {
    TPCAL_RETURN_IF_ERROR(SampleFeature(piece, f, options, &plan));
  }
  return plan;
}

Result<ProbingPlan> MakeProbingPlan(const TestPiece& piece) { return MakeProbingPlan(piece, piece.config.probing); }

std::vector<std::string> PlanExtraColumns(const kinematics::MachineModel& machine) {
  std::vector<std::string> cols = {"op", "t_s"};
  if (machine.HasAxis(kinematics::Axis::kA)) cols.push_back("A_deg");
  if (machine.HasAxis(kinematics::Axis::kB)) cols.push_back("B_deg");
  if (machine.HasAxis(kinematics::Axis::kC)) cols.push_back("C_deg");
  cols.insert(cols.end(), {"X_mm", "Y_mm", "Z_mm"});
  return cols;
}

std::vector<PlanRow> PlanRows(const ProbingPlan& plan) {
  const Rigid3 datum_from_part = plan.part_from_datum.inverse();
  std::vector<PlanRow> rows;
  rows.reserve(plan.points.size());
  for (const PlanPoint& p : plan.points) {
    PlanRow r;
    r.feature = p.feature;
    r.xyz_mm = datum_from_part * p.point_part_mm;
    r.ijk = datum_from_part.linear() * p.normal_part;
    r.op = p.cut.axes.op;
    r.t_s = p.cut.axes.t_s;
    r.a_deg = RadToDeg(p.cut.axes.a_rad);
    r.b_deg = RadToDeg(p.cut.axes.b_rad);
    r.c_deg = RadToDeg(p.cut.axes.c_rad);
    r.x_mm = p.cut.axes.x_mm;
    r.y_mm = p.cut.axes.y_mm;
    r.z_mm = p.cut.axes.z_mm;
    rows.push_back(r);
  }
  return rows;
}

PointSet PlanPointSet(const ProbingPlan& plan) {
  const Rigid3 datum_from_part = plan.part_from_datum.inverse();
  PointSet ps;
  ps.source = "probing plan of " + plan.piece_name;
  for (const PlanPoint& p : plan.points) {
    ps.xyz_mm.push_back(datum_from_part * p.point_part_mm);
    ps.normal.push_back(datum_from_part.linear() * p.normal_part);
    ps.feature.push_back(ps.InternFeature(p.feature));
  }
  return ps;
}

}  // namespace tpcal::testpieces
