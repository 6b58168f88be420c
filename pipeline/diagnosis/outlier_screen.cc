#include "pipeline/diagnosis/outlier_screen.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <fmt/format.h>
#include <map>

#include "core/median.h"
#include "pipeline/diagnosis/diagnosis_least_squares.h"
#include "pipeline/diagnosis/feature_neighbours.h"

namespace tpcal::pipeline {
namespace {

constexpr int kMaxRounds = 40;

// Variance of the median of k standard normal draws (k = 1..4 exact to 3 digits; pi / 2k beyond).
double MedianVariance(std::size_t k) {
  static const double v[] = {0.0, 1.0, 0.5, 0.449, 0.298};
  return k <= 4 ? v[k] : 3.14159265358979 / (2.0 * static_cast<double>(k));
}

// An orthonormal basis of the columns of X scaled to unit norm (singular values at most 1e-9 of
// the largest dropped). Raw polynomial columns (a sextic straightness candidate) span 15 orders of
// magnitude; a pivoted QR of them kept directions at 1e-9 of the largest and returned residuals
// 1e5 times |y|. Plain norms, not ColumnNorms: its rounding rule, relative to the largest column,
// would zero the unit base columns beside such monomials. Columns already orthonormal (the
// diagnosis's base basis) are returned as they are: X^T X costs a fraction of the SVD.
Eigen::MatrixXd OrthonormalColumns(const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd gram = X.transpose() * X;
  if ((gram - Eigen::MatrixXd::Identity(X.cols(), X.cols())).cwiseAbs().maxCoeff() < 1e-12) return X;
  return diagnosis_internal::MakeBasis(X, X.colwise().norm().transpose(), 1e-9, true).U;
}

// The least-squares fit of y on Q (orthonormal columns) over the rows not flagged, from the normal
// equations of every row (Q^T Q, Q^T y: once per screen) less the flagged rows': a round costs
// flagged x p^2, not a factorisation of every kept row (10^5 points: those QRs were 7 % of
// the diagnosis, perf).
struct TrimmedFit {
  const Eigen::MatrixXd& Q;
  const Eigen::VectorXd& y;
  Eigen::MatrixXd gram;
  Eigen::VectorXd qty;
  TrimmedFit(const Eigen::MatrixXd& q, const Eigen::VectorXd& yy) : Q(q), y(yy), qty(q.transpose() * yy) {
    gram.setZero(q.cols(), q.cols());
    if (q.rows() > 0 && q.cols() > 0) gram.selfadjointView<Eigen::Lower>().rankUpdate(q.transpose());
  }
};

// Residuals at every row of that fit over the rows not flagged[i]. Q's singular values are at most
// 1: a direction the kept rows hold below 1e-6 of the largest (an eigenvalue of their Gram matrix
// below 1e-12 of its largest) is the flagged rows' alone, and fitting it would extrapolate their
// residuals: it is left out.
Eigen::VectorXd TrimmedResiduals(const TrimmedFit& t, const std::vector<bool>& flagged) {
  std::vector<Eigen::Index> out;
  for (std::size_t i = 0; i < flagged.size(); ++i)
    if (flagged[i]) out.push_back(static_cast<Eigen::Index>(i));
  const Eigen::Index p = t.Q.cols();
  if (p == 0 || t.Q.rows() - static_cast<Eigen::Index>(out.size()) <= p) return t.y;
  Eigen::MatrixXd Qf(static_cast<Eigen::Index>(out.size()), p);
  Eigen::VectorXd yf(Qf.rows());
  for (Eigen::Index k = 0; k < Qf.rows(); ++k) {
    Qf.row(k) = t.Q.row(out[static_cast<std::size_t>(k)]);
    yf(k) = t.y(out[static_cast<std::size_t>(k)]);
  }
  Eigen::MatrixXd G = t.gram;
  if (Qf.rows() > 0) G.selfadjointView<Eigen::Lower>().rankUpdate(Qf.transpose(), -1.0);  // Eigen: no update of depth 0
  const Eigen::VectorXd b = t.qty - Qf.transpose() * yf;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G.selfadjointView<Eigen::Lower>());
  const Eigen::VectorXd& ev = eig.eigenvalues();
  Eigen::VectorXd z = eig.eigenvectors().transpose() * b;
  for (Eigen::Index k = 0; k < p; ++k) z(k) = ev(k) > 1e-12 * ev(p - 1) ? z(k) / ev(k) : 0.0;
  return t.y - t.Q * (eig.eigenvectors() * z);
}

// Connected components (same sign as their seed, through the symmetric neighbour graph) of the
// points with seed(i), grown from a member a through the points b with join(b, a).
template <typename Seed, typename Join>
std::vector<std::vector<int>> Components(const Eigen::VectorXd& r, const std::vector<std::vector<int>>& adj, Seed seed,
                                         Join join) {
  std::vector<std::vector<int>> out;
  std::vector<bool> seen(static_cast<std::size_t>(r.size()), false);
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (seen[static_cast<std::size_t>(i)] || !seed(static_cast<int>(i))) continue;
    std::vector<int> comp;
    std::deque<int> todo{static_cast<int>(i)};
    seen[static_cast<std::size_t>(i)] = true;
    while (!todo.empty()) {
      const int a = todo.front();
      todo.pop_front();
      comp.push_back(a);
      for (int b : adj[static_cast<std::size_t>(a)])
        if (!seen[static_cast<std::size_t>(b)] && r(b) * r(i) > 0 && join(b, a)) {
          seen[static_cast<std::size_t>(b)] = true;
          todo.push_back(b);
        }
    }
    std::sort(comp.begin(), comp.end());
    out.push_back(std::move(comp));
  }
  return out;
}

DefectPatch MakePatch(std::span<const kinematics::Observation> obs, const Eigen::VectorXd& r, std::vector<int> members) {
  DefectPatch p;
  p.group = obs[static_cast<std::size_t>(members.front())].group;
  for (int m : members) {
    p.centre_mm += obs[static_cast<std::size_t>(m)].cut.nominal_point_mm;
    p.mean_um += r(m);
    if (std::abs(r(m)) > std::abs(p.peak_um)) p.peak_um = r(m);
  }
  p.centre_mm /= static_cast<double>(members.size());
  p.mean_um /= static_cast<double>(members.size());
  for (int m : members)
    p.extent_mm = std::max(p.extent_mm, (obs[static_cast<std::size_t>(m)].cut.nominal_point_mm - p.centre_mm).norm());
  p.members = std::move(members);
  return p;
}

// What the screen sees of the points: neighbours, graph, feature sizes, options, and a
// reference's leftover uncertainty (factor R, n x r; no column: none).
struct ScreenContext {
  std::span<const kinematics::Observation> obs;
  std::vector<std::vector<int>> nb, adj;
  std::map<int, int> group_size;
  const OutlierScreenOptions& o;
  const Eigen::MatrixXd& R;
  std::vector<double> departure_var;  // per observation: DepartureVarianceOf, computed once
  std::vector<double> patch_seed_z;   // by patch size m: PatchSeedZ
};

// The seed threshold of an m-point patch among n observations: seed_z up to seed_reference_points
// (N), above it SeedZFor of N + m (n - N) candidates (each point starts about m times as many
// connected m-point sets as single points).
std::vector<double> PatchSeedZ(const OutlierScreenOptions& options, std::size_t n) {
  std::vector<double> z(static_cast<std::size_t>(2 * options.max_patch_points + 1), options.seed_z);
  const std::size_t reference = options.seed_reference_points;
  if (reference == 0 || n <= reference) return z;
  for (std::size_t m = 1; m < z.size(); ++m) z[m] = SeedZFor(options, reference + m * (n - reference));
  return z;
}

// The threshold of a component of m points (m beyond the table: its last entry).
double SeedZOf(const ScreenContext& c, std::size_t m) { return c.patch_seed_z[std::min(m, c.patch_seed_z.size() - 1)]; }

// Observation i's noise sigma relative to one probe hit's (Observation::noise_scale).
double Scale(const ScreenContext& c, int i) { return c.obs[static_cast<std::size_t>(i)].noise_scale; }

// The variance of point i's departure from the median of its neighbours, in units of one hit's
// sigma^2: its own and the median's (v_k times its neighbours' mean; 1 + v_k for hits).
double DepartureVarianceOf(const ScreenContext& c, int i) {
  const auto& list = c.nb[static_cast<std::size_t>(i)];
  double around = 0.0;
  for (int j : list) around += Scale(c, j) * Scale(c, j);
  around /= static_cast<double>(list.size());
  return Scale(c, i) * Scale(c, i) + MedianVariance(list.size()) * around;
}

double DepartureVariance(const ScreenContext& c, int i) { return c.departure_var[static_cast<std::size_t>(i)]; }

// d_i = r_i - median of its neighbours' r; sigma (one hit's) from the MAD of d_i / sqrt(DepartureVariance).
void NeighbourDeviations(const ScreenContext& c, const Eigen::VectorXd& r, double min_sigma_um, OutlierScreen* s) {
  s->neighbour_dev_um = Eigen::VectorXd::Zero(r.size());
  std::vector<double> scaled, v;
  scaled.reserve(static_cast<std::size_t>(r.size()));
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const auto& list = c.nb[static_cast<std::size_t>(i)];
    if (list.empty()) continue;
    v.clear();
    for (int j : list) v.push_back(r(j));
    s->neighbour_dev_um(i) = r(i) - MedianInPlace(v);
    scaled.push_back(std::abs(s->neighbour_dev_um(i)) / std::sqrt(DepartureVariance(c, static_cast<int>(i))));
  }
  s->sigma_dof = 0.37 * static_cast<double>(scaled.size());
  s->sigma_um = scaled.size() >= 10 ? std::max(min_sigma_um, 1.4826 * Median(scaled)) : 0.0;
}

// What a reference's leftover uncertainty adds to the variance of the sum of the residuals over
// `comp` (|sum of R's rows|^2, um^2; 0 without one).
double ReferenceVariance(const ScreenContext& c, const std::vector<int>& comp) {
  if (c.R.cols() == 0) return 0.0;
  Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(c.R.cols());
  for (int i : comp) sum += c.R.row(i);
  return sum.squaredNorm();
}

// The same for point i's departure from its neighbours (|R_i - their mean R|^2, um^2; 0 without).
double ReferenceDepartureVariance(const ScreenContext& c, int i) {
  const auto& nb = c.nb[static_cast<std::size_t>(i)];
  if (c.R.cols() == 0 || nb.empty()) return 0.0;
  Eigen::RowVectorXd around = Eigen::RowVectorXd::Zero(c.R.cols());
  for (int j : nb) around += c.R.row(j) / static_cast<double>(nb.size());
  return (c.R.row(i) - around).squaredNorm();
}

// A component's departure in units of its standard deviation: |sum of r| / sqrt(m) over sigma (m:
// the members' summed noise_scale^2, their count for hits), with what a reference's leftover
// uncertainty adds (|r| / sigma for one hit without one).
double FaultZ(const ScreenContext& c, const OutlierScreen& s, const std::vector<int>& comp) {
  double sum = 0.0, m = 0.0;
  for (int i : comp) sum += s.residual_um(i), m += Scale(c, i) * Scale(c, i);
  const double s2 = s.sigma_um * s.sigma_um;
  return std::abs(sum) / (std::sqrt(m) * s.sigma_um * std::sqrt(1.0 + ReferenceVariance(c, comp) / (m * s2)));
}

// The most points a patch of comp's feature may hold: max_patch_points and max_patch_share of them.
double MaxPatchSize(const ScreenContext& c, const std::vector<int>& comp) {
  const int n_g = c.group_size.at(c.obs[static_cast<std::size_t>(comp.front())].group);
  return std::min<double>(c.o.max_patch_points, c.o.max_patch_share * n_g);
}

// Is a component a fault (an isolated outlier or a small patch) rather than systematic? Its
// FaultZ beyond seed_z, and one point's departure from its neighbours too (scaled alike).
bool IsFault(const ScreenContext& c, const OutlierScreen& s, const std::vector<int>& comp) {
  const int n_g = c.group_size.at(c.obs[static_cast<std::size_t>(comp.front())].group);
  if (n_g < 3) return false;
  if (comp.size() == 1) {
    const int i = comp.front();
    const double s2 = s.sigma_um * s.sigma_um;
    return FaultZ(c, s, comp) > c.o.seed_z &&
           std::abs(s.neighbour_dev_um(i)) >
               c.o.seed_z * s.sigma_um * std::sqrt(DepartureVariance(c, i) + ReferenceDepartureVariance(c, i) / s2);
  }
  return static_cast<double>(comp.size()) <= MaxPatchSize(c, comp) && FaultZ(c, s, comp) > SeedZOf(c, comp.size());
}

// The members of `comp` connected to its peak through members of at least join_ratio of the
// peak's |r|: a patch that its neighbours' pull, or noise beyond grow_z, made too large to be a
// fault (NewFaults asks only of components at most twice a patch's size: a larger one is systematic,
// and peeling its cores round after round would take a whole error motion away).
std::vector<int> Core(const ScreenContext& c, const Eigen::VectorXd& r, const std::vector<int>& comp) {
  int peak = comp.front();
  for (int i : comp)
    if (std::abs(r(i)) > std::abs(r(peak))) peak = i;
  std::vector<bool> in(static_cast<std::size_t>(r.size()), false);
  for (int i : comp) in[static_cast<std::size_t>(i)] = std::abs(r(i)) >= c.o.join_ratio * std::abs(r(peak));
  auto parts = Components(r, c.adj, [&](int i) { return i == peak; }, [&](int b, int) { return static_cast<bool>(in[static_cast<std::size_t>(b)]); });
  return parts.front();
}

// Whether every member of comp outside its core lies within seed_z sigma: the rim of a dent
// (neighbours just beyond grow_z), not the flanks of a smooth error (a lobe's flanks of a
// noise-free error motion reach far beyond seed_z).
bool WeakRim(const ScreenContext& c, const OutlierScreen& s, const std::vector<int>& comp, const std::vector<int>& core) {
  for (int i : comp)
    if (std::find(core.begin(), core.end(), i) == core.end() && std::abs(s.residual_um(i)) > c.o.seed_z * s.sigma_um * Scale(c, i))
      return false;
  return true;
}

// How many flagged points of comp's sign are connected to it: a component that would grow a
// flagged patch beyond a patch's size is the rest of something systematic whose core was flagged
// (Core), not a fault of its own.
std::size_t FlaggedBeside(const ScreenContext& c, const Eigen::VectorXd& r, const std::vector<int>& comp,
                          const std::vector<bool>& flagged) {
  std::vector<bool> in(flagged.size(), false);
  for (int i : comp) in[static_cast<std::size_t>(i)] = true;
  const auto grown = Components(r, c.adj, [&](int i) { return i == comp.front(); },
                                [&](int b, int) { return flagged[static_cast<std::size_t>(b)] || in[static_cast<std::size_t>(b)]; });
  return grown.front().size() - comp.size();
}

// The faults among the points not yet flagged, from this round's residuals.
std::vector<std::vector<int>> NewFaults(const ScreenContext& c, const OutlierScreen& s, const std::vector<bool>& flagged) {
  const Eigen::VectorXd& r = s.residual_um;
  auto seeds = [&](int i) {
    return !flagged[static_cast<std::size_t>(i)] && std::abs(r(i)) > c.o.grow_z * s.sigma_um * Scale(c, i);
  };
  auto joins = [&](int b, int a) {
    const double rb = std::abs(r(b));
    return seeds(b) || (!flagged[static_cast<std::size_t>(b)] && rb > c.o.join_floor_z * s.sigma_um * Scale(c, b) &&
                        rb >= c.o.join_ratio * std::abs(r(a)));
  };
  std::vector<std::vector<int>> out;
  auto grows_no_patch = [&](const std::vector<int>& f) {
    return static_cast<double>(f.size() + FlaggedBeside(c, r, f, flagged)) <= MaxPatchSize(c, f);
  };
  for (auto& comp : Components(r, c.adj, seeds, joins)) {
    if (IsFault(c, s, comp)) {
      if (grows_no_patch(comp)) out.push_back(std::move(comp));
    } else if (comp.size() > 1 && static_cast<double>(comp.size()) <= 2.0 * MaxPatchSize(c, comp)) {
      std::vector<int> core = Core(c, r, comp);
      if (core.size() < comp.size() && WeakRim(c, s, comp, core) && IsFault(c, s, core) && grows_no_patch(core))
        out.push_back(std::move(core));
    }
  }
  return out;
}

// Worst first: of this round's faults, those within a factor 2 of the largest FaultZ, so that the
// pull of a gross outlier on the fit is gone before its neighbours are judged.
std::vector<const std::vector<int>*> WorstFaults(const ScreenContext& c, const OutlierScreen& s,
                                                 const std::vector<std::vector<int>>& faults) {
  double worst = 0.0;
  for (const auto& f : faults) worst = std::max(worst, FaultZ(c, s, f));
  std::vector<const std::vector<int>*> out;
  for (const auto& f : faults)
    if (FaultZ(c, s, f) >= 0.5 * worst) out.push_back(&f);
  return out;
}

// The flagged points grouped (same-sign neighbours) into outliers and patches; a feature with more
// groups than max(2, max_components_share x its points) has all its points kept. Returns whether
// any point was kept that way.
bool FinalFlags(const ScreenContext& c, const std::vector<bool>& flagged, OutlierScreen* s) {
  const Eigen::VectorXd& r = s->residual_um;
  auto is_flagged = [&](int i) { return static_cast<bool>(flagged[static_cast<std::size_t>(i)]); };
  std::map<int, std::vector<std::vector<int>>> by_group;
  for (auto& comp : Components(r, c.adj, is_flagged, [&](int b, int) { return is_flagged(b); }))
    by_group[c.obs[static_cast<std::size_t>(comp.front())].group].push_back(std::move(comp));
  s->flag.assign(c.obs.size(), ScreenFlag::kKept);
  s->patches.clear();
  bool released = false;
  for (auto& [g, comps] : by_group) {
    if (static_cast<double>(comps.size()) > std::max(2.0, c.o.max_components_share * c.group_size.at(g))) {
      released = true;
      continue;
    }
    for (auto& comp : comps) {
      const ScreenFlag f = comp.size() == 1 ? ScreenFlag::kOutlier : ScreenFlag::kLocalDefect;
      for (int i : comp) s->flag[static_cast<std::size_t>(i)] = f;
      if (comp.size() > 1) s->patches.push_back(MakePatch(c.obs, r, std::move(comp)));
    }
  }
  std::sort(s->patches.begin(), s->patches.end(),
            [](const DefectPatch& a, const DefectPatch& b) { return a.members.front() < b.members.front(); });
  return released;
}

}  // namespace

Status OutlierScreenOptions::Validate() const {
  if (!(seed_z > 0 && grow_z > 0 && grow_z <= seed_z))
    return {StatusCode::kInvalidArgument, "outlier screen: need 0 < grow_z <= seed_z"};
  if (!(join_floor_z > 0 && join_floor_z <= grow_z && join_ratio > 0 && join_ratio <= 1))
    return {StatusCode::kInvalidArgument, "outlier screen: need 0 < join_floor_z <= grow_z and 0 < join_ratio <= 1"};
  if (!(min_sigma_um >= 0)) return {StatusCode::kInvalidArgument, "outlier screen: need min_sigma_um >= 0"};
  if (neighbours < 1 || max_patch_points < 2) return {StatusCode::kInvalidArgument, "outlier screen: need neighbours >= 1 and max_patch_points >= 2"};
  if (!(max_patch_share > 0 && max_patch_share <= 1 && max_components_share >= 0))
    return {StatusCode::kInvalidArgument, "outlier screen: need 0 < max_patch_share <= 1 and max_components_share >= 0"};
  return {};
}

int OutlierScreen::CountFlagged() const {
  return static_cast<int>(std::count_if(flag.begin(), flag.end(), [](ScreenFlag f) { return f != ScreenFlag::kKept; }));
}

std::vector<int> OutlierScreen::KeptIndices() const {
  std::vector<int> out;
  for (std::size_t i = 0; i < flag.size(); ++i)
    if (flag[i] == ScreenFlag::kKept) out.push_back(static_cast<int>(i));
  return out;
}

double SeedZFor(const OutlierScreenOptions& options, std::size_t n) {
  const auto reference = static_cast<double>(options.seed_reference_points);
  if (options.seed_reference_points == 0 || static_cast<double>(n) <= reference) return options.seed_z;
  const double tail = std::erfc(options.seed_z / std::sqrt(2.0)) * reference / static_cast<double>(n);
  double lo = options.seed_z, hi = 40.0;  // erfc is decreasing: bisect to double precision
  for (int i = 0; i < 200 && lo < hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (std::erfc(mid / std::sqrt(2.0)) > tail ? lo : hi) = mid;
  }
  return hi;
}

OutlierScreen ScreenOutliers(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                             std::span<const kinematics::Observation> observations, const OutlierScreenOptions& options,
                             const Eigen::MatrixXd& reference_remaining_um,
                             std::shared_ptr<const FeatureNeighbourGraph> neighbours) {
  assert(reference_remaining_um.cols() == 0 ||
         reference_remaining_um.rows() == static_cast<Eigen::Index>(observations.size()));
  OutlierScreenOptions sized = options;
  sized.seed_z = SeedZFor(options, observations.size());
  const double rise = sized.seed_z / options.seed_z;  // exactly 1 up to seed_reference_points
  sized.grow_z *= rise;
  sized.join_floor_z *= rise;
  if (!neighbours || !neighbours->Fits(observations.size(), options.neighbours))
    neighbours = std::make_shared<const FeatureNeighbourGraph>(
        FeatureNeighbourGraph{options.neighbours, FeatureNeighbours(observations, options.neighbours)});
  ScreenContext c{observations, neighbours->lists, {}, {}, sized, reference_remaining_um, {}, PatchSeedZ(options, observations.size())};
  c.adj = c.nb;  // symmetric neighbour graph
  for (std::size_t i = 0; i < c.nb.size(); ++i)
    for (int j : c.nb[i]) {
      auto& back = c.adj[static_cast<std::size_t>(j)];
      if (std::find(back.begin(), back.end(), static_cast<int>(i)) == back.end()) back.push_back(static_cast<int>(i));
    }
  for (const auto& o : observations) ++c.group_size[o.group];
  c.departure_var.assign(observations.size(), 0.0);
  for (std::size_t i = 0; i < observations.size(); ++i)
    if (!c.nb[i].empty()) c.departure_var[i] = DepartureVarianceOf(c, static_cast<int>(i));
  const Eigen::MatrixXd Q = OrthonormalColumns(X);
  const TrimmedFit fit(Q, y);
  OutlierScreen s;
  s.neighbours = std::move(neighbours);
  std::vector<bool> flagged(observations.size(), false);
  for (s.rounds = 1;; ++s.rounds) {
    s.residual_um = TrimmedResiduals(fit, flagged);
    NeighbourDeviations(c, s.residual_um, options.min_sigma_um, &s);
    if (s.sigma_um <= 0 || s.rounds > kMaxRounds) break;
    const std::vector<std::vector<int>> faults = NewFaults(c, s, flagged);
    if (faults.empty()) break;
    for (const auto* f : WorstFaults(c, s, faults))
      for (int i : *f) flagged[static_cast<std::size_t>(i)] = true;
  }
  s.flag.assign(observations.size(), ScreenFlag::kKept);
  if (s.sigma_um > 0 && FinalFlags(c, flagged, &s)) {
    for (std::size_t i = 0; i < flagged.size(); ++i) flagged[i] = s.flag[i] != ScreenFlag::kKept;
    s.residual_um = TrimmedResiduals(fit, flagged);
    NeighbourDeviations(c, s.residual_um, options.min_sigma_um, &s);
  }
  return s;
}

testpieces::MeasuredObservations ObservationRows(const testpieces::MeasuredObservations& all, std::span<const int> rows) {
  testpieces::MeasuredObservations out;
  out.feature_names = all.feature_names;
  for (int i : rows) {
    out.observations.push_back(all.observations[static_cast<std::size_t>(i)]);
    if (!all.point_index.empty()) out.point_index.push_back(all.point_index[static_cast<std::size_t>(i)]);
  }
  return out;
}

void ListFlagged(const OutlierScreen& s, const testpieces::MeasuredObservations& mo, bool left_out,
                 std::vector<ScreenedPoint>* points, std::vector<LocalDefect>* defects) {
  auto point_of = [&](int i) {
    return mo.point_index.empty() ? static_cast<std::size_t>(i) : mo.point_index[static_cast<std::size_t>(i)];
  };
  auto feature_of = [&](int i) {
    return mo.feature_names[static_cast<std::size_t>(mo.observations[static_cast<std::size_t>(i)].group)];
  };
  for (std::size_t i = 0; i < s.flag.size(); ++i) {
    if (s.flag[i] == ScreenFlag::kKept) continue;
    const int k = static_cast<int>(i);
    points->push_back({point_of(k), 0, feature_of(k), s.flag[i] == ScreenFlag::kOutlier ? "outlier" : "local_defect",
                       s.residual_um(k), ScreenReason(s, k, feature_of(k)), left_out});
  }
  for (const auto& patch : s.patches) {
    LocalDefect d{feature_of(patch.members.front()), static_cast<int>(patch.members.size()), patch.peak_um,
                  patch.mean_um, patch.centre_mm, patch.extent_mm, {}, {}};
    for (int m : patch.members) d.point_index.push_back(point_of(m));
    defects->push_back(std::move(d));
  }
}

void AttachScreenLines(const PointSet& measured, std::vector<ScreenedPoint>* points, std::vector<LocalDefect>* defects) {
  for (auto& p : *points) p.line = measured.LineOf(p.point_index);
  for (auto& d : *defects) {
    d.lines.clear();
    for (std::size_t i : d.point_index) d.lines.push_back(measured.LineOf(i));
  }
}

std::string ScreenReason(const OutlierScreen& screen, int i, const std::string& feature) {
  const double r = screen.residual_um(i);
  if (screen.flag[static_cast<std::size_t>(i)] == ScreenFlag::kOutlier)
    return fmt::format("outlier: {:.2f} um from the fitted model, {:.2f} um from its neighbours on {} (noise {:.2f} um)", r,
                       screen.neighbour_dev_um(i), feature, screen.sigma_um);
  for (const auto& p : screen.patches)
    if (std::binary_search(p.members.begin(), p.members.end(), i))
      return fmt::format("local defect: one of {} neighbouring points on {} departing together (peak {:.2f} um over {:.1f} mm; noise {:.2f} um)",
                         p.members.size(), feature, p.peak_um, 2.0 * p.extent_mm, screen.sigma_um);
  return "kept";
}

}  // namespace tpcal::pipeline
