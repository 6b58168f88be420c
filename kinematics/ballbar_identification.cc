#include "kinematics/ballbar_identification.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/units.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/internal/student_t.h"

namespace tpcal::kinematics {
namespace {

// File-local names carry a Bbi prefix (unity build: one translation unit per target).

constexpr char kBbiDirections[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
constexpr double kBbiNodeTol_deg = 1e-9;   // angles closer than this are one node
constexpr double kBbiStep = 1e-6;          // central-difference step, internal units (mm, rad)
constexpr double kBbiSpanTol = 1e-6;       // a family lies in the null span (relative residual)
constexpr double kBbiRowTol = 1e-6;        // |row of an orthonormal basis|^2 taken as 0 or 1

std::string BbiDeg(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The linear system of step 2: rows = readings, columns = 6 * nodes error entries (display
// units, term d node i at column d * nodes + i), then the set-up terms.
struct BbiSystem {
  std::vector<double> nodes_deg;
  std::vector<int> node_of_reading;
  bool periodic = false;
  Eigen::MatrixXd a;  // [G S]
  Eigen::VectorXd y;  // dl - dl0, um
  std::vector<BallbarSetupTerm> setup;
  std::vector<int> setup_kind;  // 0 offset, 1 centring cos, 2 centring sin
};

Status BbiCheck(const MachineModel& model, const std::vector<BallbarGeometry>& installations,
                const std::vector<BallbarReading>& readings, const BallbarIdentificationOptions& options) {
  TPCAL_RETURN_IF_ERROR(options.Validate());
  const std::string k(1, AxisLetter(options.axis));
  if (!model.HasAxis(options.axis)) return Status(StatusCode::kInvalidArgument, "the machine has no axis " + k);
  for (const BallbarGeometry& g : installations) {
    if (g.installation.kind == BallbarKind::kCircle || g.installation.axis != options.axis)
      return Status(StatusCode::kInvalidArgument, "ball bar '" + g.installation.name + "' does not turn the " + k +
                                                      " axis identified (every installation must)");
  }
  for (const BallbarReading& r : readings) {
    const std::string where = r.line > 0 ? "line " + std::to_string(r.line) + ": " : std::string();
    if (r.installation < 0 || r.installation >= static_cast<int>(installations.size()))
      return Status(StatusCode::kInvalidArgument, where + "reading names installation " +
                                                      std::to_string(r.installation) + ", which is not given");
    if (!std::isfinite(r.angle_deg) || !std::isfinite(r.dl_um) || !std::isfinite(r.t_s))
      return Status(StatusCode::kInvalidArgument, where + "a reading value is not finite");
  }
  return Status();
}

// Distinct angles (continuous axis: reduced into [0, 360)), ascending, and each reading's node.
void BbiNodes(const MachineModel& model, const std::vector<BallbarReading>& readings, Axis axis, BbiSystem* sys) {
  sys->periodic = model.links[static_cast<std::size_t>(model.LinkIndex(axis))].continuous;
  auto reduce = [&](double a) {
    if (!sys->periodic) return a;
    double r = std::fmod(a, 360.0);
    if (r < 0.0) r += 360.0;
    return r > 360.0 - kBbiNodeTol_deg ? 0.0 : r;
  };
  for (const BallbarReading& r : readings) sys->nodes_deg.push_back(reduce(r.angle_deg));
  std::sort(sys->nodes_deg.begin(), sys->nodes_deg.end());
  sys->nodes_deg.erase(std::unique(sys->nodes_deg.begin(), sys->nodes_deg.end(),
                                   [](double x, double y) { return std::abs(x - y) < kBbiNodeTol_deg; }),
                       sys->nodes_deg.end());
  for (const BallbarReading& r : readings) {
    const double a = reduce(r.angle_deg);
    int best = 0;
    for (int i = 1; i < static_cast<int>(sys->nodes_deg.size()); ++i)
      if (std::abs(sys->nodes_deg[i] - a) < std::abs(sys->nodes_deg[best] - a)) best = i;
    sys->node_of_reading.push_back(best);
  }
}

Result<ErrorState> BbiZeroTables(const MachineModel& model, Axis axis, const BbiSystem& sys) {
  ErrorState tables(model);
  for (int d = 0; d < 6; ++d) {
    ErrorTerm t;
    t.kind = TermKind::kTable;
    t.label = std::string("E_") + kBbiDirections[d] + AxisLetter(axis);
    t.quantity = d < 3 ? Quantity::kLength : Quantity::kAngle;
    t.effects = {SlotEffect{axis, static_cast<Component>(d), 1.0}};
    t.argument = axis;
    for (double n : sys.nodes_deg) t.nodes.push_back(DegToRad(n));
    t.periodic = sys.periodic;
    t.coefficients.assign(t.ExpectedCoefficients(), 0.0);
    TPCAL_RETURN_IF_ERROR(tables.AddTerm(model, std::move(t)));
  }
  return tables;
}

// The set-up columns (kinds 0 offset, 1 cos, 2 sin) of the installations that have readings.
void BbiSetupColumns(const std::vector<BallbarGeometry>& installations, const std::vector<BallbarReading>& readings,
                     const BallbarIdentificationOptions& options, BbiSystem* sys) {
  for (int j = 0; j < static_cast<int>(installations.size()); ++j) {
    if (std::none_of(readings.begin(), readings.end(), [j](const BallbarReading& r) { return r.installation == j; }))
      continue;
    const std::string& name = installations[j].installation.name;
    for (int kind = 0; kind < 3; ++kind) {
      if (kind == 0 && !options.fit_length_offsets) continue;
      if (kind > 0 && !options.fit_centring) continue;
      BallbarSetupTerm t;
      t.installation = j;
      t.name = name + (kind == 0 ? " offset" : kind == 1 ? " centring cos" : " centring sin");
      sys->setup.push_back(t);
      sys->setup_kind.push_back(kind);
    }
  }
}

// Step 2: G by central differences of the bar length at the reading's commands, S, y.
Status BbiDesign(const MachineModel& model, const std::vector<BallbarGeometry>& installations,
                 const std::vector<BallbarReading>& readings, ErrorState* tables, BbiSystem* sys) {
  const int nn = static_cast<int>(sys->nodes_deg.size());
  const int ne = 6 * nn, nr = static_cast<int>(readings.size());
  sys->a = Eigen::MatrixXd::Zero(nr, ne + static_cast<int>(sys->setup.size()));
  sys->y.resize(nr);
  Workspace ws;
  for (int r = 0; r < nr; ++r) {
    const BallbarReading& rd = readings[r];
    const BallbarGeometry& g = installations[rd.installation];
    Result<AxisState> axes = BallbarCommand(model, g, rd.angle_deg, rd.t_s);
    TPCAL_RETURN_IF_ERROR(axes);
    const double l0_mm = g.installation.nominal_length_mm;
    sys->y(r) = rd.dl_um - MmToUm(BallbarLengthMm(model, *tables, g, *axes, &ws) - l0_mm);
    for (int d = 0; d < 6; ++d) {  // a reading on node i sees only node i (linear interpolation)
      const int e = d * nn + sys->node_of_reading[r];
      const double per = tables->coefficient_info(e).display_per_internal;
      tables->set_coefficient(e, kBbiStep);
      const double plus = BallbarLengthMm(model, *tables, g, *axes, &ws);
      tables->set_coefficient(e, -kBbiStep);
      const double minus = BallbarLengthMm(model, *tables, g, *axes, &ws);
      tables->set_coefficient(e, 0.0);
      sys->a(r, e) = MmToUm(plus - minus) / (2.0 * kBbiStep * per);
    }
    const double angle = DegToRad(rd.angle_deg);
    for (std::size_t s = 0; s < sys->setup.size(); ++s) {
      if (sys->setup[s].installation != rd.installation) continue;
      const int kind = sys->setup_kind[s];
      sys->a(r, ne + static_cast<int>(s)) = kind == 0 ? 1.0 : kind == 1 ? std::cos(angle) : std::sin(angle);
    }
  }
  return Status();
}

// Candidate families (display units) for naming the null span: translation or tilt, radial /
// tangential / axial part relative to the axis, times 1, cos or sin of the angle. The axis turns
// about the third of (p, q, axis); the radial direction is cos p + sign sin q, the sign of the
// turn tried both ways (only the machine's own matches).
struct BbiFamily {
  std::string name;
  Eigen::VectorXd v;
};

std::vector<BbiFamily> BbiCandidates(Axis axis, const std::vector<double>& nodes_deg, int sign) {
  const int ia = static_cast<int>(axis) - 3, ip = (ia + 1) % 3, iq = (ia + 2) % 3;
  const int nn = static_cast<int>(nodes_deg.size());
  const std::string k(1, AxisLetter(axis));
  const char* harmonic[3] = {"mean", "cos " , "sin "};
  std::vector<BbiFamily> out;
  for (int tilt = 0; tilt < 2; ++tilt) {
    const int off = 3 * tilt;
    const std::string p = std::string("E_") + kBbiDirections[off + ip] + k;
    const std::string q = std::string("E_") + kBbiDirections[off + iq] + k;
    const std::string a = std::string("E_") + kBbiDirections[off + ia] + k;
    const std::string what = tilt ? "tilt" : "translation";
    for (int part = 0; part < 3; ++part) {
      for (int h = 0; h < 3; ++h) {
        BbiFamily f;
        f.v = Eigen::VectorXd::Zero(6 * nn);
        for (int i = 0; i < nn; ++i) {
          const double th = DegToRad(nodes_deg[i]);
          const double fh = h == 0 ? 1.0 : h == 1 ? std::cos(th) : std::sin(th);
          const double c = std::cos(th), s = sign * std::sin(th);
          if (part == 0) f.v((off + ip) * nn + i) = fh * c, f.v((off + iq) * nn + i) = fh * s;
          if (part == 1) f.v((off + ip) * nn + i) = -fh * s, f.v((off + iq) * nn + i) = fh * c;
          if (part == 2) f.v((off + ia) * nn + i) = fh;
        }
        const std::string pm = sign > 0 ? " + " : " - ";
        const std::string form = part == 0   ? p + " cos " + k + pm + q + " sin " + k
                                 : part == 1 ? (sign > 0 ? "-" : "") + p + " sin " + k + " + " + q + " cos " + k
                                             : a;
        const char* part_name[3] = {"radial", "tangential", "axial"};
        f.name = std::string(part_name[part]) + " " + what + " (" + form + "): " +
                 (h == 0 ? std::string("mean over ") + k : std::string(harmonic[h]) + k + " component");
        out.push_back(std::move(f));
      }
    }
  }
  return out;
}

// The set-up kinds (numerically) that absorb family v: S s = -G v solved, kinds with |s| > 0.
std::string BbiAbsorbedBy(const BbiSystem& sys, int ne, const Eigen::VectorXd& v) {
  const int ns = static_cast<int>(sys.setup.size());
  if (ns == 0) return "confounded with other error motions (no set-up term is fitted)";
  const Eigen::MatrixXd s = sys.a.rightCols(ns);
  const Eigen::VectorXd x = s.completeOrthogonalDecomposition().solve(-sys.a.leftCols(ne) * v);
  bool kinds[3] = {false, false, false};
  for (int i = 0; i < ns; ++i)
    if (std::abs(x(i)) > 1e-6 * std::max(1.0, x.cwiseAbs().maxCoeff())) kinds[sys.setup_kind[i]] = true;
  std::string out;
  if (kinds[0]) out += "the length offsets";
  if (kinds[1] || kinds[2]) out += std::string(out.empty() ? "" : " and ") + "the centring (first harmonic of dl)";
  return out.empty() ? "confounded with other error motions" : "confounded with " + out;
}

// Names the null span (orthonormal basis q of the error part): the candidate families inside
// it, then what is left as counted directions with their largest entries.
std::vector<std::string> BbiNameFamilies(const BbiSystem& sys, Axis axis, const Eigen::MatrixXd& q,
                                         const std::vector<std::string>& entry_names) {
  std::vector<std::string> out;
  if (q.cols() == 0) return out;
  const int ne = static_cast<int>(q.rows());
  Eigen::MatrixXd found(ne, 0);
  for (int sign : {+1, -1}) {
    for (const BbiFamily& f : BbiCandidates(axis, sys.nodes_deg, sign)) {
      if (f.v.norm() == 0.0) continue;
      const Eigen::VectorXd in_span = q * (q.transpose() * f.v);
      if ((f.v - in_span).norm() > kBbiSpanTol * f.v.norm()) continue;
      if (found.cols() > 0) {  // already named (the axial families match for both signs)
        const Eigen::VectorXd rest = f.v - found * found.completeOrthogonalDecomposition().solve(f.v);
        if (rest.norm() < kBbiSpanTol * f.v.norm()) continue;
      }
      found.conservativeResize(Eigen::NoChange, found.cols() + 1);
      found.col(found.cols() - 1) = f.v;
      out.push_back(f.name + ": " + BbiAbsorbedBy(sys, ne, f.v));
    }
  }
  Eigen::MatrixXd rest = q;
  if (found.cols() > 0) rest -= found * found.completeOrthogonalDecomposition().solve(q);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(rest, Eigen::ComputeThinU);
  for (int c = 0; c < svd.singularValues().size(); ++c) {
    if (svd.singularValues()(c) < kBbiSpanTol) break;
    const Eigen::VectorXd u = svd.matrixU().col(c);
    std::vector<int> idx(ne);
    for (int i = 0; i < ne; ++i) idx[i] = i;
    std::partial_sort(idx.begin(), idx.begin() + std::min(3, ne), idx.end(),
                      [&](int x, int y) { return std::abs(u(x)) > std::abs(u(y)); });
    std::string s = "a further combination, largest entries:";
    for (int i = 0; i < std::min(3, ne); ++i) {
      char buf[48];
      std::snprintf(buf, sizeof buf, " %+.3f ", u(idx[i]));
      s += buf + entry_names[idx[i]];
    }
    out.push_back(s);
  }
  return out;
}

// Step 3: the minimum-norm solution x_mn = w U_r^T y of the scaled system, w = D V_r S_r^-1 (so
// the covariance is sigma^2 w w^T), and the null directions, unscaled (zero columns included).
struct BbiSolution {
  int rank = 0;
  Eigen::VectorXd x_mn;
  Eigen::MatrixXd w, null;
};

BbiSolution BbiSolve(const BbiSystem& sys, double rank_tolerance) {
  const int nx = static_cast<int>(sys.a.cols());
  Eigen::VectorXd scale(nx);
  for (int c = 0; c < nx; ++c) {
    const double n = sys.a.col(c).norm();
    scale(c) = n > 0.0 ? 1.0 / n : 0.0;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(sys.a * scale.asDiagonal(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  BbiSolution out;
  while (out.rank < sv.size() && sv(out.rank) > rank_tolerance * sv(0)) ++out.rank;
  const Eigen::MatrixXd& v = svd.matrixV();
  out.w = scale.asDiagonal() * v.leftCols(out.rank) * sv.head(out.rank).cwiseInverse().asDiagonal();
  out.x_mn = out.w * (svd.matrixU().leftCols(out.rank).transpose() * sys.y);
  out.null = scale.asDiagonal() * v.rightCols(nx - out.rank);
  for (int c = 0; c < nx; ++c) {  // a zero column (scale 0) is null too
    if (scale(c) > 0.0) continue;
    out.null.conservativeResize(Eigen::NoChange, out.null.cols() + 1);
    out.null.col(out.null.cols() - 1) = Eigen::VectorXd::Unit(nx, c);
  }
  return out;
}

// Step 4: qb, an orthonormal basis of the error part of the null space; t, the map from any
// least-squares solution to the one with no error component along qb (t = I - N (qb^T N_e)^+
// qb^T E); setup_only, the set-up part of the null directions without an error part.
struct BbiConvention {
  Eigen::MatrixXd qb, t, setup_only;
};

BbiConvention BbiApplyConvention(const BbiSolution& sol, int ne) {
  const int nx = static_cast<int>(sol.x_mn.size());
  BbiConvention out;
  out.qb.resize(ne, 0);
  out.t = Eigen::MatrixXd::Identity(nx, nx);
  out.setup_only.resize(nx - ne, 0);
  if (sol.null.cols() == 0) return out;
  const Eigen::MatrixXd null_e = sol.null.topRows(ne);
  Eigen::JacobiSVD<Eigen::MatrixXd> ns(null_e, Eigen::ComputeThinU | Eigen::ComputeFullV);
  const Eigen::VectorXd& nsv = ns.singularValues();
  int k = 0;
  while (k < nsv.size() && nsv(k) > kBbiSpanTol * nsv(0)) ++k;
  out.qb = ns.matrixU().leftCols(k);
  out.setup_only = sol.null.bottomRows(nx - ne) * ns.matrixV().rightCols(sol.null.cols() - k);
  if (k == 0) return out;
  const Eigen::MatrixXd qn = out.qb.transpose() * null_e;
  out.t.leftCols(ne) -= sol.null * qn.completeOrthogonalDecomposition().pseudoInverse() * out.qb.transpose();
  return out;
}

// Step 5: the entries of `out->errors` (value, u, interval, flags) from the solution x and its
// covariance; returns their names "E_XC(C 40)".
std::vector<std::string> BbiFillEntries(const BbiSystem& sys, Axis axis, const Eigen::VectorXd& x,
                                        const Eigen::MatrixXd& cov, const Eigen::MatrixXd& qb,
                                        BallbarIdentification* out) {
  const int ne = 6 * static_cast<int>(sys.nodes_deg.size());
  const double k95 = out->dof > 0 ? internal::StudentTQuantile975(out->dof) : 0.0;
  std::vector<std::string> entry_names;
  for (int e = 0; e < ne; ++e) {
    const CoefficientInfo& info = out->errors.coefficient_info(e);
    BallbarErrorEntry x_e;
    x_e.symbol = out->errors.terms()[info.term].label;
    x_e.coefficient = info.name;
    x_e.angle_deg = sys.nodes_deg[info.index];
    x_e.unit = info.unit;
    entry_names.push_back(x_e.symbol + "(" + std::string(1, AxisLetter(axis)) + " " + BbiDeg(x_e.angle_deg) + ")");
    const double in_span = qb.cols() > 0 ? qb.row(e).squaredNorm() : 0.0;
    x_e.identifiable = in_span < 1.0 - kBbiRowTol;
    x_e.convention_dependent = in_span > kBbiRowTol;
    if (x_e.convention_dependent) ++out->convention_dependent;
    if (x_e.identifiable) {
      x_e.value = x(e);
      out->errors.set_coefficient(e, x_e.value / info.display_per_internal);
      if (out->sigma_known) {
        x_e.u = std::sqrt(std::max(0.0, cov(e, e)));
        x_e.ci95_low = x_e.value - k95 * x_e.u;
        x_e.ci95_high = x_e.value + k95 * x_e.u;
      }
    } else {
      out->covariance.row(e).setZero();
      out->covariance.col(e).setZero();
      out->not_identifiable.push_back(entry_names.back());
    }
    out->entries.push_back(std::move(x_e));
  }
  return entry_names;
}

}  // namespace

Status BallbarIdentificationOptions::Validate() const {
  if (!IsRotary(axis)) return Status(StatusCode::kInvalidArgument, "the identified axis must be rotary (A, B, C)");
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1.0))
    return Status(StatusCode::kInvalidArgument, "rank_tolerance must be in (0, 1)");
  return Status();
}

Result<BallbarIdentification> IdentifyBallbar(const MachineModel& model,
                                              const std::vector<BallbarGeometry>& installations,
                                              const std::vector<BallbarReading>& readings,
                                              const BallbarIdentificationOptions& options) {
  // 1. Inputs, nodes, the zero tables and the set-up columns.
  TPCAL_RETURN_IF_ERROR(BbiCheck(model, installations, readings, options));
  BbiSystem sys;
  BbiNodes(model, readings, options.axis, &sys);
  if (sys.nodes_deg.size() < 2)
    return Status(StatusCode::kInvalidArgument, "ball-bar identification needs readings at 2 or more angles");
  Result<ErrorState> zero = BbiZeroTables(model, options.axis, sys);
  TPCAL_RETURN_IF_ERROR(zero);
  BallbarIdentification out(*zero);
  out.angle_deg = sys.nodes_deg;
  out.periodic = sys.periodic;
  BbiSetupColumns(installations, readings, options, &sys);
  // 2. The linear system dl - dl0 = [G S] x.
  TPCAL_RETURN_IF_ERROR(BbiDesign(model, installations, readings, &out.errors, &sys));
  const int nn = static_cast<int>(sys.nodes_deg.size()), ne = 6 * nn;
  const int nx = static_cast<int>(sys.a.cols()), nr = static_cast<int>(sys.a.rows());
  // 3. Scaled SVD least squares; 4. the convention on the null space.
  const BbiSolution sol = BbiSolve(sys, options.rank_tolerance);
  out.rows = nr, out.unknowns = nx, out.rank = sol.rank, out.dof = nr - sol.rank;
  const Eigen::VectorXd resid = sys.y - sys.a * sol.x_mn;
  for (int r = 0; r < nr; ++r) out.residuals_um.push_back(resid(r));
  out.sigma_known = out.dof > 0;
  out.sigma_um = out.sigma_known ? std::sqrt(resid.squaredNorm() / out.dof) : 0.0;
  const BbiConvention conv = BbiApplyConvention(sol, ne);
  const Eigen::VectorXd x = conv.t * sol.x_mn;
  const Eigen::MatrixXd cov = out.sigma_um * out.sigma_um * (conv.t * sol.w * sol.w.transpose() * conv.t.transpose());
  out.covariance = cov.topLeftCorner(ne, ne);
  out.not_separable_basis = conv.qb;
  const Eigen::MatrixXd& qb = conv.qb;
  const Eigen::MatrixXd& setup_only = conv.setup_only;
  // 5. Entries, set-up terms, the words.
  const std::vector<std::string> entry_names = BbiFillEntries(sys, options.axis, x, cov, qb, &out);
  for (std::size_t s = 0; s < sys.setup.size(); ++s) {
    BallbarSetupTerm term = sys.setup[s];
    const int c = ne + static_cast<int>(s);
    term.identifiable = setup_only.cols() == 0 || setup_only.row(static_cast<int>(s)).norm() < kBbiSpanTol;
    if (term.identifiable) {
      term.value_um = x(c);
      term.u_um = out.sigma_known ? std::sqrt(std::max(0.0, cov(c, c))) : 0.0;
    }
    out.setup_terms.push_back(term);
  }
  out.not_separable = BbiNameFamilies(sys, options.axis, qb, entry_names);
  out.conventions = {
      "the maps carry no component along the not-separable families (orthogonal in um and urad); "
      "those parts are absorbed by the set-up terms and are reported nowhere",
      out.sigma_known ? "sigma from the residuals, dof = rows - rank; 95 % intervals Student t"
                      : "dof <= 0: sigma unknown, no u and no interval is given",
  };
  return out;
}

Result<Eigen::MatrixXd> BallbarMapResponse(const MachineModel& model, const std::vector<BallbarGeometry>& installations,
                                           const std::vector<BallbarReading>& readings,
                                           const std::vector<std::string>& errors,
                                           const BallbarIdentificationOptions& options) {
  Eigen::MatrixXd out;
  Workspace ws;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (std::find(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(k), errors[k]) != errors.begin() + static_cast<std::ptrdiff_t>(k))
      return Status(StatusCode::kInvalidArgument, "ball-bar map response: '" + errors[k] + "' named twice");
    ErrorState unit(model);
    auto active = ActivateParameters(model, &unit, {errors[k]});
    if (!active.ok()) return active.status();
    if (active->coefficients.size() != 1)
      return Status(StatusCode::kInvalidArgument, "ball-bar map response: '" + errors[k] + "' is not one position-independent error");
    const int c = active->coefficients.front();
    unit.set_coefficient(c, 1.0 / unit.coefficient_info(c).display_per_internal);
    std::vector<BallbarReading> alone = readings;
    for (BallbarReading& r : alone) {
      if (r.installation < 0 || r.installation >= static_cast<int>(installations.size()))
        return Status(StatusCode::kInvalidArgument, "a ball-bar reading names no installation");
      auto dl = SimulateBallbarDlUm(model, unit, installations[static_cast<std::size_t>(r.installation)], r.angle_deg,
                                    r.t_s, &ws);
      if (!dl.ok()) return dl.status();
      r.dl_um = *dl;
    }
    auto id = IdentifyBallbar(model, installations, alone, options);
    if (!id.ok()) return id.status();
    if (k == 0) out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(id->entries.size()), static_cast<Eigen::Index>(errors.size()));
    for (std::size_t i = 0; i < id->entries.size(); ++i)
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = id->entries[i].value;
  }
  return out;
}

}  // namespace tpcal::kinematics
