// ForwardModel with nonlinear terms (geometric nonlinearity): Newton per load case (its first
// iterate is the linear solution), load stepping when that fails, and the exact parameter
// derivatives from the tangent at the converged state (implicit function theorem:
// R(u(theta), theta) = f(theta)). With ModelTerms::nonlinear_weight the prediction blends the
// linear and nonlinear solutions, u = (1 - w) u_lin + w u_nl, with exact derivatives of both.
// A factorised tangent carries the state it was made at (KeptTangent): a Jacobian at an
// equilibrium of the same matrix solves on it. Only the hold-out folds' caches take their
// Jacobians on the tangent at hand instead (FactorizationCache::jacobians_on_kept_tangents).
#include <Eigen/CholmodSupport>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "factorization_cache.hpp"
#include "free_block.hpp"
#include "isospring/analysis/tangent_solver.hpp"
#include "isospring/fitting/identify_model.hpp"

namespace isospring::fitting {

struct ForwardModel::NonlinearCache {
  std::mutex mutex;
  std::vector<Eigen::VectorXd> solutions;         // per load case; empty until solved
  std::vector<Eigen::VectorXd> linear_solutions;  // the linear solution at the same theta, or empty
  // The factorisations of an evaluation, kept so that the next one reuses their symbolic
  // analyses (the tangent's pattern does not change with u or theta); one evaluation at a time.
  std::mutex solver_mutex;
  // The linear K_ff's factor and the coefficients it was made for: a fit's next evaluation
  // that changed only E (every coefficient scaled alike) solves with it, scaled.
  KeptTangent linear_solver;
  std::vector<double> linear_coefficients;  // empty: no factor
  // Per load case: its last factorised tangent (valid once factorised), the chord matrix of the
  // next evaluation's Newton iterations.
  std::vector<std::shared_ptr<KeptTangent>> tangent_solvers;
  std::vector<char> factorised;  // not vector<bool>: load cases write theirs concurrently
};

std::shared_ptr<ForwardModel::NonlinearCache> ForwardModel::make_nonlinear_cache() {
  return std::make_shared<NonlinearCache>();
}

namespace {

constexpr double kTolerance = 1e-10;  // |r_free| relative to the load (or the reactions)
constexpr int kMaxIterations = 30;
constexpr int kMaxSteps = 64;                   // load steps of the last attempt
constexpr double kSmallestFirstStep = 1.0 / 8;  // solve_equilibrium's ladder stops below it
// Chord (modified Newton) steps reuse the last factorised tangent of the load case instead of
// assembling and factorising a new one: a fit's next evaluation is at a nearby theta, where they
// converge fast, and the element tangents are most of a Newton iteration's cost (~14 Mflop per
// degree-3 solid element against ~1 for its forces; measured on the suite's large-deformation
// cantilever: 46 % of identify's time in their dense products). A chord step that reduces the
// residual by less than kChordRate is undone and replaced by a Newton step, after which chord
// steps resume on the new tangent (measured on the suite's tube_graded, whose shear load cases
// converge slowly at first: the two score tests of the large-deformation candidate took 9 and 5
// tangents instead of 12 and 10 when one slow chord step stopped them for the solve).
constexpr double kChordRate = 0.25;
constexpr int kMaxChordSteps = 12;
// The markers' accuracy where only they count (the score test at w = 0), relative to their
// displacement: 1e-6 is 5e-4 of a noise of 0.2 % of the displacement (the suite's), and the
// chord steps from there to the force tolerance were a third of the score test's time on the
// suite's cantilever at nu = 0.45 (and a slow one near the end cost a tangent).
constexpr double kMarkerTolerance = 1e-6;
// The residual's rounding floor relative to the forces it is the difference of (see
// force_magnitude), with a margin: measured 0.9-4e-16 of them where Newton stalled (below), so
// 1e-14 accepts only iterates within 25-100 x that floor.
constexpr double kRoundOff = 1e-14;
// Above this fraction of the load the rounding floor is not looked at: it would take forces
// 1e10 x the load (a floor of 1e-6 of it) to reach there.
constexpr double kRoundOffGate = 1e-4;

// The size of the forces whose difference the free residual is: || |K| |u| || on the free DOFs,
// entry by entry, so without the cancellation of K u itself. Why: the residual cannot be computed
// more accurately than about the machine epsilon times this, and for a nearly incompressible,
// slender body in bending it exceeds the load by orders of magnitude (lambda ~ 25 E at nu = 0.49
// times a displacement field whose second differences are the load). Measured on the suite's
// cantilever at nu = 0.49 with support springs (8,019 DOFs): the forces are ~1e6 x the load,
// and Newton stalled at |r| = 4.4e-10 and 8e-11 (two load cases), just above 1e-10 of the load,
// and spent its 30 tangents there; the clamped model passed the same test only thanks to its
// reactions.
double force_magnitude(const Eigen::SparseMatrix<double>& stiffness, const Eigen::VectorXd& u,
                       const std::vector<int>& free_index) {
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(u.size());
  for (int c = 0; c < stiffness.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(stiffness, c); it; ++it)
      rows[it.row()] += std::abs(it.value() * u[c]);
  double sum = 0.0;
  for (Eigen::Index d = 0; d < rows.size(); ++d)
    if (free_index[static_cast<size_t>(d)] >= 0) sum += rows[d] * rows[d];
  return std::sqrt(sum);
}

// A model's first solve on another model's tangent (NonlinearEvaluation::chords_from_start):
// Anderson mixing over the last 5 chord increments, at most 20 steps, given up after 3 steps
// without a smaller increment. Measured on the suite's cantilever_frame_gravity_nu049 (8,019
// DOFs): 10-15 residual evaluations per load case to the force tolerance, about 0.12 s each
// against 2 s for a tangent's assembly and factorisation.
constexpr int kAndersonDepth = 5;
constexpr int kMaxStartChords = 20;
constexpr int kStartStall = 3;

// s > 0 with c_j = s c0_j to 1e-13 of c_j for every j, else 0.
double common_scale(const std::vector<double>& c, const std::vector<double>& c0) {
  if (c.size() != c0.size() || c.empty()) return 0.0;
  double s = 0.0;
  for (size_t j = 0; j < c.size() && s == 0.0; ++j)
    if (c0[j] != 0.0) s = c[j] / c0[j];
  if (!(s > 0.0)) return 0.0;
  for (size_t j = 0; j < c.size(); ++j)
    if (std::abs(c[j] - s * c0[j]) > 1e-13 * std::abs(c[j])) return 0.0;
  return s;
}

}  // namespace

// One evaluation at theta, as its stages: the coefficients at theta and the summed stiffness,
// the linear solutions (for the blend), the caches' per-load-case slots, then per load case a
// Newton solve from the best start at hand and the prediction with its Jacobian. The caller
// holds the nonlinear caches' locks throughout.
class ForwardModel::NonlinearEvaluation {
 public:
  NonlinearEvaluation(const ForwardModel& model, const Eigen::VectorXd& theta, bool with_jacobian,
                      bool linearised, double* series)
      : m_(model),
        theta_(theta),
        with_jacobian_(with_jacobian),
        linearised_(linearised),
        series_(series),
        nf_(static_cast<int>(model.free_dofs_.size())),
        nls_(static_cast<size_t>(model.num_load_cases_)),
        cache_(*model.nonlinear_cache_),
        shared_(*model.linear_cache_),
        linear_solver_(model.nonlinear_cache_->linear_solver) {}

  ModelEvaluation run() {
    evaluate_coefficients();
    if (linearised_ && (w_index_ < 0 || w_ != 0.0))
      throw std::logic_error("ForwardModel::evaluate_linearised: needs the blend weight at w = 0");
    factorise_linear_stiffness();
    solve_linear();
    if (linearised_) return linearised_at_zero_weight(series_);
    prepare_caches();
    return solve_load_cases();
  }

 private:
  using Parts = std::vector<std::vector<Eigen::VectorXd>>;  // per nonlinear term, n_k(u)

  void evaluate_coefficients();
  void factorise_linear_stiffness();
  void solve_linear();
  void prepare_caches();
  ModelEvaluation solve_load_cases();
  ModelEvaluation linearised_at_zero_weight(double* series) const;
  Eigen::VectorXd second_order_term(const Eigen::VectorXd& u, const Eigen::VectorXd& v) const;
  void solve_load_case(size_t lc, ModelEvaluation& out);
  Eigen::VectorXd newton_start(size_t lc, bool factorised, const KeptTangent*& borrowed);
  bool chords_from_start(size_t lc, const KeptTangent& tangent, Eigen::VectorXd& u) const;
  bool solve_equilibrium(size_t lc, Eigen::VectorXd& u, KeptTangent& solver, bool& factorised,
                         const KeptTangent* borrowed, bool own_start, Parts& parts);
  std::shared_ptr<KeptTangent> kept_equilibrium(size_t lc, Eigen::VectorXd& u, Parts& parts) const;
  void remember(size_t lc, const Eigen::VectorXd& u, bool converged, bool factorised);
  void predict(size_t lc, Eigen::VectorXd u, const Parts& parts, const KeptTangent& solver,
               ModelEvaluation& out) const;

  Eigen::VectorXd internal_force(const Eigen::VectorXd& u, Parts& parts,
                                 Eigen::SparseMatrix<double>* tangent_ff) const;
  bool free_residual(const Eigen::VectorXd& force, double s, const Eigen::VectorXd& u,
                     const Eigen::VectorXd& internal, Eigen::VectorXd& r_free) const;
  bool residual_converged(double norm, double scale, const Eigen::VectorXd& u) const;
  void step(const KeptTangent& factor, const Eigen::VectorXd& r_free, Eigen::VectorXd& u) const;
  bool newton(size_t lc, const Eigen::VectorXd& force, double s, Eigen::VectorXd& u,
              KeptTangent& solver, bool& factorised, const KeptTangent* borrowed, Parts& parts);
  bool factorise_tangent(const Eigen::VectorXd& u, Parts& parts, KeptTangent& solver) const;
  Eigen::MatrixXd linear_rhs(const Eigen::MatrixXd& dforce, const Eigen::VectorXd& v) const;
  Eigen::MatrixXd solve_free(const KeptTangent& factor, const Eigen::MatrixXd& rhs) const;

  const ForwardModel& m_;
  const Eigen::VectorXd& theta_;
  const bool with_jacobian_;
  const bool linearised_;  // evaluate_linearised: no Newton, du/dw to first order at w = 0
  double* const series_;   // evaluate_linearised's second_order_ratio, or null
  const int nf_;           // free DOFs
  const size_t nls_;       // load cases
  NonlinearCache& cache_;
  FactorizationCache& shared_;
  // The linear K_ff at theta (the tangent at u = 0). The chord steps of the load cases that run
  // at the same time share it; its solves take turns (KeptTangent::solve).
  KeptTangent& linear_solver_;

  // Set by evaluate_coefficients: the linear terms' coefficients c_j and gradients, K_ff and
  // K = sum_j c_j K_j; the nonlinear terms' coefficients e_k and gradients, per term.
  std::vector<double> c_;
  std::vector<Eigen::VectorXd> dc_;
  Eigen::SparseMatrix<double> kff_;
  Eigen::SparseMatrix<double> stiffness_;
  std::vector<std::vector<double>> e_;
  std::vector<std::vector<Eigen::VectorXd>> de_;
  int w_index_ = -1;           // the blend weight's index (ModelTerms::nonlinear_weight)
  double w_ = 1.0;             // the blend weight
  bool need_tangent_ = false;  // the Jacobian needs the tangent at the converged state
  // Newton ends with a factorised tangent at its solution (exact Jacobians); else, with
  // FactorizationCache::jacobians_on_kept_tangents, the Jacobian solves on the tangent at hand.
  bool tangent_at_solution_ = false;
  // Which tangent matrix this evaluation's coefficients make (KeptTangent::key and terms).
  std::vector<double> tangent_key_;
  std::vector<const void*> tangent_terms_;

  // Set by solve_linear, per load case: the load and its derivatives, the linear solution and
  // its derivatives (with the blend only).
  std::vector<Eigen::VectorXd> forces_, u_linear_;
  std::vector<Eigen::MatrixXd> dforces_, du_linear_;
};

void ForwardModel::NonlinearEvaluation::evaluate_coefficients() {
  const size_t nt = m_.terms_.stiffness.size();
  c_.resize(nt);
  dc_.resize(nt);
  kff_.resize(nf_, nf_);
  for (size_t j = 0; j < nt; ++j) {
    c_[j] = m_.terms_.stiffness[j].coefficient(theta_, &dc_[j]);
    kff_ += c_[j] * m_.free_blocks_[j];
  }
  // Values and gradients of the nonlinear coefficients, per nonlinear term.
  const size_t nn = m_.terms_.nonlinear.size();
  e_.resize(nn);
  de_.resize(nn);
  for (size_t t = 0; t < nn; ++t)
    for (const Coefficient& coefficient : m_.terms_.nonlinear[t].coefficients) {
      Eigen::VectorXd g;
      e_[t].push_back(coefficient(theta_, &g));
      de_[t].push_back(g);
    }
  // K = sum_j c_j K_j, summed once here: a Newton solve evaluates the force ~10 times per load
  // case, and a product with each K_j costs as much as one with their sum (measured on the
  // suite's tube_graded with a stiffness gradient, 8 terms: a force evaluation 95 -> 52 ms).
  stiffness_.resize(m_.num_dofs_, m_.num_dofs_);
  for (size_t j = 0; j < nt; ++j) stiffness_ += c_[j] * m_.terms_.stiffness[j].matrix;
  w_index_ = m_.terms_.nonlinear_weight;
  w_ = w_index_ >= 0 ? theta_[w_index_] : 1.0;
  // The Jacobian needs the tangent at the converged state unless the blend weight is 0: there
  // du/dtheta = du_lin/dtheta and du/dw = u_nl - u_lin, so u_nl itself is all that is needed
  // (the score screening of the candidate evaluates exactly there, at its neutral w = 0).
  need_tangent_ = with_jacobian_ && w_ != 0.0;
  tangent_at_solution_ = need_tangent_ && !shared_.jacobians_on_kept_tangents;
  // The tangent K_ff + sum_k e_k dn_k/du is fixed by the free DOFs, the stiffness terms with a
  // non-zero coefficient (each named by its part of the model's fingerprint: entries, sum,
  // weighted sum) and their coefficients, and the nonlinear terms and theirs. Terms with a zero
  // coefficient add nothing: a candidate at its neutral values (a stiffness gradient at a = 0)
  // makes the tangent of the model without it.
  tangent_key_.clear();
  for (size_t j = 0; j < nt; ++j)
    if (c_[j] != 0.0) {
      const auto at = m_.fingerprint_.begin() + 3 + 3 * static_cast<std::ptrdiff_t>(j);
      tangent_key_.insert(tangent_key_.end(), at, at + 3);
      tangent_key_.push_back(c_[j]);
    }
  tangent_terms_.clear();
  for (size_t t = 0; t < nn; ++t) {
    tangent_key_.insert(tangent_key_.end(), e_[t].begin(), e_[t].end());
    // A term without an identity is this model's own: only its own tangents match.
    const void* identity = m_.terms_.nonlinear[t].identity;
    tangent_terms_.push_back(identity ? identity : &cache_);
  }
}

// The linear stiffness's factor, for the linear solutions of the blend. A fit of the model
// changes E at every step, which scales K_ff as a whole: the factor made at the first
// evaluation serves every later one, scaled (one factorisation per evaluation before). The
// solutions differ from a new factorisation's by rounding
// (KeptTangentCantilever.TheBlendsLinearFactorServesAChangeOfEScaled).
void ForwardModel::NonlinearEvaluation::factorise_linear_stiffness() {
  if (w_index_ < 0) return;
  const double scale = common_scale(c_, cache_.linear_coefficients);
  if (scale > 0.0) {
    linear_solver_.scale = scale;
    return;
  }
  cache_.linear_coefficients.clear();
  linear_solver_.scale = 1.0;
  ++shared_.blend_factorizations;
  if (!linear_solver_.solver.compute(kff_))
    throw std::runtime_error(
        "the stiffness at the current parameters is not positive definite (a parameter left "
        "its physical range, e.g. a negative Young's modulus or nu >= 0.5)");
  cache_.linear_coefficients = c_;
}

// Internal force at u: K u + sum_k e_k n_k(u); the nonlinear parts and the free tangent block
// come along.
Eigen::VectorXd ForwardModel::NonlinearEvaluation::internal_force(
    const Eigen::VectorXd& u, Parts& parts, Eigen::SparseMatrix<double>* tangent_ff) const {
  const size_t nn = m_.terms_.nonlinear.size();
  parts.resize(nn);
  Eigen::VectorXd r = stiffness_ * u;
  if (tangent_ff) *tangent_ff = kff_;
  for (size_t t = 0; t < nn; ++t) {
    Eigen::SparseMatrix<double> tangent;
    m_.terms_.nonlinear[t].evaluate(u, e_[t], parts[t], tangent_ff ? &tangent : nullptr);
    for (size_t k = 0; k < parts[t].size(); ++k) r += e_[t][k] * parts[t][k];
    if (tangent_ff) *tangent_ff += detail::free_upper_block(tangent, m_.free_index_, nf_);
  }
  return r;
}

// The residual on the free DOFs at load factor s at u (`internal`: the internal force there), and
// whether it counts as converged (residual_converged).
bool ForwardModel::NonlinearEvaluation::free_residual(const Eigen::VectorXd& force, double s,
                                                      const Eigen::VectorXd& u,
                                                      const Eigen::VectorXd& internal,
                                                      Eigen::VectorXd& r_free) const {
  r_free.resize(nf_);
  double load = 0.0, reaction = 0.0;
  for (int d = 0; d < m_.num_dofs_; ++d) {
    const int k = m_.free_index_[static_cast<size_t>(d)];
    if (k >= 0) {
      r_free[k] = s * force[d] - internal[d];
      load += s * s * force[d] * force[d];
    } else {
      reaction += internal[d] * internal[d];
    }
  }
  return residual_converged(r_free.norm(), std::sqrt(std::max(load, reaction)), u);
}

// The one convergence test of every Newton and chord loop here: the free residual's norm is
// below kTolerance of `scale` (the larger of the load and the reactions), or it is at its
// rounding floor at u, where no iteration can reduce it further. The floor is looked at only
// once the residual is below kRoundOffGate of the scale (a pass over all of K, as the product
// K u in the residual itself). One function, so that a loop cannot stall at the floor that
// another accepts (a model's first solve on a kept tangent did, running its chord steps to the
// stall limit and handing the converged iterate to Newton).
bool ForwardModel::NonlinearEvaluation::residual_converged(double norm, double scale,
                                                           const Eigen::VectorXd& u) const {
  if (norm <= kTolerance * scale || norm == 0.0) return true;
  return norm <= kRoundOffGate * scale &&
         norm <= kRoundOff * force_magnitude(stiffness_, u, m_.free_index_);
}

void ForwardModel::NonlinearEvaluation::step(const KeptTangent& factor,
                                             const Eigen::VectorXd& r_free,
                                             Eigen::VectorXd& u) const {
  const Eigen::VectorXd du = factor.solve(r_free);
  for (int k = 0; k < nf_; ++k) u[m_.free_dofs_[static_cast<size_t>(k)]] += du[k];
}

// Newton at load factor s (loads and prescribed values scaled) from u, updated in place, with
// chord steps while they converge fast: on `solver` when it holds a factorised tangent
// (`factorised`), else on `borrowed` (another model's last tangent at the same free DOFs), else
// on the linear stiffness (the tangent at u = 0, factorised for the blend), which is all a small
// deformation needs. On success at s = 1 with tangent_at_solution_, `solver` holds the factorised
// tangent at the converged u (else that factorisation is skipped: no solve needs it).
bool ForwardModel::NonlinearEvaluation::newton(size_t lc, const Eigen::VectorXd& force, double s,
                                               Eigen::VectorXd& u, KeptTangent& solver,
                                               bool& factorised, const KeptTangent* borrowed,
                                               Parts& parts) {
  for (int d = 0; d < m_.num_dofs_; ++d)
    if (m_.free_index_[static_cast<size_t>(d)] < 0) u[d] = s * m_.prescribed_[d];
  Eigen::VectorXd r_free, before_chord, r_before_chord;
  double norm_before_chord = 0.0;
  bool after_chord = false;
  int chords = 0;
  // The score test's evaluation at w = 0 (no tangent needed) uses the solution only through its
  // markers: it stops once a chord step that contracted the residual at least kChordRate-fold
  // moved them by at most kMarkerTolerance of their displacement, the rest of the linearly
  // converging iteration then being below a third of that step.
  const bool marker_stop = s == 1.0 && w_index_ >= 0 && w_ == 0.0 && !need_tangent_;
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& h = m_.observations_[lc].operator_;
  double marker_step = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= kMaxIterations; ++it) {
    bool converged = free_residual(force, s, u, internal_force(u, parts, nullptr), r_free);
    const double norm = r_free.norm();
    if (marker_stop && !converged && after_chord && norm <= kChordRate * norm_before_chord &&
        marker_step <= kMarkerTolerance * (h * u).norm())
      converged = true;
    if (!std::isfinite(norm)) {
      if (!after_chord) return false;
      converged = false;
    }
    if (after_chord && !converged && !(norm <= kChordRate * norm_before_chord)) {
      u = before_chord;  // too slow: a Newton step from where the chord step started
      r_free = r_before_chord;
    } else if (converged && !(tangent_at_solution_ && s == 1.0)) {
      return true;
    } else if (!converged && (factorised || borrowed || w_index_ >= 0) && chords < kMaxChordSteps) {
      before_chord = u;
      r_before_chord = r_free;
      norm_before_chord = norm;
      after_chord = true;
      ++chords;
      if (factorised || borrowed) {
        step(factorised ? solver : *borrowed, r_free, u);
      } else {
        // At rest (u = 0) the tangent is the linear stiffness (the nonlinear parts are of
        // second order and up), so a step on the linear factor from there is Newton's own: it
        // is kept however little it reduces the residual. Undone as a slow chord step, it would
        // be repeated on a factorised tangent at u = 0, the same matrix (measured on the suite's
        // cantilever at nu = 0.45, 8,019 DOFs: the residual at the linear solution is 48 x the
        // load, and 2 of the first score test's 5 factorisations were those).
        if (u.isZero(0.0)) after_chord = false;
        step(linear_solver_, r_free, u);
      }
      if (marker_stop) marker_step = (h * (u - before_chord)).norm();
      continue;
    }
    after_chord = false;
    if (it == kMaxIterations) return false;
    factorised = factorise_tangent(u, parts, solver);
    if (!factorised) return false;
    if (converged) return true;
    step(solver, r_free, u);
  }
  return false;
}

// The tangent at u assembled and factorised into `solver`, which then carries the state it was
// made at (KeptTangent); `parts` are the nonlinear parts at u. False when it is singular.
bool ForwardModel::NonlinearEvaluation::factorise_tangent(const Eigen::VectorXd& u, Parts& parts,
                                                          KeptTangent& solver) const {
  Eigen::SparseMatrix<double> tangent_ff;
  internal_force(u, parts, &tangent_ff);
  ++shared_.tangent_factorizations;
  solver.scale = 1.0;
  solver.has_state = solver.solver.compute(tangent_ff);
  if (!solver.has_state) return false;
  solver.key = tangent_key_;
  solver.terms = tangent_terms_;
  solver.free_dofs = m_.free_dofs_;
  solver.u = u;
  return true;
}

// Right-hand sides df/dtheta - dK/dtheta v for the linear terms at displacement v.
Eigen::MatrixXd ForwardModel::NonlinearEvaluation::linear_rhs(const Eigen::MatrixXd& dforce,
                                                              const Eigen::VectorXd& v) const {
  Eigen::MatrixXd rhs = dforce;
  for (size_t j = 0; j < c_.size(); ++j)
    if (dc_[j].cwiseAbs().maxCoeff() > 0.0)
      rhs -= (m_.terms_.stiffness[j].matrix * v) * dc_[j].transpose();
  return rhs;
}

// factor^-1 rhs on the free DOFs, zero on the others.
Eigen::MatrixXd ForwardModel::NonlinearEvaluation::solve_free(const KeptTangent& factor,
                                                              const Eigen::MatrixXd& rhs) const {
  Eigen::MatrixXd rhs_free(nf_, rhs.cols());
  for (int k = 0; k < nf_; ++k) rhs_free.row(k) = rhs.row(m_.free_dofs_[static_cast<size_t>(k)]);
  const Eigen::MatrixXd x_free = factor.solve(rhs_free);
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(m_.num_dofs_, rhs.cols());
  for (int k = 0; k < nf_; ++k) x.row(m_.free_dofs_[static_cast<size_t>(k)]) = x_free.row(k);
  return x;
}

// One load case after the other: the loads, the linear solutions and their derivatives (solves
// with the one linear factor).
void ForwardModel::NonlinearEvaluation::solve_linear() {
  forces_.resize(nls_), u_linear_.resize(nls_);
  dforces_.resize(nls_), du_linear_.resize(nls_);
  // K u = f - K u_c on the free DOFs, as ForwardModel::evaluate.
  const Eigen::VectorXd ku_c = stiffness_ * m_.prescribed_;
  for (int l = 0; l < m_.num_load_cases_; ++l) {
    const auto lc = static_cast<size_t>(l);
    m_.load_vector(l, theta_, with_jacobian_, forces_[lc], dforces_[lc]);
    if (w_index_ >= 0) {
      u_linear_[lc] = m_.prescribed_ + solve_free(linear_solver_, forces_[lc] - ku_c).col(0);
      if (with_jacobian_)
        du_linear_[lc] = solve_free(linear_solver_, linear_rhs(dforces_[lc], u_linear_[lc]));
    }
  }
}

// Every per-load-case slot of the caches, so that the load cases below only write their own.
void ForwardModel::NonlinearEvaluation::prepare_caches() {
  if (cache_.tangent_solvers.size() < nls_) {
    cache_.tangent_solvers.resize(nls_);
    cache_.factorised.resize(nls_, 0);
  }
  for (auto& owned : cache_.tangent_solvers)
    if (!owned) owned = std::make_shared<KeptTangent>();
  auto grow = [this](auto& per_load_case) {
    if (per_load_case.size() < nls_) per_load_case.resize(nls_);
  };
  grow(shared_.nonlinear_starts), grow(shared_.linear_starts), grow(shared_.tangents);
  const std::lock_guard<std::mutex> lock(cache_.mutex);
  grow(cache_.solutions), grow(cache_.linear_solutions);
}

// The Newton solves, the load cases on the nonlinear terms' threads (each load case on one: the
// element loops inside run serially then). A load case reads and writes only its own slots, so
// the numbers do not depend on the thread count or the order.
ModelEvaluation ForwardModel::NonlinearEvaluation::solve_load_cases() {
  const int nl = m_.num_load_cases_;
  int team = 1;
  for (const NonlinearTerm& term : m_.terms_.nonlinear) team = std::max(team, term.threads);
  team = std::min(team, nl);
  ModelEvaluation out;
  out.predictions.resize(nls_), out.jacobians.resize(nls_), out.displacements.resize(nls_);
  std::vector<std::exception_ptr> errors(nls_);
#pragma omp parallel for schedule(dynamic) num_threads(team) if (team > 1)
  for (int l = 0; l < nl; ++l) {
    const auto lc = static_cast<size_t>(l);
    try {
      solve_load_case(lc, out);
    } catch (...) {
      errors[lc] = std::current_exception();
    }
  }
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
  return out;
}

void ForwardModel::NonlinearEvaluation::solve_load_case(size_t lc, ModelEvaluation& out) {
  Eigen::VectorXd u;
  Parts parts;
  if (need_tangent_) {
    // A Jacobian at an equilibrium whose tangent is factorised already: no Newton, no tangent.
    if (const std::shared_ptr<KeptTangent> kept = kept_equilibrium(lc, u, parts)) {
      ++shared_.kept_state_reuses;
      shared_.keep_tangent(lc, kept);  // the one a new model borrows next
      shared_.nonlinear_starts[lc] = u;
      shared_.linear_starts[lc] = u_linear_[lc];
      {
        const std::lock_guard<std::mutex> lock(cache_.mutex);
        cache_.solutions[lc] = u;
        cache_.linear_solutions[lc] = u_linear_[lc];
      }
      predict(lc, std::move(u), parts, *kept, out);
      return;
    }
  }
  const std::shared_ptr<KeptTangent>& owned_solver = cache_.tangent_solvers[lc];
  KeptTangent& solver = *owned_solver;
  bool factorised = cache_.factorised[lc] != 0;
  const KeptTangent* borrowed = nullptr;
  bool own_start = false;  // this model's own last equilibrium is at hand
  {
    const std::lock_guard<std::mutex> lock(cache_.mutex);
    own_start = cache_.solutions[lc].size() == m_.num_dofs_;
  }
  u = newton_start(lc, factorised, borrowed);
  const bool converged = solve_equilibrium(lc, u, solver, factorised, borrowed, own_start, parts);
  // The Jacobian on the tangent at hand (jacobians_on_kept_tangents): this model's last one,
  // else the one its chord steps borrowed; a new one only when there is neither.
  const KeptTangent* jacobian_tangent = &solver;
  if (converged && need_tangent_ && !tangent_at_solution_) {
    if (factorised || borrowed) {
      if (!factorised) jacobian_tangent = borrowed;
      ++shared_.jacobians_on_kept_tangent;
    } else {
      factorised = factorise_tangent(u, parts, solver);
      if (!factorised)
        throw std::runtime_error("the large-deformation tangent is singular for load case " +
                                 std::to_string(lc + 1) + " at the current parameters");
    }
  }
  remember(lc, u, converged, factorised);
  if (!converged)
    throw std::runtime_error(
        "the large-deformation model did not converge for load case " + std::to_string(lc + 1) +
        " at the current parameters (" +
        (own_start ? std::string("Newton from the last equilibrium")
                   : "Newton with up to " + std::to_string(kMaxSteps) + " load steps") +
        ")");
  {
    const std::lock_guard<std::mutex> lock(cache_.mutex);
    cache_.solutions[lc] = u;
    cache_.linear_solutions[lc] = u_linear_[lc];
  }
  predict(lc, std::move(u), parts, *jacobian_tangent, out);
}

// Newton's start: the last solution, this model's or another's (FactorizationCache), moved by
// the change of the linear solution since: u_lin(theta) + (u_nl - u_lin)(theta_last), a
// first-order predictor (the linear part follows a new modulus or stiffness gradient exactly,
// the nonlinear part is carried over); empty when there is none. `borrowed`: another model's
// last tangent at the same free DOFs, for chord steps while this model has none of its own
// (`factorised` false).
//
// With a borrowed tangent (a model's first evaluation: the large-deformation candidate's score
// test in every round after the first) the start is the other model's solution as it is, and
// chords_from_start solves from there on that tangent. The moved start is a poor predictor at
// nu -> 0.5 in bending: the linear model's response to a change of E (or a new load) differs at
// O(1) from the nonlinear model's, whose tangent is at hand. Measured on the suite's
// cantilever_frame_gravity_nu049 (8,019 DOFs), round 2 (E refitted after the frame's motion was
// added): the moved start was 6-9 % of the marker displacement off, and Newton's chord steps,
// judged by the residual's norm, spent 1-2 new tangents per load case (2-5 CPU s each).
Eigen::VectorXd ForwardModel::NonlinearEvaluation::newton_start(size_t lc, bool factorised,
                                                                const KeptTangent*& borrowed) {
  const int n = m_.num_dofs_;
  Eigen::VectorXd u, u_linear_then;
  {
    const std::lock_guard<std::mutex> lock(cache_.mutex);
    u = cache_.solutions[lc];
    u_linear_then = cache_.linear_solutions[lc];
  }
  // This model's first evaluation: another model's solution and tangent.
  if (u.size() != n && shared_.nonlinear_starts[lc].size() == n) {
    u = shared_.nonlinear_starts[lc];
    u_linear_then = shared_.linear_starts[lc];
  }
  if (!factorised && !shared_.tangents[lc].empty()) {
    const std::shared_ptr<KeptTangent>& last = shared_.tangents[lc].front();
    if (last != cache_.tangent_solvers[lc] && last->has_state && last->free_dofs == m_.free_dofs_)
      borrowed = last.get();
  }
  if (u.size() == n && borrowed) {
    ++shared_.kept_tangent_starts;
    if (chords_from_start(lc, *borrowed, u)) ++shared_.kept_tangent_converged;
    return u;
  }
  if (u.size() == n && u_linear_[lc].size() == n && u_linear_then.size() == n)
    u += u_linear_[lc] - u_linear_then;
  return u;
}

// Chord steps d_k = A^-1 (f - r(u_k)) on a kept tangent A, accelerated by Anderson mixing
// (Walker and Ni 2011, "Anderson acceleration for fixed-point iterations"): u_k+1 = u_k + d_k -
// (dU + dD) gamma, gamma the least-squares fit of d_k by the last kAndersonDepth differences dD
// of the increments (dU: of the iterates). For a linear residual this is GMRES on A^-1 K_T: the
// few directions in which A is stale (a slender body's rotations at another load level) are
// resolved in a few steps, where plain chord steps stall and Newton would factorise again.
// Progress is judged by the increments (displacements), not by the residual's norm: at
// nu -> 0.5 that norm is dominated by the volumetric stiffness, and a good step (Newton's own)
// often raises it 10-40-fold before it falls. Only the residual decides convergence, so the
// solution is the equilibrium Newton finds, to the same force tolerance. Ends there (true), else
// leaves u at the iterate with the smallest increment for Newton to continue from.
bool ForwardModel::NonlinearEvaluation::chords_from_start(size_t lc, const KeptTangent& tangent,
                                                          Eigen::VectorXd& u) const {
  for (int d = 0; d < m_.num_dofs_; ++d)
    if (m_.free_index_[static_cast<size_t>(d)] < 0) u[d] = m_.prescribed_[d];
  auto free_part = [this](const Eigen::VectorXd& full) {
    Eigen::VectorXd x(nf_);
    for (int k = 0; k < nf_; ++k) x[k] = full[m_.free_dofs_[static_cast<size_t>(k)]];
    return x;
  };
  Parts parts;
  Eigen::VectorXd r_free, best = u, d_last, x_last;
  Eigen::MatrixXd dd(nf_, 0), dx(nf_, 0);  // the history's differences, oldest first
  double best_size = std::numeric_limits<double>::infinity();
  double last_size = best_size;
  int since_best = 0;
  for (int it = 0; it < kMaxStartChords; ++it) {
    if (free_residual(forces_[lc], 1.0, u, internal_force(u, parts, nullptr), r_free)) return true;
    const Eigen::VectorXd d = tangent.solve(r_free);
    const double size = d.norm();
    if (!std::isfinite(size)) break;
    if (size < best_size) {
      best_size = size;
      best = u;
      since_best = 0;
    } else if (++since_best >= kStartStall) {
      break;
    }
    // A growing increment: the history no longer describes the residual here (its least
    // squares mix directions at round-off once the early steps were large). The next step is a
    // plain chord step, and the history starts again (measured: a stall at 1e-8 of the load
    // became convergence in two steps).
    const bool restart = it > 0 && size > last_size;
    last_size = size;
    if (restart) {
      dd.resize(nf_, 0);
      dx.resize(nf_, 0);
    }
    const Eigen::VectorXd x = free_part(u);
    if (it > 0 && !restart) {
      if (dd.cols() == kAndersonDepth) {  // the oldest difference leaves the history
        dd = dd.rightCols(kAndersonDepth - 1).eval();
        dx = dx.rightCols(kAndersonDepth - 1).eval();
      }
      dd.conservativeResize(Eigen::NoChange, dd.cols() + 1);
      dx.conservativeResize(Eigen::NoChange, dx.cols() + 1);
      dd.rightCols(1) = d - d_last;
      dx.rightCols(1) = x - x_last;
    }
    Eigen::VectorXd next = x + d;
    if (dd.cols() > 0) next -= (dx + dd) * dd.colPivHouseholderQr().solve(d);
    d_last = d;
    x_last = x;
    for (int k = 0; k < nf_; ++k) u[m_.free_dofs_[static_cast<size_t>(k)]] = next[k];
  }
  u = best;
  return false;
}

// Newton from the start at full load, else from rest in 1, 2, 4, ... equal load steps. The
// ladder stops once the first step from rest fails at kSmallestFirstStep of the load or less:
// near rest the response is close to the linear one, where Newton's first iterate (the linear
// solution) is already close, so a model that cannot carry that fraction of the load will not
// carry the whole load in more, smaller steps either (a stiffness that is not positive definite,
// a support too soft for the load); each further rung would only repeat up to kMaxIterations
// tangents per step before failing the same way.
// No ladder at all when Newton started from this model's own last equilibrium (`own_start`): the
// evaluation is then a fit's trial step away from parameters where the model converged, and its
// failure says the step was too long; the fit rejects it and tries a shorter one (the cost
// function's failure shrinks the trust region), which Newton from the same equilibrium can
// follow. On the suite's cantilever at nu = 0.49 (8,019 DOFs) a tangent costs 1.8 CPU s, and a
// ladder that fails runs up to 30 of them per attempt.
bool ForwardModel::NonlinearEvaluation::solve_equilibrium(size_t lc, Eigen::VectorXd& u,
                                                          KeptTangent& solver, bool& factorised,
                                                          const KeptTangent* borrowed,
                                                          bool own_start, Parts& parts) {
  const Eigen::VectorXd& force = forces_[lc];
  bool converged =
      u.size() == m_.num_dofs_ && newton(lc, force, 1.0, u, solver, factorised, borrowed, parts);
  if (own_start) return converged;
  for (int steps = 1; steps <= kMaxSteps && !converged; steps *= 2) {
    u = Eigen::VectorXd::Zero(m_.num_dofs_);
    bool first_step_failed = false;
    converged = true;
    for (int k = 1; k <= steps && converged; ++k) {
      converged =
          newton(lc, force, static_cast<double>(k) / steps, u, solver, factorised, nullptr, parts);
      first_step_failed = !converged && k == 1;
    }
    if (first_step_failed && steps * kSmallestFirstStep >= 1.0) break;
  }
  return converged;
}

// What the next evaluations start from: this load case's solution and its tangent.
void ForwardModel::NonlinearEvaluation::remember(size_t lc, const Eigen::VectorXd& u,
                                                 bool converged, bool factorised) {
  cache_.factorised[lc] = factorised ? 1 : 0;
  if (converged) {
    shared_.nonlinear_starts[lc] = u;
    shared_.linear_starts[lc] = u_linear_[lc];
  }
  if (factorised) shared_.keep_tangent(lc, cache_.tangent_solvers[lc]);
}

// A tangent factorised for this evaluation's matrix (tangent_key_) at a displacement that is an
// equilibrium of load case lc here (the one convergence test of every solve): this model's own
// last one, else one the cache kept. Its u is then the solution, as good as Newton's own (both
// pass the same test), and the tangent is exact there, so the Jacobian is the one Newton and a
// new factorisation would give at that u. Writes u and the nonlinear parts at u; null when none.
std::shared_ptr<KeptTangent> ForwardModel::NonlinearEvaluation::kept_equilibrium(
    size_t lc, Eigen::VectorXd& u, Parts& parts) const {
  std::vector<std::shared_ptr<KeptTangent>> candidates = {cache_.tangent_solvers[lc]};
  candidates.insert(candidates.end(), shared_.tangents[lc].begin(), shared_.tangents[lc].end());
  Eigen::VectorXd r_free;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const std::shared_ptr<KeptTangent>& kept = candidates[k];
    if (k > 0 && kept == candidates[0]) continue;  // this model's own, tried first
    if (!kept || !kept->holds(tangent_key_, tangent_terms_, m_.free_dofs_) ||
        kept->u.size() != m_.num_dofs_)
      continue;
    bool supported_alike = true;  // the prescribed values are this model's
    for (int d = 0; d < m_.num_dofs_ && supported_alike; ++d)
      if (m_.free_index_[static_cast<size_t>(d)] < 0 && kept->u[d] != m_.prescribed_[d])
        supported_alike = false;
    if (supported_alike &&
        free_residual(forces_[lc], 1.0, kept->u, internal_force(kept->u, parts, nullptr), r_free)) {
      u = kept->u;
      return kept;
    }
  }
  return nullptr;
}

// The prediction at the converged u (blended with the linear one) and its Jacobian.
void ForwardModel::NonlinearEvaluation::predict(size_t lc, Eigen::VectorXd u, const Parts& parts,
                                                const KeptTangent& solver,
                                                ModelEvaluation& out) const {
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& h = m_.observations_[lc].operator_;
  Eigen::MatrixXd jac;
  if (with_jacobian_) {
    Eigen::MatrixXd du;
    if (need_tangent_) {
      // dR/dtheta at fixed u: the linear terms' dK/dtheta u and the nonlinear parts n_k(u) de_k
      // (`parts` hold n_k at the converged u: Newton's last evaluation).
      Eigen::MatrixXd rhs = linear_rhs(dforces_[lc], u);
      for (size_t t = 0; t < m_.terms_.nonlinear.size(); ++t)
        for (size_t k = 0; k < parts[t].size(); ++k) rhs -= parts[t][k] * de_[t][k].transpose();
      du = solve_free(solver, rhs);
    }
    if (w_index_ >= 0) {
      du = need_tangent_ ? Eigen::MatrixXd(w_ * du + (1.0 - w_) * du_linear_[lc]) : du_linear_[lc];
      du.col(w_index_) += u - u_linear_[lc];
    }
    jac = h * du;
  }
  if (w_index_ >= 0) u = w_ * u + (1.0 - w_) * u_linear_[lc];
  Eigen::VectorXd y = h * u;
  const int l = static_cast<int>(lc);
  m_.add_offsets(l, theta_, with_jacobian_, y, jac);
  out.predictions[lc] = std::move(y);
  out.jacobians[lc] = std::move(jac);
  out.displacements[lc] = std::move(u);
}

// At w = 0 the blend's prediction is the linear one; its derivative in w is u_nl - u_lin, which
// needs a Newton solve per load case. To first order in the nonlinearity it is the solution of
// K v = -sum_k e_k n_k(u_lin): one evaluation of the nonlinear force at the linear solution and
// one back-substitution with the linear factor that the linear solution used (v vanishes on the
// supports: u_nl and u_lin share their prescribed values).
ModelEvaluation ForwardModel::NonlinearEvaluation::linearised_at_zero_weight(double* series) const {
  double first_norm = 0.0, second_norm = 0.0;
  ModelEvaluation out;
  out.predictions.resize(nls_), out.jacobians.resize(nls_), out.displacements.resize(nls_);
  for (size_t lc = 0; lc < nls_; ++lc) {
    const Eigen::VectorXd& u = u_linear_[lc];
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& h = m_.observations_[lc].operator_;
    Eigen::MatrixXd jac;
    if (with_jacobian_) {
      Eigen::VectorXd nonlinear_force = Eigen::VectorXd::Zero(m_.num_dofs_);
      for (size_t t = 0; t < m_.terms_.nonlinear.size(); ++t) {
        std::vector<Eigen::VectorXd> parts;
        m_.terms_.nonlinear[t].evaluate(u, e_[t], parts, nullptr);
        for (size_t k = 0; k < parts.size(); ++k) nonlinear_force += e_[t][k] * parts[k];
      }
      Eigen::MatrixXd du = du_linear_[lc];  // its column w is zero: u_lin does not depend on w
      du.col(w_index_) = -solve_free(linear_solver_, nonlinear_force).col(0);
      jac = h * du;
      if (series) {
        const Eigen::VectorXd second = second_order_term(u, du.col(w_index_));
        first_norm += (h * du.col(w_index_)).squaredNorm();
        second_norm += (h * second).squaredNorm();
      }
    }
    Eigen::VectorXd y = h * u;
    m_.add_offsets(static_cast<int>(lc), theta_, with_jacobian_, y, jac);
    out.predictions[lc] = std::move(y);
    out.jacobians[lc] = std::move(jac);
    out.displacements[lc] = u;
  }
  if (series) *series = first_norm > 0.0 ? std::sqrt(second_norm / first_norm) : 0.0;
  return out;
}

// The switched-on model's solution is a series in w, u(w) = u_lin + w v + w^2 v_2 + ..., and
// the blend's column is its sum at w = 1. Its second term: differentiating
// K u' + n(u) + w Dn(u) u' = 0 once more at w = 0 gives K v_2 = -Dn(u_lin) v. The directional
// derivative Dn(u_lin) v is a central difference of the nonlinear force (a polynomial of degree
// 3 in u: the difference's error is its cubic part times eps^2, with eps = 1e-3 |u| / |v|), so
// no tangent is assembled.
Eigen::VectorXd ForwardModel::NonlinearEvaluation::second_order_term(
    const Eigen::VectorXd& u, const Eigen::VectorXd& v) const {
  const double v_norm = v.norm();
  if (!(v_norm > 0.0)) return Eigen::VectorXd::Zero(u.size());
  const double eps = 1e-3 * std::max(u.norm(), v_norm) / v_norm;
  auto nonlinear_force = [&](const Eigen::VectorXd& at) {
    Eigen::VectorXd force = Eigen::VectorXd::Zero(m_.num_dofs_);
    for (size_t t = 0; t < m_.terms_.nonlinear.size(); ++t) {
      std::vector<Eigen::VectorXd> parts;
      m_.terms_.nonlinear[t].evaluate(at, e_[t], parts, nullptr);
      for (size_t k = 0; k < parts.size(); ++k) force += e_[t][k] * parts[k];
    }
    return force;
  };
  const Eigen::VectorXd directional =
      (nonlinear_force(u + eps * v) - nonlinear_force(u - eps * v)) / (2.0 * eps);
  return -solve_free(linear_solver_, directional).col(0);
}

ModelEvaluation ForwardModel::evaluate_nonlinear(const Eigen::VectorXd& theta, bool with_jacobian,
                                                 bool linearised, double* series) const {
  if (!nonlinear_cache_) throw std::logic_error("ForwardModel: nonlinear cache missing");
  const std::lock_guard<std::mutex> solver_lock(nonlinear_cache_->solver_mutex);
  const std::lock_guard<std::mutex> shared_lock(linear_cache_->nonlinear_mutex);
  return NonlinearEvaluation(*this, theta, with_jacobian, linearised, series).run();
}

ModelEvaluation ForwardModel::evaluate_linearised(const Eigen::VectorXd& theta,
                                                  double* second_order_ratio) const {
  if (terms_.nonlinear.empty() || terms_.nonlinear_weight < 0)
    throw std::logic_error("ForwardModel::evaluate_linearised: the model has no blend weight");
  return evaluate_nonlinear(theta, true, true, second_order_ratio);
}

}  // namespace isospring::fitting
