#include "pipeline/raw_scan_labeling.h"

#include <fmt/format.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include "core/parallel.h"

#include "pipeline/io/point_io.h"
#include "testpieces/probing_plan.h"

namespace tpcal::pipeline {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr double kDegToRad = std::numbers::pi / 180.0;
// A rotation maps the nominal piece onto itself when every mapped sample lies this close to the
// nominal surface of some feature (exact geometry in double: far below any real deviation).
constexpr double kSymmetryTol_mm = 1e-3;
constexpr int kMaxSymmetryOrder = 64;
// Nearest nominal sample farther than this: no correspondence (the default nominal sampling
// spaces levels up to ~20 mm apart on the tallest turned face).
constexpr double kNeighbourGate_mm = 20.0;

// Dense nominal sampling of the piece in the part frame, with a k-d tree.
struct NominalModel {
  std::vector<Vector3d> p_part_mm;
  std::vector<Vector3d> n_part;
  std::vector<int> feature;  // index into piece.features
  std::shared_ptr<pcl::KdTreeFLANN<pcl::PointXYZ>> tree;
  Vector3d centroid_mm = Vector3d::Zero();
  Matrix3d axes = Matrix3d::Identity();  // principal axes (columns), proper rotation
  Matrix3d normal_axes = Matrix3d::Identity();  // principal axes of the normals' orientation tensor
  Vector3d centre_mm = Vector3d::Zero();  // QuantileCentre of the samples, part frame

  // Indices of the k nearest samples to q (part frame).
  void Nearest(const Vector3d& q, int k, std::vector<int>* idx, std::vector<float>* d2) const {
    pcl::PointXYZ s(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
    idx->resize(static_cast<std::size_t>(k));
    d2->resize(static_cast<std::size_t>(k));
    const int found = tree->nearestKSearch(s, k, *idx, *d2);
    idx->resize(static_cast<std::size_t>(std::max(found, 0)));
    d2->resize(idx->size());
  }
};

// Centroid and principal axes (columns, ascending variance, right-handed) of points[indices].
void Principal(const std::vector<Vector3d>& pts, const std::vector<std::size_t>& indices, Vector3d* centroid,
               Matrix3d* axes) {
  Vector3d c = Vector3d::Zero();
  for (std::size_t i : indices) c += pts[i];
  c /= static_cast<double>(indices.size());
  Matrix3d cov = Matrix3d::Zero();
  for (std::size_t i : indices) cov += (pts[i] - c) * (pts[i] - c).transpose();
  Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
  Matrix3d v = es.eigenvectors();
  if (v.determinant() < 0) v.col(2) = -v.col(2);
  *centroid = c;
  *axes = v;
}

std::vector<std::size_t> Stride(std::size_t n, std::size_t want) {
  std::vector<std::size_t> out;
  if (want == 0 || n <= want) {
    for (std::size_t i = 0; i < n; ++i) out.push_back(i);
    return out;
  }
  const double step = static_cast<double>(n) / static_cast<double>(want);
  for (std::size_t k = 0; k < want; ++k) out.push_back(static_cast<std::size_t>(static_cast<double>(k) * step));
  return out;
}

// Principal axes (columns, right-handed) of the orientation tensor sum(n n^T) of unit normals:
// for a turned part the axis is one of them whatever the points' positions.
Matrix3d NormalAxes(const std::vector<Vector3d>& normals) {
  Matrix3d t = Matrix3d::Zero();
  for (const auto& n : normals) t += n * n.transpose();
  Eigen::SelfAdjointEigenSolver<Matrix3d> es(t);
  Matrix3d v = es.eigenvectors();
  if (v.determinant() < 0) v.col(2) = -v.col(2);
  return v;
}

// Per axis, the midpoint of the kCentreQuantile and 1 - kCentreQuantile quantiles: a centre
// that a few percent of stray points (fixture, dust) on one side do not move, unlike the
// bounding box, and that does not depend on the density as the centroid does.
constexpr double kCentreQuantile = 0.05;
Vector3d QuantileCentre(const std::vector<Vector3d>& pts) {
  Vector3d c;
  std::vector<double> v(pts.size());
  const auto lo = static_cast<std::ptrdiff_t>(kCentreQuantile * static_cast<double>(pts.size() - 1));
  const auto hi = static_cast<std::ptrdiff_t>((1.0 - kCentreQuantile) * static_cast<double>(pts.size() - 1));
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < pts.size(); ++i) v[i] = pts[i][a];
    std::nth_element(v.begin(), v.begin() + lo, v.end());
    const double q_lo = v[static_cast<std::size_t>(lo)];
    std::nth_element(v.begin(), v.begin() + hi, v.end());
    c[a] = 0.5 * (q_lo + v[static_cast<std::size_t>(hi)]);
  }
  return c;
}

Result<NominalModel> BuildNominal(const testpieces::TestPiece& piece, const testpieces::ProbingOptions& density) {
  auto plan = testpieces::MakeProbingPlan(piece, density);
  if (!plan.ok()) return plan.status().WithContext("nominal sampling for raw-scan labelling");
  std::map<std::string, int> index;
  for (std::size_t k = 0; k < piece.features.size(); ++k) index[piece.features[k].name] = static_cast<int>(k);
  NominalModel m;
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& q : plan->points) {
    auto it = index.find(q.feature);
    if (it == index.end()) continue;
    m.p_part_mm.push_back(q.point_part_mm);
    m.n_part.push_back(q.normal_part);
    m.feature.push_back(it->second);
    cloud->push_back(pcl::PointXYZ(static_cast<float>(q.point_part_mm.x()), static_cast<float>(q.point_part_mm.y()),
                                   static_cast<float>(q.point_part_mm.z())));
  }
  if (m.p_part_mm.size() < 10)
    return Status(StatusCode::kDegenerate, "the piece's nominal sampling has fewer than 10 points");
  m.tree = std::make_shared<pcl::KdTreeFLANN<pcl::PointXYZ>>();
  m.tree->setInputCloud(cloud);
  Principal(m.p_part_mm, Stride(m.p_part_mm.size(), 0), &m.centroid_mm, &m.axes);
  m.normal_axes = NormalAxes(m.n_part);
  m.centre_mm = QuantileCentre(m.p_part_mm);
  return m;
}

// Exact labelling of one point (part frame): feature index or -1, signed distance and normal.
struct PointLabel {
  int feature = PointSet::kUnlabelled;
  double distance_mm = 0.0;
  Vector3d normal = Vector3d::UnitZ();
};

class Labeler {
 public:
  Labeler(const testpieces::TestPiece& piece, const NominalModel& model, const RawScanLabelingOptions& o)
      : piece_(piece), model_(model), o_(o), cos_normal_(std::cos(o.normal_tolerance_deg * kDegToRad)) {}

  // `n_part` null: no normal check.
  PointLabel Label(const Vector3d& q_part, const Vector3d* n_part, double tolerance_mm) const {
    PointLabel best;
    double best_abs = tolerance_mm;
    model_.Nearest(q_part, o_.neighbours, &idx_, &d2_);
    int tried[16];
    int n_tried = 0;
    for (int s : idx_) {
      const int f = model_.feature[static_cast<std::size_t>(s)];
      if (std::find(tried, tried + n_tried, f) != tried + n_tried) continue;
      if (n_tried < 16) tried[n_tried++] = f;
      auto pr = testpieces::ProjectOnto(piece_.features[static_cast<std::size_t>(f)], q_part);
      if (!pr.ok() || !pr->in_patch) continue;
      if (n_part && n_part->dot(pr->normal) < cos_normal_) continue;
      const double a = std::abs(pr->signed_distance_mm);
      if (a <= best_abs) {
        best_abs = a;
        best = {f, pr->signed_distance_mm, pr->normal};
      }
    }
    return best;
  }

 private:
  const testpieces::TestPiece& piece_;
  const NominalModel& model_;
  const RawScanLabelingOptions& o_;
  double cos_normal_;
  mutable std::vector<int> idx_;
  mutable std::vector<float> d2_;
};

class Registration {
 public:
  Registration(const NominalModel& model, const PointSet& scan, const RawScanLabelingOptions& o)
      : model_(model), scan_(scan), cos_normal_(std::cos(o.normal_tolerance_deg * kDegToRad)) {}

  // Number of points of `indices` within `tol_mm` of the tangent plane of their nearest nominal
  // sample, normals agreeing.
  int Score(const Rigid3& part_from_cmm, const std::vector<std::size_t>& indices, double tol_mm) const {
    int inliers = 0;
    for (std::size_t i : indices) {
      if (Correspond(part_from_cmm, i) && std::abs(r_) <= tol_mm) ++inliers;
    }
    return inliers;
  }

  // Point-to-plane ICP with a shrinking gate; returns the refined part_from_cmm.
  Rigid3 Icp(Rigid3 part_from_cmm, const std::vector<std::size_t>& indices,
             const std::vector<double>& gates_mm) const {
    for (double gate : gates_mm) {
      for (int iter = 0; iter < 6; ++iter) {
        Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
        int used = 0;
        for (std::size_t i : indices) {
          if (!Correspond(part_from_cmm, i) || std::abs(r_) > gate) continue;
          Eigen::Matrix<double, 6, 1> j;
          j.head<3>() = q_.cross(n_);
          j.tail<3>() = n_;
          a += j * j.transpose();
          b += j * r_;
          ++used;
        }
        if (used < 12) break;
        a.diagonal().array() += 1e-9 * a.trace() + 1e-12;
        const Eigen::Matrix<double, 6, 1> d = -a.ldlt().solve(b);
        part_from_cmm = Twist(d) * part_from_cmm;
        if (d.head<3>().norm() < 1e-7 && d.tail<3>().norm() < 1e-5) break;  // 0.1 urad, 10 nm
      }
    }
    return part_from_cmm;
  }

  static Rigid3 Twist(const Eigen::Matrix<double, 6, 1>& d) {
    const Vector3d w = d.head<3>();
    Rigid3 t = Rigid3::Identity();
    if (w.norm() > 0) t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    t.translation() = d.tail<3>();
    return t;
  }

 private:
  // Sets q_ (point in part frame), n_ (nominal normal), r_ (signed distance to the tangent plane
  // of the nearest nominal sample). False when that sample is farther than kNeighbourGate_mm
  // (a few sample spacings) or the normals disagree.
  bool Correspond(const Rigid3& part_from_cmm, std::size_t i) const {
    q_ = part_from_cmm * scan_.xyz_mm[i];
    model_.Nearest(q_, 1, &idx_, &d2_);
    if (idx_.empty() || d2_[0] > kNeighbourGate_mm * kNeighbourGate_mm) return false;
    const auto s = static_cast<std::size_t>(idx_[0]);
    n_ = model_.n_part[s];
    if (scan_.has_normals() && (part_from_cmm.linear() * scan_.normal[i]).dot(n_) < cos_normal_) return false;
    r_ = n_.dot(q_ - model_.p_part_mm[s]);
    return true;
  }

  const NominalModel& model_;
  const PointSet& scan_;
  double cos_normal_;
  mutable std::vector<int> idx_;
  mutable std::vector<float> d2_;
  mutable Vector3d q_, n_;
  mutable double r_ = 0.0;
};

double RotationAngleDeg(const Matrix3d& a, const Matrix3d& b) {
  const double c = std::clamp(((a.transpose() * b).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) / kDegToRad;
}

Rigid3 RotationAbout(const Vector3d& axis, const Vector3d& point_mm, double angle_rad) {
  Rigid3 t = Rigid3::Identity();
  t.linear() = Eigen::AngleAxisd(angle_rad, axis).toRotationMatrix();
  t.translation() = point_mm - t.linear() * point_mm;
  return t;
}

// Feature of the nominal surface nearest to q (part frame), within tol_mm, or -1.
int FeatureAt(const testpieces::TestPiece& piece, const NominalModel& m, const Vector3d& q, const Vector3d& n,
              double tol_mm) {
  std::vector<int> idx;
  std::vector<float> d2;
  m.Nearest(q, 8, &idx, &d2);
  for (int s : idx) {
    const int f = m.feature[static_cast<std::size_t>(s)];
    auto pr = testpieces::ProjectOnto(piece.features[static_cast<std::size_t>(f)], q);
    if (pr.ok() && pr->in_patch && std::abs(pr->signed_distance_mm) <= tol_mm && pr->normal.dot(n) > 0.999) return f;
  }
  return -1;
}

// Rotational symmetry of the nominal piece about one of its principal axes (through the nominal
// centroid) that permutes feature labels: its order N and the permutations perm[k][f] of the
// rotations by 2 pi k / N. N = 1 when none.
struct Symmetry {
  int order = 1;
  Vector3d axis = Vector3d::UnitZ();
  std::vector<std::vector<int>> perm;
};

Symmetry FindSymmetry(const testpieces::TestPiece& piece, const NominalModel& m) {
  const auto probe = Stride(m.p_part_mm.size(), 300);
  auto maps_onto_itself = [&](const Rigid3& s) {
    for (std::size_t i : probe) {
      if (FeatureAt(piece, m, s * m.p_part_mm[i], s.linear() * m.n_part[i], kSymmetryTol_mm) < 0) return false;
    }
    return true;
  };
  for (int j = 0; j < 3; ++j) {
    const Vector3d axis = m.axes.col(j);
    for (int n = kMaxSymmetryOrder; n >= 2; --n) {
      const Rigid3 s = RotationAbout(axis, m.centroid_mm, 2.0 * std::numbers::pi / n);
      if (!maps_onto_itself(s)) continue;
      Symmetry sym;
      sym.order = n;
      sym.axis = axis;
      bool permutes = false;
      for (int k = 0; k < n; ++k) {
        const Rigid3 sk = RotationAbout(axis, m.centroid_mm, 2.0 * std::numbers::pi * k / n);
        std::vector<int> perm(piece.features.size(), -1);
        for (std::size_t i = 0; i < m.p_part_mm.size(); ++i) {
          const auto f = static_cast<std::size_t>(m.feature[i]);
          if (perm[f] >= 0) continue;
          perm[f] = FeatureAt(piece, m, sk * m.p_part_mm[i], sk.linear() * m.n_part[i], kSymmetryTol_mm);
          if (perm[f] < 0) perm[f] = static_cast<int>(f);  // sample off every patch: keep
          if (perm[f] != static_cast<int>(f)) permutes = true;
        }
        sym.perm.push_back(std::move(perm));
      }
      if (permutes) return sym;
      break;  // a symmetry that keeps every label: irrelevant for this axis
    }
  }
  return {};
}

}  // namespace

testpieces::ProbingOptions RawScanLabelingOptions::DefaultNominalDensity() {
  testpieces::ProbingOptions o;
  o.points_per_circle = 256;
  o.levels_per_face = 12;
  o.points_per_hole = 24;
  o.levels_per_hole = 4;
  o.points_per_line = 80;
  o.grid_per_side = 24;
  return o;
}

Status RawScanLabelingOptions::Validate() const {
  auto bad = [](const std::string& m) { return Status(StatusCode::kInvalidArgument, "raw-scan labelling: " + m); };
  if (!(label_tolerance_mm > 0)) return bad("label_tolerance_mm must be > 0");
  if (!(normal_tolerance_deg > 0 && normal_tolerance_deg < 90)) return bad("normal_tolerance_deg must be in (0, 90)");
  if (!(coarse_step_deg >= 1 && coarse_step_deg <= 90)) return bad("coarse_step_deg must be in [1, 90]");
  if (!(coarse_tolerance_mm > 0)) return bad("coarse_tolerance_mm must be > 0");
  if (coarse_sample_points < 20 || icp_sample_points < 20) return bad("sample point counts must be >= 20");
  if (refine_candidates < 1) return bad("refine_candidates must be >= 1");
  if (neighbours < 1 || neighbours > 64) return bad("neighbours must be in [1, 64]");
  if (!(min_labelled_fraction > 0 && min_labelled_fraction <= 1)) return bad("min_labelled_fraction must be in (0, 1]");
  if (!(max_rms_um > 0)) return bad("max_rms_um must be > 0");
  if (min_points < 10) return bad("min_points must be >= 10");
  if (anchor_feature.empty() != !anchor_near_mm.has_value())
    return bad("anchor_feature and anchor_near_mm go together");
  if (anchor_near_mm && !anchor_near_mm->allFinite()) return bad("anchor_near_mm must be finite");
  return nominal_density.Validate();
}

std::string RawScanLabeling::BriefReport() const {
  std::string s = fmt::format("{} points: {} labelled ({:.1f} %), {} rejected, RMS {:.1f} um", num_points,
                              num_points - num_rejected, 100.0 * labelled_fraction, num_rejected, rms_distance_um);
  if (symmetry_order > 1) s += fmt::format(", symmetry of order {} resolved by {}", symmetry_order, symmetry_resolved_by);
  s += ";";
  for (const auto& c : counts) s += fmt::format(" {} {}", c.feature, c.points);
  return s;
}

Result<RawScanLabeling> LabelRawScan(const testpieces::TestPiece& piece, const PointSet& scan,
                                     const RawScanLabelingOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  const std::string& source = scan.source;
  if (scan.size() < options.min_points)
    return Status(StatusCode::kTooFewPoints,
                  fmt::format("raw scan has {} points; labelling needs at least {}", scan.size(), options.min_points),
                  source);
  auto built = BuildNominal(piece, options.nominal_density);
  if (!built.ok()) return built.status().WithLocation(source);
  const NominalModel& model = *built;
  Registration reg(model, scan, options);
  Labeler labeler(piece, model, options);

  // ---- coarse: principal frames, rotation sweeps, robust centres ----
  const auto all = Stride(scan.size(), 0);
  const auto coarse_idx = Stride(scan.size(), static_cast<std::size_t>(options.coarse_sample_points));
  const auto icp_idx = Stride(scan.size(), static_cast<std::size_t>(options.icp_sample_points));
  const auto centre_idx = Stride(scan.size(), 5000);
  Vector3d scan_centroid;
  Matrix3d scan_axes;
  Principal(scan.xyz_mm, all, &scan_centroid, &scan_axes);
  // Frame pairs (nominal, scan) whose matching gives candidate rotations: the points' principal
  // axes, and with normals the normals' orientation tensor (not moved by stray points whose
  // normals follow the piece's, e.g. a fixture plate under a turned part).
  std::vector<std::pair<Matrix3d, Matrix3d>> frames = {{model.axes, scan_axes}};
  if (scan.has_normals()) frames.emplace_back(model.normal_axes, NormalAxes(scan.normal));

  struct Candidate {
    Rigid3 part_from_cmm;
    int score = 0;
  };
  std::vector<Candidate> candidates;
  const int steps = static_cast<int>(std::lround(360.0 / options.coarse_step_deg));
  std::vector<Vector3d> rotated(centre_idx.size());
  for (const auto& [nominal_axes, scan_frame] : frames) {
    for (int j = 0; j < 3; ++j) {
      for (int flip = 0; flip < 2; ++flip) {
        Vector3d signs = Vector3d::Ones();
        if (flip) {
          signs[j] = -1;
          signs[(j + 1) % 3] = -1;
        }
        const Matrix3d r0 = nominal_axes * signs.asDiagonal() * scan_frame.transpose();
        for (int k = 0; k < steps; ++k) {
          const Matrix3d r =
              Eigen::AngleAxisd(2.0 * std::numbers::pi * k / steps, nominal_axes.col(j)).toRotationMatrix() * r0;
          for (std::size_t i = 0; i < centre_idx.size(); ++i) rotated[i] = r * scan.xyz_mm[centre_idx[i]];
          Rigid3 t = Rigid3::Identity();
          t.linear() = r;
          t.translation() = model.centre_mm - QuantileCentre(rotated);
          candidates.push_back({t, reg.Score(t, coarse_idx, options.coarse_tolerance_mm)});
        }
      }
    }
  }
  const int candidates_scored = static_cast<int>(candidates.size());
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });

  // ---- refinement of the best distinct candidates ----
  const double fine_range_deg = options.coarse_step_deg;
  std::vector<Rigid3> starts;
  for (const auto& c : candidates) {
    if (static_cast<int>(starts.size()) >= options.refine_candidates) break;
    bool distinct = true;
    for (const auto& s : starts)
      if (RotationAngleDeg(s.linear(), c.part_from_cmm.linear()) < 2.0 * options.coarse_step_deg) distinct = false;
    if (distinct) starts.push_back(c.part_from_cmm);
  }
  struct Refined {
    Rigid3 part_from_cmm;
    std::vector<PointLabel> labels;
    std::size_t labelled = 0;
    double rms_mm = 0.0;
  };
  // Labels of scan points `indices` (others stay unlabelled) at placement t. Large sets are split
  // over threads (each point's label depends on that point only; sums are taken in order after).
  auto label_points = [&](const Rigid3& t, const std::vector<std::size_t>& indices) {
    Refined out{t, std::vector<PointLabel>(scan.size()), 0, 0.0};
    auto work = [&](std::size_t begin, std::size_t end) {
      Labeler local(piece, model, options);  // per-thread query buffers
      for (std::size_t k = begin; k < end; ++k) {
        const std::size_t i = indices[k];
        const Vector3d q = t * scan.xyz_mm[i];
        Vector3d n;
        if (scan.has_normals()) n = t.linear() * scan.normal[i];
        out.labels[i] = local.Label(q, scan.has_normals() ? &n : nullptr, options.label_tolerance_mm);
      }
    };
    // One chunk per thread at most: each builds its own Labeler.
    ParallelChunks(indices.size(), std::max(kParallelMinPoints, indices.size() / HardwareThreads() + 1),
                   [&](std::size_t begin, std::size_t end) {
                     work(begin, end);
                     return true;
                   });
    double ss = 0.0;
    for (std::size_t i : indices) {
      if (out.labels[i].feature == PointSet::kUnlabelled) continue;
      ++out.labelled;
      ss += out.labels[i].distance_mm * out.labels[i].distance_mm;
    }
    out.rms_mm = out.labelled ? std::sqrt(ss / static_cast<double>(out.labelled)) : 0.0;
    return out;
  };
  // ICP against the exact surfaces of the labelled features (a few Gauss-Newton steps).
  auto exact_icp = [&](Rigid3 t) {
    for (int iter = 0; iter < 3; ++iter) {
      Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      int used = 0;
      for (std::size_t i : icp_idx) {
        const Vector3d q = t * scan.xyz_mm[i];
        Vector3d n;
        if (scan.has_normals()) n = t.linear() * scan.normal[i];
        const PointLabel l = labeler.Label(q, scan.has_normals() ? &n : nullptr, 2.0 * options.label_tolerance_mm);
        if (l.feature == PointSet::kUnlabelled) continue;
        Eigen::Matrix<double, 6, 1> j;
        j.head<3>() = q.cross(l.normal);
        j.tail<3>() = l.normal;
        a += j * j.transpose();
        b += j * l.distance_mm;
        ++used;
      }
      if (used < 12) break;
      a.diagonal().array() += 1e-9 * a.trace() + 1e-12;
      t = Registration::Twist(-a.ldlt().solve(b)) * t;
    }
    return t;
  };

  // Quick ICP of every start on the scoring subsample; the two best go on to the fine sweep.
  std::vector<Candidate> quick;
  for (const Rigid3& start : starts) {
    const Rigid3 t = reg.Icp(start, coarse_idx, {20.0, 10.0, 5.0, 2.0});
    quick.push_back({t, reg.Score(t, coarse_idx, options.coarse_tolerance_mm)});
  }
  std::stable_sort(quick.begin(), quick.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  if (quick.size() > 2) quick.resize(2);
  std::optional<Refined> best;
  for (const Candidate& q : quick) {
    // Fine sweep about each nominal principal axis to seat symmetry-breaking features (holes).
    Rigid3 best_t = q.part_from_cmm;
    int best_score = q.score;
    for (int j = 0; j < 3; ++j) {
      for (double a_deg = -fine_range_deg; a_deg <= fine_range_deg + 1e-9; a_deg += 1.0) {
        if (a_deg == 0.0) continue;
        const Rigid3 s =
            RotationAbout(model.axes.col(j), model.centroid_mm, a_deg * kDegToRad) * q.part_from_cmm;
        const int sc = reg.Score(s, coarse_idx, options.coarse_tolerance_mm);
        if (sc > best_score) {
          best_score = sc;
          best_t = s;
        }
      }
    }
    const Rigid3 t = exact_icp(reg.Icp(reg.Icp(best_t, coarse_idx, {5.0, 2.0}), icp_idx, {1.0, 0.5}));
    Refined r = label_points(t, icp_idx);  // the choice between candidates: on the ICP subsample
    if (!best || r.labelled > best->labelled || (r.labelled == best->labelled && r.rms_mm < best->rms_mm))
      best = std::move(r);
  }
  if (!best) return Status(StatusCode::kInternal, "raw-scan labelling: no candidate placement", source);
  if (icp_idx.size() < scan.size()) best = label_points(best->part_from_cmm, all);

  const double fraction = static_cast<double>(best->labelled) / static_cast<double>(scan.size());
  if (fraction < options.min_labelled_fraction || best->rms_mm * 1e3 > options.max_rms_um)
    return Status(StatusCode::kNotConverged,
                  fmt::format("raw scan registration to the nominal {} failed: the best of {} candidate placements "
                              "puts {:.1f} % of the {} points within {} mm of a nominal feature (needs {:.1f} %), "
                              "RMS {:.1f} um (limit {:.1f} um); is this a scan of that piece?",
                              piece.name, candidates_scored, 100.0 * fraction, scan.size(),
                              options.label_tolerance_mm, 100.0 * options.min_labelled_fraction, best->rms_mm * 1e3,
                              options.max_rms_um),
                  source);

  // ---- symmetry: choose among equivalent placements by the anchor, else by file order ----
  const Symmetry sym = FindSymmetry(piece, model);
  int chosen = 0;
  std::string message = fmt::format("best of {} coarse placements, {} refined", candidates_scored, starts.size());
  if (sym.order > 1) {
    auto less = [&](int ka, int kb) {  // lexicographic order of labels in file order
      for (const auto& l : best->labels) {
        if (l.feature == PointSet::kUnlabelled) continue;
        const int fa = sym.perm[static_cast<std::size_t>(ka)][static_cast<std::size_t>(l.feature)];
        const int fb = sym.perm[static_cast<std::size_t>(kb)][static_cast<std::size_t>(l.feature)];
        if (fa != fb) return fa < fb;
      }
      return false;
    };
    int anchor = -1;  // piece feature index of the anchor
    for (std::size_t f = 0; f < piece.features.size(); ++f)
      if (piece.features[f].name == options.anchor_feature) anchor = static_cast<int>(f);
    if (options.anchor_near_mm && anchor < 0)
      return Status(StatusCode::kInvalidArgument,
                    "raw-scan anchor: '" + options.anchor_feature + "' is not a feature of the " + piece.name, source);
    if (options.anchor_near_mm) {
      // Nominal centroid of the anchor feature (part frame); in labelling k it sits at
      // (S_k part_from_cmm)^-1 of it in the scan frame.
      Vector3d c_part = Vector3d::Zero();
      int m = 0;
      for (std::size_t j = 0; j < model.feature.size(); ++j)
        if (model.feature[j] == anchor) c_part += model.p_part_mm[j], ++m;
      c_part /= std::max(1, m);
      double best_d = std::numeric_limits<double>::infinity();
      for (int k = 0; k < sym.order; ++k) {
        const Rigid3 s_k = RotationAbout(sym.axis, model.centroid_mm, 2.0 * std::numbers::pi * k / sym.order);
        const double d = ((s_k * best->part_from_cmm).inverse() * c_part - *options.anchor_near_mm).norm();
        if (d < best_d) best_d = d, chosen = k;
      }
      message += fmt::format(
          "; the nominal piece is symmetric under rotations by 360/{} deg about its axis, which permute feature labels: "
          "of the {} equivalent labellings the one placing {} nearest the anchor ({:.1f} mm from it) was chosen "
          "(rotation {})",
          sym.order, sym.order, options.anchor_feature, best_d, chosen);
    } else {
      for (int k = 1; k < sym.order; ++k)
        if (less(k, chosen)) chosen = k;
      message += fmt::format(
          "; the nominal piece is symmetric under rotations by 360/{} deg about its axis, which permute feature labels: "
          "of the {} equivalent labellings the one listing features in plan order in the file was chosen (rotation {})",
          sym.order, sym.order, chosen);
    }
  }
  const Rigid3 s_chosen = RotationAbout(sym.axis, model.centroid_mm, 2.0 * std::numbers::pi * chosen / sym.order);

  RawScanLabeling out;
  out.part_from_cmm = s_chosen * best->part_from_cmm;
  out.num_points = scan.size();
  out.piece_feature.assign(scan.size(), PointSet::kUnlabelled);
  std::vector<std::size_t> per_feature(piece.features.size(), 0);
  double ss = 0.0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const auto& l = best->labels[i];
    if (l.feature == PointSet::kUnlabelled) continue;
    const int f = sym.order > 1 ? sym.perm[static_cast<std::size_t>(chosen)][static_cast<std::size_t>(l.feature)]
                                : l.feature;
    out.piece_feature[i] = f;
    ++per_feature[static_cast<std::size_t>(f)];
    ss += l.distance_mm * l.distance_mm;
  }
  out.labelled.source = scan.source;
  // Names of the features that received points, in the piece's order.
  std::vector<int> label_of_feature(piece.features.size(), PointSet::kUnlabelled);
  for (std::size_t f = 0; f < piece.features.size(); ++f)
    if (per_feature[f] > 0) label_of_feature[f] = out.labelled.InternFeature(piece.features[f].name);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (out.piece_feature[i] == PointSet::kUnlabelled) continue;
    out.labelled.xyz_mm.push_back(scan.xyz_mm[i]);
    if (scan.has_normals()) out.labelled.normal.push_back(scan.normal[i]);
    out.labelled.feature.push_back(label_of_feature[static_cast<std::size_t>(out.piece_feature[i])]);
    if (!scan.line.empty()) out.labelled.line.push_back(scan.line[i]);
  }
  // Numeric and text attributes follow their points.
  for (const auto& a : scan.attributes) {
    PointAttribute b{a.name, {}, {}};
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (out.piece_feature[i] == PointSet::kUnlabelled) continue;
      if (a.is_numeric())
        b.values.push_back(a.values[i]);
      else
        b.text.push_back(a.text[i]);
    }
    out.labelled.attributes.push_back(std::move(b));
  }
  for (std::size_t f = 0; f < piece.features.size(); ++f)
    out.counts.push_back({piece.features[f].name, per_feature[f]});
  out.num_rejected = scan.size() - best->labelled;
  out.labelled_fraction = fraction;
  out.rms_distance_um = 1e3 * std::sqrt(ss / static_cast<double>(best->labelled));
  out.candidates_scored = candidates_scored;
  out.symmetry_order = sym.order;
  if (sym.order > 1) out.symmetry_resolved_by = options.anchor_near_mm ? "anchor " + options.anchor_feature : "file order";
  out.message = std::move(message);
  return out;
}

Result<std::optional<RawScanLabeling>> LabelIfRawScan(const testpieces::TestPiece& piece, PointSet* points,
                                                      const RawScanLabelingOptions& options) {
  if (points->has_labels()) return std::optional<RawScanLabeling>();
  auto labelled = LabelRawScan(piece, *points, options);
  if (!labelled.ok()) return labelled.status();
  *points = std::move(labelled->labelled);
  labelled->labelled = PointSet{};
  labelled->piece_feature.clear();
  return std::optional<RawScanLabeling>(std::move(*labelled));
}

Result<LabelledPoints> ReadLabelledPoints(const std::string& path, const testpieces::TestPiece& piece,
                                          const RawScanLabelingOptions& options, const PointReadOptions& read) {
  auto points = ReadPoints(path, read);
  if (!points.ok()) return points.status();
  auto labelled = LabelIfRawScan(piece, &*points, options);
  if (!labelled.ok()) return labelled.status();
  return LabelledPoints{std::move(*points), std::move(*labelled)};
}

}  // namespace tpcal::pipeline
