// Exact 2D geometry for the minimum-zone evaluations: hull, minimum-width strip, exact annulus
// checks, minimum circumscribed and maximum inscribed circles. The only fitting/ translation unit
// with CGAL 2D kernels, so it stays the single place that pays their compile time.
#include <CGAL/Convex_hull_traits_adapter_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Min_circle_2.h>
#include <CGAL/Min_circle_2_traits_2.h>
#include <CGAL/Random.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "fitting/minimum_zone_exact.h"
#include "fitting/minimum_zone_lp.h"

namespace tpcal::fitting::internal {
namespace {

using K = CGAL::Epick;
using EK = CGAL::Epeck;
using Q = CGAL::Exact_rational;  // the exact field type of Epeck (GMP rationals)
using I = CGAL::Interval_nt_advanced;  // needs CGAL::Protect_FPU_rounding in scope

constexpr double kU = std::numeric_limits<double>::epsilon() / 2;

struct QPoint {
  Q x, y;
  QPoint() = default;
  QPoint(const Q& x_, const Q& y_) : x(x_), y(y_) {}
  explicit QPoint(const Eigen::Vector2d& p) : x(p.x()), y(p.y()) {}
};
QPoint operator-(const QPoint& a, const QPoint& b) { return {a.x - b.x, a.y - b.y}; }
Q Cross(const QPoint& a, const QPoint& b) { return a.x * b.y - a.y * b.x; }
Q Dot(const QPoint& a, const QPoint& b) { return a.x * b.x + a.y * b.y; }
Q Norm2(const QPoint& a) { return Dot(a, a); }

std::vector<K::Point_2> ToEpick(std::span<const Eigen::Vector2d> pts) {
  std::vector<K::Point_2> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.emplace_back(p.x(), p.y());
  return out;
}

I ToI(const Q& q) { return I(CGAL::to_interval(q)); }

// Sign of |p - c|^2 - r2 with c, r2 rational: interval filter, exact fallback.
int CompareDistance2(const Eigen::Vector2d& p, const QPoint& c, const I& cx, const I& cy, const Q& r2,
                     const I& r2i) {
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const I dx = I(p.x()) - cx, dy = I(p.y()) - cy;
    const I d2 = dx * dx + dy * dy;
    if (d2.sup() < r2i.inf()) return -1;
    if (d2.inf() > r2i.sup()) return 1;
  }
  const Q d2 = Norm2(QPoint(p) - c);
  return d2 < r2 ? -1 : (d2 > r2 ? 1 : 0);
}

// Is w strictly inside the counter-clockwise arc from direction u to direction v (u, v distinct)?
bool InCcwArc(const QPoint& u, const QPoint& v, const QPoint& w) {
  const int cuv = CGAL::sign(Cross(u, v));
  if (cuv > 0) return CGAL::sign(Cross(u, w)) > 0 && CGAL::sign(Cross(w, v)) > 0;
  if (cuv < 0) return !(CGAL::sign(Cross(v, w)) >= 0 && CGAL::sign(Cross(w, u)) >= 0);
  return CGAL::sign(Cross(u, w)) > 0;  // opposite directions: the half-plane left of u
}
bool SameRay(const QPoint& u, const QPoint& w) {
  return CGAL::sign(Cross(u, w)) == 0 && CGAL::sign(Dot(u, w)) > 0;
}

// Exact check of a candidate circle (centre c, squared radius r2): no point strictly inside.
// Returns the contacts (points exactly on the circle) through `contacts` if non-null.
bool EmptyCircle(std::span<const Eigen::Vector2d> pts, const QPoint& c, const Q& r2,
                 std::vector<ZoneContact>* contacts) {
  const I cx = ToI(c.x), cy = ToI(c.y), r2i = ToI(r2);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int s = CompareDistance2(pts[i], c, cx, cy, r2, r2i);
    if (s < 0) return false;
    if (s == 0 && contacts) contacts->push_back({i, ZoneSide::kUpper});
  }
  return true;
}

// Exact circumcentre of three points.
bool Circumcenter(const QPoint& a, const QPoint& b, const QPoint& c, QPoint* out) {
  const QPoint ab = b - a, ac = c - a;
  const Q d = 2 * Cross(ab, ac);
  if (CGAL::sign(d) == 0) return false;
  const Q nb = Norm2(ab), nc = Norm2(ac);
  out->x = a.x + (ac.y * nb - ab.y * nc) / d;
  out->y = a.y + (ab.x * nc - ac.x * nb) / d;
  return true;
}

// Exact: is c inside or on the convex polygon given by ccw hull vertices?
bool InsideHull(std::span<const Eigen::Vector2d> pts, const std::vector<std::size_t>& hull, const QPoint& c) {
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const QPoint a(pts[hull[i]]), b(pts[hull[(i + 1) % hull.size()]]);
    if (CGAL::sign(Cross(b - a, c - a)) < 0) return false;
  }
  return true;
}

Eigen::Vector2d ToVec(const QPoint& p) { return {CGAL::to_double(p.x), CGAL::to_double(p.y)}; }

}  // namespace

long FirstNonFinite(std::span<const Eigen::Vector2d> pts) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) return static_cast<long>(i);
  }
  return -1;
}
long FirstNonFinite(std::span<const Eigen::Vector3d> pts) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) return static_cast<long>(i);
  }
  return -1;
}

bool AllCollinear2(std::span<const Eigen::Vector2d> pts) {
  if (pts.size() < 3) return true;
  const K::Point_2 p0(pts[0].x(), pts[0].y());
  std::size_t j = 1;
  while (j < pts.size() && pts[j] == pts[0]) ++j;
  if (j == pts.size()) return true;
  const K::Point_2 p1(pts[j].x(), pts[j].y());
  for (const auto& q : pts) {
    if (CGAL::orientation(p0, p1, K::Point_2(q.x(), q.y())) != CGAL::COLLINEAR) return false;
  }
  return true;
}

std::vector<std::size_t> ConvexHull2(std::span<const Eigen::Vector2d> pts) {
  const std::vector<K::Point_2> P = ToEpick(pts);
  std::vector<std::size_t> idx(P.size()), out;
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  using Traits = CGAL::Convex_hull_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::const_type>;
  CGAL::convex_hull_2(idx.begin(), idx.end(), std::back_inserter(out), Traits(CGAL::make_property_map(P)));
  return out;
}

Strip2 MinimumWidthStrip2(std::span<const Eigen::Vector2d> pts) {
  Strip2 out;
  const std::vector<std::size_t> hull = ConvexHull2(pts);
  if (hull.size() < 2) {
    out.message = "all points coincide";
    return out;
  }
  const std::size_t h = hull.size();
  std::vector<QPoint> v;
  v.reserve(h);
  for (std::size_t i : hull) v.emplace_back(pts[i]);
  if (h == 2) {  // all collinear: width 0
    const Eigen::Vector2d e = pts[hull[1]] - pts[hull[0]];
    out.normal = Eigen::Vector2d(-e.y(), e.x()).normalized();
    out.lower_offset_mm = out.normal.dot(pts[hull[0]]);
    out.width_mm = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      out.contacts.push_back({i, ZoneSide::kLower});
      out.contacts.push_back({i, ZoneSide::kUpper});
    }
    out.ok = true;
    return out;
  }
  // Rotating calipers, exact: for edge i (v_i -> v_i+1, interior on the left) the farthest vertex
  // maximises cross(e_i, v_j - v_i); it only advances as i does.
  auto next = [h](std::size_t i) { return (i + 1) % h; };
  std::size_t j = 1;
  Q best_num, best_len2;
  std::size_t best_i = 0, best_j = 0;
  bool have = false;
  for (std::size_t i = 0; i < h; ++i) {
    const QPoint e = v[next(i)] - v[i];
    if (i == 0) {
      j = next(i);
      while (CGAL::sign(Cross(e, v[next(j)] - v[j])) > 0) j = next(j);
    } else {
      while (CGAL::sign(Cross(e, v[next(j)] - v[j])) > 0) j = next(j);
    }
    const Q num = Cross(e, v[j] - v[i]);
    const Q len2 = Norm2(e);
    // width^2 = num^2 / len2; compare num^2 * best_len2 < best_num^2 * len2
    if (!have || num * num * best_len2 < best_num * best_num * len2) {
      best_num = num;
      best_len2 = len2;
      best_i = i;
      best_j = j;
      have = true;
    }
  }
  const QPoint a = v[best_i], e = v[next(best_i)] - v[best_i];
  const Eigen::Vector2d ed = ToVec(e);
  out.normal = Eigen::Vector2d(-ed.y(), ed.x()).normalized();
  out.lower_offset_mm = out.normal.dot(pts[hull[best_i]]);
  out.width_mm = std::sqrt(CGAL::to_double(best_num * best_num / best_len2));
  (void)best_j;
  // Contacts: every point exactly on either line (cross(e, p - a) == 0 or == best_num).
  I ex, ey, ax, ay, num_i;
  ex = ToI(e.x); ey = ToI(e.y); ax = ToI(a.x); ay = ToI(a.y); num_i = ToI(best_num);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    bool maybe_low = true, maybe_high = true;
    {
      CGAL::Protect_FPU_rounding<true> guard;
      const I c = ex * (I(pts[i].y()) - ay) - ey * (I(pts[i].x()) - ax);
      maybe_low = c.inf() <= 0;
      maybe_high = c.sup() >= num_i.inf();
    }
    if (!maybe_low && !maybe_high) continue;
    const Q c = Cross(e, QPoint(pts[i]) - a);
    if (CGAL::sign(c) == 0) out.contacts.push_back({i, ZoneSide::kLower});
    if (c == best_num) out.contacts.push_back({i, ZoneSide::kUpper});
  }
  out.ok = true;
  return out;
}

double MinimumWidthLowerBound2(std::span<const Eigen::Vector2d> pts) {
  const std::vector<std::size_t> hull = ConvexHull2(pts);
  const std::size_t h = hull.size();
  if (h < 3) return 0;
  auto P = [&](std::size_t i) -> const Eigen::Vector2d& { return pts[hull[i % h]]; };
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  double best = std::numeric_limits<double>::infinity();
  double extent = 0;
  for (std::size_t i = 0; i < h; ++i) extent = std::max(extent, P(i).cwiseAbs().maxCoeff());
  std::size_t j = 1;
  for (std::size_t i = 0; i < h; ++i) {
    const Eigen::Vector2d e = P(i + 1) - P(i);
    const double len = e.norm();
    if (len == 0) continue;
    // Advance while the next vertex is farther (any vertex gives a lower value: safe).
    for (std::size_t guard = 0; guard < h && cross(e, P(j + 1) - P(i)) > cross(e, P(j) - P(i)); ++guard) ++j;
    best = std::min(best, cross(e, P(j) - P(i)) / len);
  }
  // Rounding of the differences and cross products relative to the coordinate magnitude.
  return std::max(0.0, best - 64 * kU * extent);
}

ExactAnnulus ExactAnnulus22(std::span<const Eigen::Vector2d> pts, std::size_t a1, std::size_t a2, std::size_t b1,
                            std::size_t b2) {
  ExactAnnulus out;
  const QPoint A1(pts[a1]), A2(pts[a2]), B1(pts[b1]), B2(pts[b2]);
  // 2 (a2 - a1) . c = |a2|^2 - |a1|^2 ;  2 (b2 - b1) . c = |b2|^2 - |b1|^2
  const Q m11 = 2 * (A2.x - A1.x), m12 = 2 * (A2.y - A1.y), r1 = Norm2(A2) - Norm2(A1);
  const Q m21 = 2 * (B2.x - B1.x), m22 = 2 * (B2.y - B1.y), r2 = Norm2(B2) - Norm2(B1);
  const Q det = m11 * m22 - m12 * m21;
  if (CGAL::sign(det) == 0) return out;
  const QPoint c((r1 * m22 - m12 * r2) / det, (m11 * r2 - r1 * m21) / det);
  const Q R2 = Norm2(A1 - c), rr2 = Norm2(B1 - c);
  if (!(rr2 < R2)) return out;
  out.ok = true;
  out.center_mm = ToVec(c);
  const double Rd = std::sqrt(CGAL::to_double(R2)), rd = std::sqrt(CGAL::to_double(rr2));
  out.r_outer_mm = Rd;
  out.r_inner_mm = rd;
  out.width_mm = CGAL::to_double(R2 - rr2) / (Rd + rd);

  const QPoint u1 = A1 - c, u2 = A2 - c, w1 = B1 - c, w2 = B2 - c;
  out.alternating = !SameRay(u1, u2) && !SameRay(u1, w1) && !SameRay(u1, w2) && !SameRay(u2, w1) &&
                    !SameRay(u2, w2) && (InCcwArc(u1, u2, w1) != InCcwArc(u1, u2, w2));

  const I cx = ToI(c.x), cy = ToI(c.y), R2i = ToI(R2), r2i = ToI(rr2);
  out.contains_all = true;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int so = CompareDistance2(pts[i], c, cx, cy, R2, R2i);
    if (so > 0) {
      if (out.contains_all) out.first_violation = i;
      out.contains_all = false;
      continue;
    }
    if (so == 0) {
      out.contacts.push_back({i, ZoneSide::kUpper});
      continue;
    }
    const int si = CompareDistance2(pts[i], c, cx, cy, rr2, r2i);
    if (si < 0) {
      if (out.contains_all) out.first_violation = i;
      out.contains_all = false;
    } else if (si == 0) {
      out.contacts.push_back({i, ZoneSide::kLower});
    }
  }
  return out;
}

ExactCircle MinCircumscribedCircle2(std::span<const Eigen::Vector2d> pts) {
  ExactCircle out;
  std::vector<EK::Point_2> P;
  P.reserve(pts.size());
  for (const auto& p : pts) P.emplace_back(p.x(), p.y());
  CGAL::Random random(0x5eed);  // Min_circle_2 shuffles its input: fixed seed, deterministic time
  CGAL::Min_circle_2<CGAL::Min_circle_2_traits_2<EK>> mc(P.begin(), P.end(), true, random);
  if (mc.is_degenerate()) {
    out.message = "all points coincide";
    return out;
  }
  const auto& circle = mc.circle();
  const QPoint c(CGAL::exact(circle.center().x()), CGAL::exact(circle.center().y()));
  const Q r2 = CGAL::exact(circle.squared_radius());
  out.center_mm = ToVec(c);
  out.radius_mm = std::sqrt(CGAL::to_double(r2));
  // Contacts: points exactly on the circle (all others are strictly inside by construction).
  const I cx = ToI(c.x), cy = ToI(c.y), r2i = ToI(r2);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int s = CompareDistance2(pts[i], c, cx, cy, r2, r2i);
    if (s > 0) {
      out.message = "internal: Min_circle_2 result does not contain a point";
      return out;
    }
    if (s == 0) out.contacts.push_back({i, ZoneSide::kUpper});
  }
  out.ok = true;
  return out;
}

ExactCircle MaxInscribedCircle2(std::span<const Eigen::Vector2d> pts) {
  ExactCircle out;
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb>;
  using DT = CGAL::Delaunay_triangulation_2<K, Tds>;
  std::vector<std::pair<K::Point_2, std::size_t>> pv;
  pv.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) pv.emplace_back(K::Point_2(pts[i].x(), pts[i].y()), i);
  DT dt(pv.begin(), pv.end());
  if (dt.dimension() < 2) {
    out.message = "points are collinear";
    return out;
  }
  const std::vector<std::size_t> hull = ConvexHull2(pts);

  // Candidates in double: Voronoi vertices inside the hull, then Voronoi crossings of hull edges.
  struct Candidate {
    double r2;
    int type;  // 0: Voronoi vertex (i, j, k); 1: crossing of hull edge (i -> j) with bisector (k, l)
    std::size_t i, j, k, l;
  };
  std::vector<Candidate> cand;
  double best = 0;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    const K::Point_2 c = dt.circumcenter(f);
    const double r2 = CGAL::squared_distance(c, f->vertex(0)->point());
    const auto located = dt.locate(c, f);
    if (dt.is_infinite(located)) continue;
    cand.push_back({r2, 0, f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info(), 0});
    best = std::max(best, r2);
  }
  // A centre on hull edge ab has r <= |ab|/2: walk only edges that could beat the best vertex.
  for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
    const auto f = e->first;
    const int i = e->second;
    const bool hull_edge = dt.is_infinite(f) || dt.is_infinite(f->neighbor(i));
    if (!hull_edge) continue;
    auto va = f->vertex(DT::cw(i)), vb = f->vertex(DT::ccw(i));
    const Eigen::Vector2d a(va->point().x(), va->point().y()), b(vb->point().x(), vb->point().y());
    if ((b - a).squaredNorm() / 4 < best * (1 - 1e-9)) continue;
    const Eigen::Vector2d ab = b - a;
    auto s = va;
    double t = 0;
    for (std::size_t step = 0; step <= pts.size(); ++step) {
      const Eigen::Vector2d sp(s->point().x(), s->point().y());
      double t_next = 2;
      DT::Vertex_handle v_next;
      auto vc = dt.incident_vertices(s), done = vc;
      do {
        if (dt.is_infinite(vc)) continue;
        const Eigen::Vector2d vp(vc->point().x(), vc->point().y());
        const double denom = 2 * (vp - sp).dot(ab);
        if (denom <= 0) continue;
        const double tv = (vp.squaredNorm() - sp.squaredNorm() - 2 * (vp - sp).dot(a)) / denom;
        if (tv > t && tv < t_next) {
          t_next = tv;
          v_next = vc;
        }
      } while (++vc != done);
      if (t_next >= 1) break;
      const Eigen::Vector2d x = a + t_next * ab;
      const double r2 = (x - sp).squaredNorm();
      cand.push_back({r2, 1, va->info(), vb->info(), s->info(), v_next->info()});
      best = std::max(best, r2);
      s = v_next;
      t = t_next;
    }
  }
  if (cand.empty()) {
    out.message = "no inscribed circle candidate";
    return out;
  }
  // Exact evaluation of the near-best candidates; the exact maximum wins.
  std::sort(cand.begin(), cand.end(), [](const Candidate& x, const Candidate& y) { return x.r2 > y.r2; });
  bool have = false;
  QPoint best_c;
  Q best_r2;
  for (const Candidate& cd : cand) {
    // Ranked in double; every candidate within 1e-9 (relative) of the exact best is decided exactly.
    if (have && cd.r2 < CGAL::to_double(best_r2) * (1 - 1e-9)) break;
    QPoint c;
    Q r2;
    if (cd.type == 0) {
      if (!Circumcenter(QPoint(pts[cd.i]), QPoint(pts[cd.j]), QPoint(pts[cd.k]), &c)) continue;
      if (!InsideHull(pts, hull, c)) continue;
      r2 = Norm2(QPoint(pts[cd.i]) - c);
    } else {
      // Point a + t (b - a) equidistant from sites k and l: 2 (l - k).(a + t ab) = |l|^2 - |k|^2.
      const QPoint a(pts[cd.i]), b(pts[cd.j]), pk(pts[cd.k]), pl(pts[cd.l]);
      const QPoint ab = b - a, kl = pl - pk;
      const Q denom = 2 * Dot(kl, ab);
      if (CGAL::sign(denom) == 0) continue;
      const Q t = (Norm2(pl) - Norm2(pk) - 2 * Dot(kl, a)) / denom;
      if (t < 0 || t > 1) continue;
      c = QPoint(a.x + t * ab.x, a.y + t * ab.y);
      r2 = Norm2(pk - c);
    }
    if (have && !(r2 > best_r2)) continue;
    if (!EmptyCircle(pts, c, r2, nullptr)) continue;
    best_c = c;
    best_r2 = r2;
    have = true;
  }
  if (!have) {
    out.message = "no candidate passed the exact checks";
    return out;
  }
  out.center_mm = ToVec(best_c);
  out.radius_mm = std::sqrt(CGAL::to_double(best_r2));
  EmptyCircle(pts, best_c, best_r2, &out.contacts);
  out.ok = true;
  return out;
}

}  // namespace tpcal::fitting::internal
