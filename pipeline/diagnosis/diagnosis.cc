#include "pipeline/diagnosis/diagnosis.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>

#include "core/parallel.h"
#include "core/tall_qr.h"
#include "core/tall_svd.h"
#include "core/units.h"
#include "gdt/inspection.h"
#include "testpieces/default_parameters.h"
#include "kinematics/identification.h"
#include "pipeline/diagnosis/diagnosis_candidates.h"
#include "pipeline/diagnosis/diagnosis_cv.h"
#include "testpieces/point_association.h"

namespace tpcal::pipeline {
namespace {

// Numerical rank: the base model absorbs every direction it can fit, however weakly (identification
// reports directions below 1e-3 of the strongest as not identifiable, kinematics/identification.h).
constexpr double kBaseRankTolerance = 1e-7;
constexpr double kMinLeverage = 1e-9;
// From this many points the candidates are evaluated on several threads (below, threads cost more
// than they save: a candidate of the 352-point sample takes ~0.3 ms).
constexpr Eigen::Index kParallelPoints = 20000;        // 1 - h below this: the point fits itself (PRESS huge)

// Orthonormal basis of the column space of J (columns scaled to unit norm first).
struct Basis {
  Eigen::MatrixXd U;        // n x r
  Eigen::MatrixXd V;        // p x p (scaled coordinates)
  Eigen::VectorXd sigma;    // p
  Eigen::VectorXd scale;    // p: column norms (0 for zero columns)
  int rank = 0;
};

Basis MakeBasis(const Eigen::MatrixXd& J, const Eigen::VectorXd& norms, double rel_tol, bool relative_to_largest) {
  Basis b;
  b.scale = norms;
  Eigen::MatrixXd Js = J;
  for (Eigen::Index j = 0; j < J.cols(); ++j) Js.col(j) = norms(j) > 0 ? Eigen::VectorXd(J.col(j) / norms(j)) : Eigen::VectorXd::Zero(J.rows());
  if (J.cols() == 0) {
    b.U.resize(J.rows(), 0);
    return b;
  }
  TallSvdResult svd = TallSvd(Js, /*compute_u=*/true);
  b.sigma = std::move(svd.sigma);
  b.V = std::move(svd.V);
  const double ref = relative_to_largest ? (b.sigma.size() ? b.sigma(0) : 0.0) : 1.0;
  for (Eigen::Index k = 0; k < b.sigma.size(); ++k)
    if (b.sigma(k) > rel_tol * ref && b.sigma(k) > 0) ++b.rank;
  b.U = svd.U.leftCols(b.rank);
  return b;
}

// Column norms; a column below kRoundingColumn x the largest is rounding of an exactly zero
// signature (e.g. E_Z0A on the flank-milled cone, 3e-15 um/um: Z slides the tool along its own
// axis) and gets norm 0 (not fitted, not identifiable): scaled to unit norm it would be a random
// direction, fitted with coefficients of 1e12 mm.
constexpr double kRoundingColumn = 1e-10;
Eigen::VectorXd ZeroRoundingColumns(Eigen::VectorXd n) {
  const double largest = n.size() ? n.maxCoeff() : 0.0;
  for (Eigen::Index j = 0; j < n.size(); ++j)
    if (n(j) <= kRoundingColumn * largest) n(j) = 0.0;
  return n;
}
Eigen::VectorXd ColumnNorms(const Eigen::MatrixXd& J) {
  Eigen::VectorXd n(J.cols());
  for (Eigen::Index j = 0; j < J.cols(); ++j) n(j) = J.col(j).norm();
  return ZeroRoundingColumns(std::move(n));
}

// A candidate's columns (or two candidates' for a joint fit), each n long.
using Columns = std::vector<Eigen::Map<const Eigen::VectorXd>>;
Columns ColumnsOf(const CandidateColumns& c) {
  Columns out;
  for (Eigen::Index j = 0; j < c.cols(); ++j) out.push_back(c.col(j));
  return out;
}
Eigen::VectorXd ColumnNorms(const Columns& C) {
  Eigen::VectorXd n(static_cast<Eigen::Index>(C.size()));
  for (std::size_t j = 0; j < C.size(); ++j) n(static_cast<Eigen::Index>(j)) = C[j].norm();
  return ZeroRoundingColumns(std::move(n));
}

// Coefficients (original column units) of the least-squares fit of y on the basis' columns,
// minimum-norm in scaled units, and their analytic standard uncertainties for residual variance s2.
void Solve(const Basis& b, const Eigen::VectorXd& y, double s2, Eigen::VectorXd* coef, Eigen::VectorXd* u,
           std::vector<bool>* identifiable) {
  const Eigen::Index p = b.scale.size();
  coef->setZero(p);
  u->setZero(p);
  identifiable->assign(static_cast<std::size_t>(p), true);
  if (p == 0) return;
  const Eigen::MatrixXd Vr = b.V.leftCols(b.rank);
  Eigen::VectorXd z = b.U.transpose() * y;
  for (int k = 0; k < b.rank; ++k) z(k) /= b.sigma(k);
  Eigen::VectorXd c = Vr * z;
  Eigen::MatrixXd W = Vr;
  for (int k = 0; k < b.rank; ++k) W.col(k) /= b.sigma(k);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double s = b.scale(j) > 0 ? b.scale(j) : 1.0;
    (*coef)(j) = c(j) / s;
    (*u)(j) = std::sqrt(s2 * W.row(j).squaredNorm()) / s;
    const double null_part = b.rank < p ? b.V.row(j).tail(p - b.rank).norm() : 0.0;
    if (null_part > 1e-6 || b.scale(j) == 0) (*identifiable)[static_cast<std::size_t>(j)] = false;
  }
}

// Upper tail of the F distribution (Paulson's normal approximation; adequate for d2 > 30).
double FUpperTail(double f, double d1, double d2) {
  if (!(f > 0) || d1 <= 0 || d2 <= 0) return 1.0;
  const double a = 2.0 / (9.0 * d1), b = 2.0 / (9.0 * d2);
  const double c = std::cbrt(f);
  const double z = ((1.0 - b) * c - (1.0 - a)) / std::sqrt(a + b * c * c);
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

double Rms(const Eigen::VectorXd& r) { return r.size() ? std::sqrt(r.squaredNorm() / static_cast<double>(r.size())) : 0.0; }

Eigen::VectorXd Press(const Eigen::VectorXd& r, const Eigen::VectorXd& h) {
  Eigen::VectorXd e(r.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) e(i) = r(i) / std::max(1.0 - h(i), kMinLeverage);
  return e;
}

Eigen::VectorXd RowSquaredNorms(const Eigen::MatrixXd& U) {
  Eigen::VectorXd h = Eigen::VectorXd::Zero(U.rows());
  if (U.cols() > 0) h = U.rowwise().squaredNorm();
  return h;
}

struct ProjectedCandidate {
  Basis basis;            // of the candidate columns projected on the complement of the base
  Eigen::VectorXd fitted; // in the residual space
};

// A candidate's columns C (n x p) seen through the complement of the span of Q (orthonormal,
// the base design). span(C) is orthonormalised first (relative rank tolerance 1e-10 on unit-norm
// columns); its directions whose principal angle to span(Q) has a sine below `tol` are absorbed.
// The kept directions give the basis U (n x k) of the fit on the residual; a fit z = U^T r maps
// back to C's coefficients x = B z (p x k, C's own units), cov(x) = sigma^2 B B^T.
struct Projected {
  Eigen::MatrixXd U, B;
  std::vector<bool> identifiable;
  int rank = 0;
  double max_sine = 0.0;  // of the principal angles to the base: the share of the most visible direction
  double rms_sine = 0.0;  // RMS over span(C)'s directions: the share of a typical signature
};

Projected ProjectCandidate(const Columns& C, const Eigen::MatrixXd& Q, double tol) {
  Projected out;
  const Eigen::Index n = Q.rows(), p = static_cast<Eigen::Index>(C.size());
  out.identifiable.assign(static_cast<std::size_t>(p), false);
  out.U.resize(n, 0);
  out.B.resize(p, 0);
  if (p == 0) return out;
  const Eigen::VectorXd norms = ColumnNorms(C);
  // One n x p buffer and one QR, by row blocks and in place (core/tall_qr.h): at 2e6 points the
  // first-touch page faults of copies and the passes of a second n x p QR cost more than the rest.
  // With C_s = C diag(1/norms) (unit-norm columns), X = Q^T C_s and (I - Q Q^T) C_s = Q_2 R_2:
  // C_s = Q X + Q_2 R_2 with Q^T Q_2 = 0, so the small [X; R_2] has the Gram matrix of C_s, hence
  // its singular values and right vectors (no QR of C_s itself).
  Eigen::MatrixXd W(n, p);
  for (Eigen::Index j = 0; j < p; ++j)
    if (norms(j) > 0)
      W.col(j) = C[static_cast<std::size_t>(j)] / norms(j);
    else
      W.col(j).setZero();
  Eigen::MatrixXd X(Q.cols(), p);
  if (Q.cols() > 0) {
    X.noalias() = Q.transpose() * W;
    W.noalias() -= Q * X;
  }
  const TallQr qr2(&W);
  const Eigen::MatrixXd R2 = qr2.R();
  // 1. span(C): singular values S_c and right vectors V_c of C_s.
  Eigen::VectorXd sc;
  Eigen::MatrixXd Vc;
  {
    Eigen::MatrixXd S(X.rows() + R2.rows(), p);
    S << X, R2;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(S, Eigen::ComputeFullV);
    sc = svd.singularValues();
    Vc = svd.matrixV();
  }
  int rc = 0;
  for (Eigen::Index k = 0; k < sc.size(); ++k)
    if (sc(k) > 1e-10 * sc(0) && sc(k) > 0) ++rc;
  if (rc == 0) return out;
  // 2. The orthonormal basis U_c = C_s V_c S_c^-1 of span(C) seen through the complement of
  // span(Q): P = (I - Q Q^T) U_c = Q_2 M with M = R_2 V_c S_c^-1 (m x rc). The SVD of M is that
  // of P; its singular values are the sines of the principal angles between span(C) and span(Q).
  Eigen::MatrixXd Vcr = Vc.leftCols(rc);
  for (int j = 0; j < rc; ++j) Vcr.col(j) /= sc(j);
  const Eigen::MatrixXd M = R2 * Vcr;
  Eigen::JacobiSVD<Eigen::MatrixXd> msvd(M, Eigen::ComputeThinU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = msvd.singularValues();
  out.max_sine = s.size() > 0 ? s(0) : 0.0;
  out.rms_sine = s.size() > 0 ? std::sqrt(s.squaredNorm() / static_cast<double>(rc)) : 0.0;
  int k = 0;
  while (k < s.size() && s(k) > tol) ++k;
  out.rank = k;
  if (k == 0) return out;
  out.U = qr2.ApplyQ(msvd.matrixU().leftCols(k));
  // x_scaled = V_c S_c^-1 (V_p S_p^-1) z; x = x_scaled / norms.
  Eigen::MatrixXd Vp = msvd.matrixV().leftCols(k);
  for (int j = 0; j < k; ++j) Vp.col(j) /= s(j);
  out.B = Vcr * Vp;
  for (Eigen::Index j = 0; j < p; ++j) out.B.row(j) /= (norms(j) > 0 ? norms(j) : 1.0);
  // Identifiable coefficients: e_j in the row space of the determined functionals F = V_p^T S_c V_c^T.
  const Eigen::MatrixXd Ft = Vc.leftCols(rc) * sc.head(rc).asDiagonal() * msvd.matrixV().leftCols(k);
  Eigen::JacobiSVD<Eigen::MatrixXd> fsvd(Ft, Eigen::ComputeThinU);
  int fr = 0;
  for (Eigen::Index j = 0; j < fsvd.singularValues().size(); ++j)
    if (fsvd.singularValues()(j) > 1e-9 * fsvd.singularValues()(0)) ++fr;
  const Eigen::MatrixXd Qf = fsvd.matrixU().leftCols(fr);
  for (Eigen::Index j = 0; j < p; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(p);
    e(j) = 1.0;
    out.identifiable[static_cast<std::size_t>(j)] = norms(j) > 0 && (e - Qf * (Qf.transpose() * e)).norm() < 1e-6;
  }
  return out;
}

void GroupStats(const std::map<std::string, std::vector<Eigen::Index>>& groups, const Eigen::VectorXd& r,
                const std::vector<double>& t_s, double sigma, double z_out, std::vector<GroupGap>* out,
                std::vector<std::string>* standing, const std::string& prefix) {
  for (const auto& [name, idx] : groups) {
    GroupGap g;
    g.group = name;
    g.n_points = static_cast<int>(idx.size());
    double ss = 0, sum = 0, tsum = 0;
    for (auto i : idx) {
      ss += r(i) * r(i);
      sum += r(i);
      tsum += t_s[static_cast<std::size_t>(i)];
      g.max_abs_um = std::max(g.max_abs_um, std::abs(r(i)));
    }
    const double n = static_cast<double>(idx.size());
    g.rms_um = std::sqrt(ss / n);
    g.mean_um = sum / n;
    g.mean_t_s = tsum / n;
    g.z = sigma > 0 ? (ss / (sigma * sigma) - n) / std::sqrt(2.0 * n) : 0.0;
    g.stands_out = g.z > z_out;
    if (g.stands_out) standing->push_back(prefix + name);
    out->push_back(g);
  }
}

}  // namespace

Status DiagnosisOptions::Validate() const {
  if (!(alpha > 0 && alpha < 1)) return {StatusCode::kInvalidArgument, "diagnosis alpha must be in (0, 1)"};
  if (!(absorbed_tolerance > 0 && absorbed_tolerance < 1))
    return {StatusCode::kInvalidArgument, "diagnosis absorbed_tolerance must be in (0, 1)"};
  if (!(noise_um >= 0)) return {StatusCode::kInvalidArgument, "diagnosis noise_um must be >= 0"};
  if (!(alias_capture > 0 && alias_capture <= 1))
    return {StatusCode::kInvalidArgument, "diagnosis alias_capture must be in (0, 1]"};
  if (max_harmonic < 1) return {StatusCode::kInvalidArgument, "diagnosis max_harmonic must be >= 1"};
  if (!(stand_out_z > 0)) return {StatusCode::kInvalidArgument, "diagnosis stand_out_z must be > 0"};
  if (!(holdout_tolerance > 0 && holdout_tolerance < 1))
    return {StatusCode::kInvalidArgument, "diagnosis holdout_tolerance must be in (0, 1)"};
  if (!(reference_match_mm > 0)) return {StatusCode::kInvalidArgument, "diagnosis reference_match_mm must be > 0"};
  return {};
}

namespace {

// The diagnosis; `reference_dev_um` (per observation, or null): the point reference's normal
// deviations, subtracted from the measured ones (DiagnoseAgainstPoints).
// The slots one linearisation writes: the base coefficients' and every machine-error candidate's.
std::vector<kinematics::ErrorSlot> DiagnosisSlotUnion(const kinematics::ErrorState& errors, const std::vector<int>& base_coefficients,
                                     const std::vector<kinematics::ErrorSlot>& candidate_slots) {
  std::vector<kinematics::ErrorSlot> slots = kinematics::SlotsOf(errors, base_coefficients);
  kinematics::AddSlots(candidate_slots, &slots);
  return slots;
}

Result<DiagnosisResult> DiagnoseImpl(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                     const testpieces::MeasuredObservations& mo, const DiagnosisOptions& options,
                                     const Eigen::VectorXd* reference_dev_um) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const auto& obs = mo.observations;
  const auto n = static_cast<Eigen::Index>(obs.size());
  const bool point_reference = reference_dev_um != nullptr;
  if (point_reference && options.reference)
    return Status(StatusCode::kInvalidArgument, "diagnosis: a reference point file and reference machine errors together");
  const bool reference_mode = options.reference.has_value() || point_reference;
  std::vector<std::string> base_names =
      options.base_parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.base_parameters;

  // ---- 1. Base model: the base set fitted (Gauss-Newton, two linearisations), or the reference.
  kinematics::ErrorState errors = options.reference ? *options.reference : kinematics::ErrorState(machine);
  kinematics::ActiveSet base_active;
  if (!base_names.empty()) {
    if (!reference_mode) {
      auto act = kinematics::ActivateParameters(machine, &errors, base_names);
      if (!act.ok()) return act.status();
      base_active = *act;
    } else {
      kinematics::ErrorState tmp = errors;
      auto act = kinematics::ActivateParameters(machine, &tmp, base_names);
      if (!act.ok()) return act.status();
      errors = tmp;
      base_active = *act;
    }
  }
  const int q_fit = reference_mode ? 0 : base_active.size();
  if (n <= q_fit + 6)
    return Status(StatusCode::kTooFewPoints, "diagnosis needs more than " + std::to_string(q_fit + 6) +
                                                 " points for the base model, got " + std::to_string(n));
  Eigen::MatrixXd X0;
  Eigen::VectorXd y;
  Basis base;
  Eigen::VectorXd base_coef, base_u;
  std::vector<bool> base_ident;
  // Gauss-Newton: a second linearisation at the fitted base only when the fit is large enough for
  // second-order terms to matter: |angle| > 1000 urad or |length| > 1000 um (below that they stay
  // under lever * angle^2 = 500 mm * 1e-6 = 5e-4 um, far below any CMM noise).
  int passes = 1;
  // One slot linearisation per pass serves the base model and (the last) every machine-error
  // candidate: the union of the slots both write.
  auto candidate_slots = CandidateSlots(piece, machine, errors, base_names, reference_mode);
  if (!candidate_slots.ok()) return candidate_slots.status();
  const std::vector<int> base_coefficients = reference_mode ? std::vector<int>{} : base_active.coefficients;
  std::optional<kinematics::SlotDesign> made;       // a linearisation made here
  const kinematics::SlotDesign* design = nullptr;   // the one in use (made, or the caller's nominal one)
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<kinematics::ErrorSlot> slots = DiagnosisSlotUnion(errors, base_coefficients, *candidate_slots);
    const kinematics::SlotDesign* given = options.nominal_slot_design.get();
    const bool use_given = pass == 0 && !reference_mode && given && given->dslot_um.rows() == n &&
                           std::all_of(slots.begin(), slots.end(), [&](const kinematics::ErrorSlot& sl) {
                             return std::find(given->slots.begin(), given->slots.end(), sl) != given->slots.end();
                           });
    if (use_given) {
      design = given;
    } else {
      auto lin = kinematics::LineariseSlots(machine, errors, slots, obs);
      if (!lin.ok()) return lin.status();
      made = std::move(*lin);
      design = &*made;
    }
    auto J_base = kinematics::CoefficientColumns(*design, errors, base_coefficients, obs);
    if (!J_base.ok()) return J_base.status();
    X0.resize(n, q_fit + 6);
    if (q_fit > 0) X0.leftCols(q_fit) = *J_base;
    X0.rightCols(6) = design->lin.J_dev_alignment;
    y = design->lin.measured_dev_um - design->lin.predicted_dev_um;
    if (point_reference) y -= *reference_dev_um;
    base = MakeBasis(X0, ColumnNorms(X0), kBaseRankTolerance, true);
    const Eigen::VectorXd r0 = y - base.U * (base.U.transpose() * y);
    const double s2 = r0.squaredNorm() / std::max<double>(1.0, static_cast<double>(n - base.rank));
    Solve(base, y, s2, &base_coef, &base_u, &base_ident);
    if (pass == 0 && !reference_mode)
      for (int k = 0; k < q_fit; ++k)
        if (base_ident[static_cast<std::size_t>(k)] && std::abs(base_coef(k)) > 1000.0) passes = 2;
    if (pass + 1 < passes) {  // move the linearisation point to the fitted base errors
      for (int k = 0; k < q_fit; ++k) {
        const int c = base_active.coefficients[static_cast<std::size_t>(k)];
        const double per = errors.coefficient_info(c).display_per_internal;
        if (base_ident[static_cast<std::size_t>(k)]) errors.set_coefficient(c, errors.coefficient(c) + base_coef(k) / per);
      }
    }
  }
  // After the second pass base_coef holds the correction at the fitted point: total = fitted + correction.
  DiagnosisResult out;
  out.n_points = static_cast<int>(n);
  out.base_columns = base.rank;
  out.base_model = point_reference
                       ? options.reference_name + " (reference point file: measured minus reference point by point, "
                                                  "re-alignment fitted)"
                   : reference_mode ? options.reference_name + " (fixed machine errors, re-alignment fitted)"
                                    : "location errors and squareness (" + std::to_string(q_fit) +
                                          " parameters) + re-alignment, fitted";
  for (int k = 0; k < q_fit; ++k) {
    const int c = base_active.coefficients[static_cast<std::size_t>(k)];
    const auto& info = errors.coefficient_info(c);
    EffectParameter p;
    p.name = info.name;
    p.unit = info.unit;
    p.value = errors.coefficient(c) * info.display_per_internal + base_coef(k);
    p.u = base_u(k);
    p.identifiable = base_ident[static_cast<std::size_t>(k)];
    out.base_parameters.push_back(p);
  }
  const Eigen::VectorXd r0 = y - base.U * (base.U.transpose() * y);
  const Eigen::VectorXd h0 = RowSquaredNorms(base.U);
  const double ssr0 = r0.squaredNorm();
  const double press_before = Rms(Press(r0, h0));
  // Leave-one-feature-out of the base fit (diagnosis_cv.h).
  const int n_features = static_cast<int>(mo.feature_names.size());
  std::vector<int> feature_of_point(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) feature_of_point[static_cast<std::size_t>(i)] = obs[static_cast<std::size_t>(i)].group;
  const GroupCrossValidation feature_cv(base.U, feature_of_point, n_features, options.holdout_tolerance);
  const GroupCvResult cv0 = feature_cv.Evaluate(r0);
  auto not_held_out = [&](const std::vector<bool>& holdable) {
    std::vector<std::string> names;
    for (int g = 0; g < n_features; ++g)
      if (!holdable[static_cast<std::size_t>(g)] && !feature_cv.rows(g).empty())
        names.push_back(mo.feature_names[static_cast<std::size_t>(g)]);
    return names;
  };
  auto count = [](const std::vector<bool>& v) { return static_cast<int>(std::count(v.begin(), v.end(), true)); };
  out.press_rms_um = press_before;
  out.cv_rms_um = cv0.Rms();
  out.n_features = 0;
  for (int g = 0; g < n_features; ++g) out.n_features += feature_cv.rows(g).empty() ? 0 : 1;
  out.cv_features = count(cv0.holdable);
  out.cv_not_held_out = not_held_out(cv0.holdable);
  out.rms_um = Rms(r0);
  out.max_abs_um = r0.size() ? r0.cwiseAbs().maxCoeff() : 0.0;
  out.gap_um.assign(r0.data(), r0.data() + r0.size());
  for (const auto& o : obs) out.point_feature.push_back(mo.feature_names[static_cast<std::size_t>(o.group)]);

  // ---- 2. Candidates.
  auto catalogue = BuildCandidates(piece, machine, errors, mo, base_names, reference_mode, design);
  if (!catalogue.ok()) return catalogue.status();
  const double ln_n = std::log(static_cast<double>(n));
  // Per candidate, for the pairwise ranking: feature-CV squared residual per feature and the
  // features held out (empty for the PRESS fallback), and the PRESS sum of squares.
  struct CvTrace {
    std::vector<double> ss_by_feature;
    std::vector<bool> held_out;
    double press_ss = 0.0;
  };
  const std::size_t n_candidates = catalogue->candidates.size();
  std::vector<Projected> bases(n_candidates);
  std::vector<CvTrace> traces(n_candidates);
  std::vector<CandidateResult> results(n_candidates);
  // Candidates are independent: evaluated on several threads for large point sets (each writes
  // its own slot, so the results do not depend on the schedule).
  ParallelForEach(n_candidates, n >= kParallelPoints, [&](std::size_t ci) {
    const CandidateColumns& cc = catalogue->candidates[ci];
    CandidateResult cr;
    cr.family = cc.family;
    cr.name = cc.name;
    cr.n_columns = static_cast<int>(cc.cols());
    const Columns C = ColumnsOf(cc);
    Projected b = ProjectCandidate(C, base.U, options.absorbed_tolerance);
    cr.rank = b.rank;
    cr.observable = b.rank > 0;
    cr.visible_share = b.max_sine;
    cr.typical_visible_share = b.rms_sine;
    cr.press_rms_before_um = press_before;
    const Eigen::VectorXd fitted = b.U * (b.U.transpose() * r0);
    const Eigen::VectorXd r1 = r0 - fitted;
    const double ssr1 = r1.squaredNorm();
    const double dof1 = static_cast<double>(n - base.rank - b.rank);
    cr.rms_after_um = Rms(r1);
    cr.max_abs_after_um = r1.size() ? r1.cwiseAbs().maxCoeff() : 0.0;
    cr.shrink_pct = out.rms_um > 0 ? 100.0 * (1.0 - cr.rms_after_um / out.rms_um) : 0.0;
    cr.press_rms_after_um = Rms(Press(r1, h0 + RowSquaredNorms(b.U)));
    {  // feature-CV before and after over the features the joint design can hold out
      const GroupCvResult cv1 = b.rank > 0 ? feature_cv.Evaluate(b.U, r1) : cv0;
      CvTrace trace;
      cr.cv_features = count(cv1.holdable);
      cr.cv_not_held_out = not_held_out(cv1.holdable);
      // Does any held-out feature carry the effect (a non-zero column entry)? If not, the
      // feature-CV cannot test the candidate (e.g. an effect acting on one feature only, which is
      // then not holdable): it is judged by its PRESS figure instead, and says so.
      bool reaches = false;
      double largest = 0.0;
      for (const auto& c : C) largest = std::max(largest, c.size() ? c.cwiseAbs().maxCoeff() : 0.0);
      const double row_tol = 1e-12 * std::max(1e-300, largest);
      for (int g = 0; g < n_features && !reaches && b.rank > 0 && !C.empty(); ++g) {
        if (!cv1.holdable[static_cast<std::size_t>(g)]) continue;
        for (auto i : feature_cv.rows(g)) {
          for (const auto& c : C)
            if (std::abs(c(i)) > row_tol) {
              reaches = true;
              break;
            }
          if (reaches) break;
        }
      }
      // Does the candidate make a feature unholdable that the base model holds out (its columns
      // there are fixed by that feature's points alone, e.g. a straightness polynomial by the
      // features at the ends of its axis range)? Its feature-CV would then be taken over a
      // different, smaller set than the base's, leaving out exactly the features where it
      // extrapolates worst, and would not be comparable with the other candidates': it is judged
      // by PRESS instead (as a candidate no held-out feature carries), and says so. Holdable sets
      // only shrink when columns are added (interlacing), so equal counts mean equal sets.
      const bool loses_features = count(cv1.holdable) < count(cv0.holdable);
      trace.press_ss = cr.press_rms_after_um * cr.press_rms_after_um * static_cast<double>(n);
      if (b.rank == 0 || (reaches && !loses_features)) {
        cr.cv_rms_before_um = cv0.RmsOver(cv1.holdable);
        cr.cv_rms_after_um = cv1.Rms();
        trace.ss_by_feature = cv1.ss_by_group;
        trace.held_out = cv1.holdable;
      } else {
        cr.cv_method = "leave-one-point-out";
        cr.cv_method_reason = reaches ? "the effect's columns are fixed by features the base model holds out, which it "
                                        "makes unholdable: leave-one-feature-out would compare it on fewer features"
                                      : "no held-out feature carries the effect";
        cr.cv_rms_before_um = cr.press_rms_before_um;
        cr.cv_rms_after_um = cr.press_rms_after_um;
      }
      traces[ci] = std::move(trace);
    }
    cr.cv_shrink_pct = cr.cv_rms_before_um > 0 ? 100.0 * (1.0 - cr.cv_rms_after_um / cr.cv_rms_before_um) : 0.0;
    if (b.rank > 0 && dof1 > 0 && ssr1 > 0) {
      cr.f_stat = ((ssr0 - ssr1) / b.rank) / (ssr1 / dof1);
      cr.p_value = FUpperTail(cr.f_stat, b.rank, dof1);
      cr.delta_bic = static_cast<double>(n) * std::log(ssr1 / ssr0) + b.rank * ln_n;
    }
    // Parameters of the effect (joint fit = fit of the residual on the projected columns).
    const double s2 = dof1 > 0 ? ssr1 / dof1 : 0.0;
    const Eigen::VectorXd coef = b.rank > 0 ? Eigen::VectorXd(b.B * (b.U.transpose() * r0))
                                            : Eigen::VectorXd(Eigen::VectorXd::Zero(cc.cols()));
    for (Eigen::Index j = 0; j < coef.size(); ++j) {
      const double u = b.rank > 0 ? std::sqrt(s2 * b.B.row(j).squaredNorm()) : 0.0;
      cr.parameters.push_back({cc.parameter_names[static_cast<std::size_t>(j)], cc.units[static_cast<std::size_t>(j)],
                               coef(j), u, b.identifiable[static_cast<std::size_t>(j)]});
    }
    // Bias the effect was putting into the base coefficients: the base absorbs X0+ (C coef).
    if (q_fit > 0 && b.rank > 0) {
      Eigen::VectorXd effect = Eigen::VectorXd::Zero(n);
      for (std::size_t j = 0; j < C.size(); ++j) effect += coef(static_cast<Eigen::Index>(j)) * C[j];
      Eigen::VectorXd dcoef, du;
      std::vector<bool> dident;
      Solve(base, effect, 0.0, &dcoef, &du, &dident);
      for (int k = 0; k < q_fit; ++k) {
        const auto& bp = out.base_parameters[static_cast<std::size_t>(k)];
        if (!bp.identifiable || std::abs(dcoef(k)) < 1e-9) continue;  // no number for what the data cannot separate
        cr.base_shift.push_back({bp.name, bp.unit, bp.value, bp.value - dcoef(k)});
      }
    }
    bases[ci] = std::move(b);
    results[ci] = std::move(cr);
  });
  const double alpha_each = options.alpha / std::max<std::size_t>(1, results.size());
  for (auto& cr : results)
    cr.significant = cr.observable && cr.p_value < alpha_each && cr.cv_rms_after_um < cr.cv_rms_before_um;

  // ---- 3. Verdict and aliasing.
  std::vector<std::size_t> order(results.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  // Ranking of the significant candidates, pairwise (candidates hold out different features, so
  // their cv figures are not comparable as they stand). A beats B when A's held-out squared
  // residuals are smaller than B's on the features both hold out, by more than twice the standard
  // error of the sum of the per-feature differences d_g = ss_A,g - ss_B,g (paired over the m common
  // features: |sum d| > 2 sqrt(m) sd(d)); by PRESS over every point (the smaller wins) when either
  // is judged by PRESS (cv_method) or they share fewer than 3 held-out features: two candidates are
  // always compared on the same kind of figure. Both feature-tested means both hold out exactly
  // the base's features, so the common set is the base's. When that does not decide (the data
  // cannot tell them apart by prediction), the smaller delta BIC wins. Order: most pairwise wins
  // first, then the cv ratio after / before, then catalogue order.
  auto beats = [&](std::size_t a, std::size_t b) {
    const CvTrace &ta = traces[a], &tb = traces[b];
    double sum = 0.0, sum2 = 0.0;
    int m = 0;
    if (!ta.held_out.empty() && !tb.held_out.empty()) {
      for (std::size_t g = 0; g < ta.held_out.size(); ++g) {
        if (!ta.held_out[g] || !tb.held_out[g]) continue;
        const double d = ta.ss_by_feature[g] - tb.ss_by_feature[g];
        sum += d;
        sum2 += d * d;
        ++m;
      }
    }
    if (m >= 3) {
      const double mean = sum / m;
      const double var = std::max(0.0, (sum2 - m * mean * mean) / (m - 1));
      const double se_sum = std::sqrt(var * m);
      if (sum < -2.0 * se_sum) return true;
      if (sum > 2.0 * se_sum) return false;
    } else if (ta.press_ss < tb.press_ss) {
      return true;
    } else if (ta.press_ss > tb.press_ss) {
      return false;
    }
    return results[a].delta_bic < results[b].delta_bic;
  };
  std::vector<int> wins(results.size(), 0);
  for (std::size_t a = 0; a < results.size(); ++a)
    for (std::size_t b = 0; b < results.size(); ++b)
      if (a != b && results[a].significant && results[b].significant && beats(a, b)) ++wins[a];
  auto rank_key = [&](std::size_t k) {
    const auto& c = results[k];
    const double ratio = c.cv_rms_before_um > 0 ? c.cv_rms_after_um / c.cv_rms_before_um : 1.0;
    return std::make_tuple(c.significant ? 0 : (c.observable ? 1 : 2), -wins[k], ratio);
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rank_key(a) < rank_key(b); });
  // Best candidate of each family (first in the ranking).
  std::map<std::string, std::size_t> best_of_family;
  for (auto k : order) best_of_family.try_emplace(results[k].family, k);

  // Residual after the base and candidate k, and the test of adding candidate j to it.
  // F statistic and p-value of candidate j added to base + candidate k ({0, 1} when j adds nothing).
  auto f_beyond = [&](std::size_t j, std::size_t k) -> std::pair<double, double> {
    Eigen::MatrixXd Q(n, base.U.cols() + bases[k].U.cols());
    Q << base.U, bases[k].U;
    const Eigen::VectorXd rk = r0 - bases[k].U * (bases[k].U.transpose() * r0);
    Projected bj = ProjectCandidate(ColumnsOf(catalogue->candidates[j]), Q, options.absorbed_tolerance);
    if (bj.rank == 0) return {0.0, 1.0};
    const Eigen::VectorXd rjk = rk - bj.U * (bj.U.transpose() * rk);
    const double dof = static_cast<double>(n - Q.cols() - bj.rank);
    if (dof <= 0 || rjk.squaredNorm() <= 0) return {0.0, 1.0};
    const double f = ((rk.squaredNorm() - rjk.squaredNorm()) / bj.rank) / (rjk.squaredNorm() / dof);
    return {f, FUpperTail(f, bj.rank, dof)};
  };
  auto adds_beyond = [&](std::size_t j, std::size_t k) { return f_beyond(j, k).second; };  // p-value
  double ssr_final = ssr0;
  int dof_final = base.rank;
  if (!order.empty() && results[order.front()].significant) {
    const std::size_t v = order.front();
    const auto& best = results[v];
    out.verdict.family = best.family;
    out.verdict.name = best.name;
    out.verdict.shrink_pct = best.shrink_pct;
    out.verdict.cv_shrink_pct = best.cv_shrink_pct;
    ssr_final = best.rms_after_um * best.rms_after_um * static_cast<double>(n);
    dof_final = base.rank + best.rank;
    for (const auto& [family, k] : best_of_family) {
      if (family == best.family || !results[k].significant) continue;
      if (adds_beyond(v, k) > options.alpha) out.verdict.indistinguishable_from.push_back(family);
    }
  }
  // On this piece and plan: a family one of whose candidates reproduces most of the verdict's
  // fitted signature s_v (its projected columns capture >= options.alias_capture of |s_v|^2)
  // explains the gap about as well, whatever the F-test says at high signal: what still tells
  // them apart is only the shape each candidate assumes (e.g. a quartic straightness against a
  // 2-to-5-lobe radial motion along a cone section, where X is a function of C). Such a family
  // is not offered as the runner-up either.
  if (!order.empty() && results[order.front()].significant) {
    const std::size_t v = order.front();
    const Eigen::VectorXd s_v = bases[v].U * (bases[v].U.transpose() * r0);
    const double e_v = s_v.squaredNorm();
    auto& ind = out.verdict.indistinguishable_from;
    for (std::size_t k = 0; k < results.size() && e_v > 0; ++k) {
      const std::string& family = results[k].family;
      if (family == results[v].family || !results[k].observable || std::find(ind.begin(), ind.end(), family) != ind.end())
        continue;
      const double captured = (bases[k].U.transpose() * s_v).squaredNorm() / e_v;
      if (captured >= options.alias_capture) ind.push_back(family);
    }
    std::sort(ind.begin(), ind.end());
  }
  // The runner-up: of the best significant candidates of the other families (not
  // indistinguishable from the verdict), the one that adds most beyond base + verdict (smallest
  // p, largest F: a forward-selection step); `also` when that is significant.
  std::optional<std::size_t> runner;
  double p_runner = 1.0, f_runner = 0.0;
  if (!order.empty() && results[order.front()].significant) {
    const std::size_t v = order.front();
    const auto& ind = out.verdict.indistinguishable_from;
    for (const auto& [family, k] : best_of_family) {
      if (!results[k].significant || family == results[v].family ||
          std::find(ind.begin(), ind.end(), family) != ind.end())
        continue;
      // The largest F (p underflows to 0 for several strong effects; F still orders them).
      const auto [f, p] = f_beyond(k, v);
      if (!runner || f > f_runner) runner = k, p_runner = p, f_runner = f;
    }
    if (runner && p_runner < alpha_each) out.verdict.also = results[*runner].family;
  }
  // The verdict and the runner-up of another family, fitted jointly when the two are close.
  // Close: the runner-up adds significantly beyond the verdict, or else the next candidate of
  // another family in the ranking is not separated from the verdict by prediction.
  if (!order.empty() && results[order.front()].significant) {
    const std::size_t v = order.front();
    std::string why;
    if (runner && p_runner < alpha_each) {
      why = "it adds significantly beyond the verdict";
    } else {
      runner.reset();
      for (auto k : order)
        if (results[k].significant && results[k].family != results[v].family) {
          if (!beats(v, k)) {
            runner = k;
            why = "the ranking does not separate it from the verdict by prediction";
          }
          break;
        }
    }
    if (runner) {
      const std::size_t k = *runner;
      const double p_beyond = adds_beyond(k, v);
      {
        const auto& cv = catalogue->candidates[v];
        const auto& ck = catalogue->candidates[k];
        Columns C = ColumnsOf(cv);
        for (const auto& c : ColumnsOf(ck)) C.push_back(c);
        const Projected b = ProjectCandidate(C, base.U, options.absorbed_tolerance);
        PairFit pf;
        pf.families = {results[v].family, results[k].family};
        pf.names = {results[v].name, results[k].name};
        pf.why = why;
        pf.rank = b.rank;
        pf.p_value_beyond_verdict = p_beyond;
        const Eigen::VectorXd r2 = r0 - b.U * (b.U.transpose() * r0);
        pf.rms_after_um = Rms(r2);
        pf.shrink_pct = out.rms_um > 0 ? 100.0 * (1.0 - pf.rms_after_um / out.rms_um) : 0.0;
        const bool by_features = !traces[v].held_out.empty() && !traces[k].held_out.empty();
        const GroupCvResult cv2 = by_features ? feature_cv.Evaluate(b.U, r2) : cv0;
        if (by_features && count(cv2.holdable) == count(cv0.holdable)) {
          pf.cv_rms_before_um = cv0.RmsOver(cv2.holdable);
          pf.cv_rms_after_um = cv2.Rms();
        } else {
          pf.cv_method = "leave-one-point-out";
          pf.cv_rms_before_um = press_before;
          pf.cv_rms_after_um = Rms(Press(r2, h0 + RowSquaredNorms(b.U)));
        }
        pf.cv_shrink_pct = pf.cv_rms_before_um > 0 ? 100.0 * (1.0 - pf.cv_rms_after_um / pf.cv_rms_before_um) : 0.0;
        const double dof2 = static_cast<double>(n - base.rank - b.rank);
        const double s2 = dof2 > 0 ? r2.squaredNorm() / dof2 : 0.0;
        const Eigen::VectorXd coef = b.B * (b.U.transpose() * r0);
        std::vector<std::pair<std::string, std::string>> names_units;
        for (const auto* c : {&cv, &ck})
          for (std::size_t j = 0; j < c->parameter_names.size(); ++j) names_units.emplace_back(c->parameter_names[j], c->units[j]);
        for (Eigen::Index j = 0; j < coef.size(); ++j) {
          const auto& [name, unit] = names_units[static_cast<std::size_t>(j)];
          pf.parameters.push_back({name, unit, coef(j), std::sqrt(s2 * b.B.row(j).squaredNorm()),
                                   b.identifiable[static_cast<std::size_t>(j)]});
        }
        out.pair = std::move(pf);
      }
    }
  }
  for (auto k : order) out.candidates.push_back(results[k]);
  // Families without any observable candidate.
  for (const auto& [family, reason] : catalogue->not_applicable) out.unobservable.push_back({family, reason});
  std::map<std::string, bool> family_observable;
  for (const auto& c : out.candidates) family_observable[c.family] = family_observable[c.family] || c.observable;
  for (const auto& [family, obsv] : family_observable)
    if (!obsv)
      out.unobservable.push_back({family, "every candidate of this family is absorbed by the base model and the "
                                          "re-alignment on this piece and plan (or never acts on the measured points)"});
  // Families whose every candidate keeps only a small share of a typical signature outside the
  // base model (RMS sine of the principal angles below weak_visibility): observable in principle,
  // but an effect must be about 1 / share times the noise before it shows. Single cone: drift
  // (8 %) and linear positioning (4 %), which the validation finds unobservable in 59 and 60 of 60
  // trials; the turning piece's least visible family, drift, keeps 26 %.
  std::map<std::string, double> family_share;
  for (const auto& c : out.candidates)
    if (c.observable) family_share[c.family] = std::max(family_share[c.family], c.typical_visible_share);
  for (const auto& [family, share] : family_share)
    if (share < options.weak_visibility) out.weakly_observable.push_back({family, share});

  // ---- 4. Where the gap lies.
  out.noise_sigma_um = options.noise_um > 0
                           ? options.noise_um
                           : std::sqrt(ssr_final / std::max<double>(1.0, static_cast<double>(n - dof_final)));
  std::vector<double> t_s(static_cast<std::size_t>(n));
  std::map<std::string, std::vector<Eigen::Index>> by_feature, by_op, by_a;
  {  // Group keys are formatted once per distinct value (not once per point).
    std::vector<std::vector<Eigen::Index>> of_group(mo.feature_names.size());
    std::map<int, std::vector<Eigen::Index>> of_op;
    std::map<double, std::vector<Eigen::Index>> of_a;  // rounded to 0.001 deg
    const bool has_a = machine.HasAxis(kinematics::Axis::kA);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& o = obs[static_cast<std::size_t>(i)];
      t_s[static_cast<std::size_t>(i)] = o.cut.axes.t_s;
      of_group[static_cast<std::size_t>(o.group)].push_back(i);
      of_op[o.cut.axes.op].push_back(i);
      const double a_deg = RadToDeg(has_a ? o.cut.axes.a_rad : o.cut.axes.b_rad);
      of_a[std::round(a_deg * 1000.0) / 1000.0 + 0.0].push_back(i);
    }
    for (std::size_t g = 0; g < of_group.size(); ++g)
      if (!of_group[g].empty()) by_feature[mo.feature_names[g]] = std::move(of_group[g]);
    char buf[32];
    for (auto& [op, idx] : of_op) {
      std::snprintf(buf, sizeof(buf), "op %d", op);
      by_op[buf] = std::move(idx);
    }
    for (auto& [a, idx] : of_a) {
      std::snprintf(buf, sizeof(buf), "%s=%g deg", has_a ? "A" : "B", a);
      auto& v = by_a[buf];  // distinct values print distinctly at 0.001 deg; merge if not
      v.insert(v.end(), idx.begin(), idx.end());
    }
  }
  const double s = out.noise_sigma_um;
  GroupStats(by_feature, r0, t_s, s, options.stand_out_z, &out.by_feature, &out.standing_out, "feature ");
  GroupStats(by_op, r0, t_s, s, options.stand_out_z, &out.by_operation, &out.standing_out, "");
  GroupStats(by_a, r0, t_s, s, options.stand_out_z, &out.by_a_index, &out.standing_out, "");
  {  // linear trend with machining time
    Eigen::MatrixXd T(n, 2);
    for (Eigen::Index i = 0; i < n; ++i) T(i, 0) = 1.0, T(i, 1) = t_s[static_cast<std::size_t>(i)] / 3600.0;
    const Eigen::MatrixXd TtT = T.transpose() * T;
    if (std::abs(TtT.determinant()) > 1e-12) {
      const Eigen::Vector2d beta = TtT.ldlt().solve(T.transpose() * r0);
      out.drift_um_per_h = beta(1);
      out.drift_u_um_per_h = s * std::sqrt(TtT.inverse()(1, 1));
    }
  }
  {  // C harmonics of circular profiles
    std::vector<HarmonicGap> all;
    for (const auto& [name, idx] : by_feature) {
      if (idx.size() < 8) continue;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (auto i : idx) c += obs[static_cast<std::size_t>(i)].cut.nominal_point_mm;
      c /= static_cast<double>(idx.size());
      const int kmax = std::min<int>(options.max_harmonic, static_cast<int>(idx.size()) / 2 - 1);
      // One pass: cos(k phi) + i sin(k phi) = w^k with w = e^{i phi} (azimuth phi of the point).
      std::vector<std::complex<double>> sum(static_cast<std::size_t>(std::max(kmax, 0)) + 1, 0.0);
      for (auto i : idx) {
        const Eigen::Vector3d d = obs[static_cast<std::size_t>(i)].cut.nominal_point_mm - c;
        const double rho = std::hypot(d.x(), d.y());
        const std::complex<double> w = rho > 0 ? std::complex<double>(d.x() / rho, d.y() / rho) : 1.0;
        std::complex<double> wk = 1.0;
        for (int k = 1; k <= kmax; ++k) {
          wk *= w;
          sum[static_cast<std::size_t>(k)] += r0(i) * wk;
        }
      }
      for (int k = 1; k <= kmax; ++k) {
        const double m = static_cast<double>(idx.size());
        const double a = sum[static_cast<std::size_t>(k)].real() * 2.0 / m;
        const double b = sum[static_cast<std::size_t>(k)].imag() * 2.0 / m;
        HarmonicGap h{name, k, std::hypot(a, b), RadToDeg(std::atan2(b, a)), 0.0, false};
        h.z = s > 0 ? h.amplitude_um / (s * std::sqrt(2.0 / m)) : 0.0;
        all.push_back(h);
      }
    }
    // Rayleigh tail with a Bonferroni bound at 1 %: P(z > t) = exp(-t^2 / 2) per test.
    const double t = all.empty() ? 0.0 : std::sqrt(2.0 * std::log(static_cast<double>(all.size()) / 0.01));
    for (auto& h : all) {
      h.stands_out = h.z > t;
      if (h.stands_out) out.standing_out.push_back("feature " + h.feature + " harmonic " + std::to_string(h.order));
    }
    out.harmonics = std::move(all);
  }
  return out;
}

// Labelled points of `points` (any placement) as observations in the nominal part frame (datum
// frame from the piece's inspection plan). Points no cut of their feature reaches are skipped
// ("file:line: why" in *skipped); unlabelled points and unknown features stay errors.
Result<testpieces::MeasuredObservations> ObservationsForDiagnosis(const testpieces::TestPiece& piece, const PointSet& points,
                                                      std::vector<std::string>* skipped) {
  auto inspection = gdt::EvaluatePlan(piece.inspection, points);
  if (!inspection.ok()) return inspection.status();
  // A point whose cut cannot be found (typically at a face edge, pushed out of the machined band
  // by errors and noise) is left out and reported; unknown features and unlabelled points stay errors.
  return testpieces::AssociatePoints(piece, points, inspection->datum_from_cmm, testpieces::UnreachedPoint::kSkip,
                                     skipped);
}

}  // namespace

Result<std::vector<kinematics::ErrorSlot>> NominalDiagnosisSlots(const testpieces::TestPiece& piece,
                                                                 const kinematics::MachineModel& machine,
                                                                 const DiagnosisOptions& options) {
  // As DiagnoseImpl's first linearisation (not in reference mode).
  const std::vector<std::string> base_names =
      options.base_parameters.empty() ? testpieces::DefaultParameterSet(piece, machine) : options.base_parameters;
  kinematics::ErrorState errors(machine);
  kinematics::ActiveSet active;
  if (!base_names.empty()) {
    auto act = kinematics::ActivateParameters(machine, &errors, base_names);
    if (!act.ok()) return act.status();
    active = *act;
  }
  auto candidate_slots = CandidateSlots(piece, machine, errors, base_names, /*reference_mode=*/false);
  if (!candidate_slots.ok()) return candidate_slots.status();
  return DiagnosisSlotUnion(errors, active.coefficients, *candidate_slots);
}

Result<DiagnosisResult> DiagnoseObservations(const testpieces::TestPiece& piece,
                                             const kinematics::MachineModel& machine,
                                             const testpieces::MeasuredObservations& observations, const DiagnosisOptions& options) {
  return DiagnoseImpl(piece, machine, observations, options, nullptr);
}

Result<DiagnosisResult> Diagnose(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                 const PointSet& measured, const DiagnosisOptions& options) {
  std::vector<std::string> skipped;
  auto obs = ObservationsForDiagnosis(piece, measured, &skipped);
  if (!obs.ok()) return obs.status();
  auto result = DiagnoseImpl(piece, machine, *obs, options, nullptr);
  if (result.ok()) result->skipped_points = std::move(skipped);
  return result;
}

Result<DiagnosisResult> DiagnoseAgainstPoints(const testpieces::TestPiece& piece, const kinematics::MachineModel& machine,
                                              const PointSet& measured, const PointSet& reference,
                                              const DiagnosisOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  if (options.reference)
    return Status(StatusCode::kInvalidArgument, "diagnosis: a reference point file and reference machine errors together");
  std::vector<std::string> skipped, skipped_ref;
  auto mo = ObservationsForDiagnosis(piece, measured, &skipped);
  if (!mo.ok()) return mo.status();
  auto ro = ObservationsForDiagnosis(piece, reference, &skipped_ref);
  if (!ro.ok()) return ro.status();
  // The reference's normal deviations at nominal errors, as DiagnoseImpl computes the measured ones.
  auto lin = kinematics::LineariseBySlots(machine, kinematics::ErrorState(machine), {}, ro->observations);
  if (!lin.ok()) return lin.status();
  const Eigen::VectorXd ref_dev_um = lin->measured_dev_um - lin->predicted_dev_um;
  // Reference observations per feature name, in file order.
  std::map<std::string, std::vector<std::size_t>> ref_of_feature;
  for (std::size_t j = 0; j < ro->observations.size(); ++j)
    ref_of_feature[ro->feature_names[static_cast<std::size_t>(ro->observations[j].group)]].push_back(j);
  std::map<std::string, std::vector<std::size_t>> meas_of_feature;
  for (std::size_t i = 0; i < mo->observations.size(); ++i)
    meas_of_feature[mo->feature_names[static_cast<std::size_t>(mo->observations[i].group)]].push_back(i);
  const double tol_mm = options.reference_match_mm;
  auto nominal = [](const testpieces::MeasuredObservations& m, std::size_t k) -> const Eigen::Vector3d& {
    return m.observations[k].cut.nominal_point_mm;
  };
  std::vector<long> match(mo->observations.size(), -1);  // reference observation of each measured one
  DiagnosisResult::ReferenceMatch rm;
  for (const auto& [name, mi] : meas_of_feature) {
    const auto it = ref_of_feature.find(name);
    if (it == ref_of_feature.end()) continue;
    const auto& rj = it->second;
    bool by_order = mi.size() == rj.size();
    for (std::size_t k = 0; by_order && k < mi.size(); ++k)
      by_order = (nominal(*mo, mi[k]) - nominal(*ro, rj[k])).norm() <= tol_mm;
    for (std::size_t k = 0; k < mi.size(); ++k) {
      std::size_t best = rj.front();
      double best_d = (nominal(*mo, mi[k]) - nominal(*ro, best)).norm();
      if (by_order) {
        best = rj[k];
        best_d = (nominal(*mo, mi[k]) - nominal(*ro, best)).norm();
      } else {
        for (std::size_t j : rj) {  // first nearest in file order
          const double d = (nominal(*mo, mi[k]) - nominal(*ro, j)).norm();
          if (d < best_d) best = j, best_d = d;
        }
        if (best_d > tol_mm) continue;
      }
      match[mi[k]] = static_cast<long>(best);
      rm.max_offset_mm = std::max(rm.max_offset_mm, best_d);
      (by_order ? rm.matched_by_order : rm.matched_by_nearest) += 1;
    }
  }
  testpieces::MeasuredObservations kept;
  std::vector<double> dev;
  std::map<int, int> group_map;
  for (std::size_t i = 0; i < mo->observations.size(); ++i) {
    const auto& o = mo->observations[i];
    const std::size_t pi = mo->point_index[i];
    if (match[i] < 0) {
      ++rm.unmatched;
      skipped.push_back(Status(StatusCode::kInvalidArgument, "no reference point of feature " +
                                                          mo->feature_names[static_cast<std::size_t>(o.group)] +
                                                          fmt::format(" within {} mm of its nominal position", tol_mm))
                            .WithLocation(measured.source, measured.LineOf(pi))
                            .ToString());
      continue;
    }
    auto [g, inserted] = group_map.try_emplace(o.group, static_cast<int>(kept.feature_names.size()));
    if (inserted) kept.feature_names.push_back(mo->feature_names[static_cast<std::size_t>(o.group)]);
    kinematics::Observation ok = o;
    ok.group = g->second;
    kept.observations.push_back(ok);
    kept.point_index.push_back(pi);
    dev.push_back(ref_dev_um(static_cast<Eigen::Index>(match[i])));
  }
  const Eigen::VectorXd dev_um = Eigen::Map<const Eigen::VectorXd>(dev.data(), static_cast<Eigen::Index>(dev.size()));
  auto result = DiagnoseImpl(piece, machine, kept, options, &dev_um);
  if (!result.ok()) return result.status();
  for (auto& s : skipped_ref) skipped.push_back("reference: " + s);
  result->skipped_points = std::move(skipped);
  result->reference_match = rm;
  return result;
}

}  // namespace tpcal::pipeline
