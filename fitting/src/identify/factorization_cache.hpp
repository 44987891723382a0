#pragma once
// FactorizationCache (declared in isospring/fitting/identify_model.hpp): what the forward models
// of one identification share, the last factorisation of K_ff and the last large-deformation
// solutions. Private to the fitting module: the linear (identify_model.cpp) and the nonlinear
// (identify_model_nonlinear.cpp) evaluations both use it.
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "isospring/analysis/tangent_solver.hpp"
#include "isospring/fitting/identify_model.hpp"

namespace isospring::fitting {

// CHOLMOD's supernodal LL^T that can become an independent copy of another one's analysis and
// factor (cholmod_copy_factor): a copy costs a memory copy of L, a factorisation of the same
// matrix its flops (the hold-out folds start from the loop's factor).
class CopyableCholmod
    : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> {
 public:
  CopyableCholmod() { this->cholmod().print = 0; }  // a failed trial step is the caller's to handle
  // This solver as `other`'s copy; false (this one unchanged) when CHOLMOD could not copy.
  bool copy_from(const CopyableCholmod& other) {
    if (!other.m_cholmodFactor) return false;
    cholmod_factor* copy = cholmod_copy_factor(other.m_cholmodFactor, &this->cholmod());
    if (!copy) return false;
    if (this->m_cholmodFactor) cholmod_free_factor(&this->m_cholmodFactor, &this->cholmod());
    this->m_cholmodFactor = copy;
    this->m_info = other.m_info;
    this->m_analysisIsOk = other.m_analysisIsOk;
    this->m_factorizationIsOk = other.m_factorizationIsOk;
    this->m_isInitialized = other.m_isInitialized;
    this->m_shiftOffset[0] = other.m_shiftOffset[0];
    this->m_shiftOffset[1] = other.m_shiftOffset[1];
    return true;
  }
};

// A factorisation of a large-deformation model's tangent for one load case (or of its linear
// stiffness, the tangent at u = 0), and the state it was factorised at: which matrix (`key`: the
// stiffness terms with a non-zero coefficient and their coefficients, then the nonlinear terms'
// coefficients; `terms`: which nonlinear terms; the free DOFs) at which displacement `u`. An
// evaluation that needs the tangent at an equilibrium of the same matrix solves with this one
// instead of assembling and factorising it again (about 1 CPU s per load case at 8,019 DOFs): a
// refit's first Jacobian at the parameters of the loop's last one (every hold-out fold), a
// covariance at a fit's last point, a candidate whose neutral values leave the stiffness and the
// equilibrium as they were (a later round's score tests of gravity, a load factor, a rigid
// motion or a stiffness gradient).
struct KeptTangent {
  analysis::TangentSolver solver;
  // The matrix solved is `scale` times the factorised one (the linear stiffness after a change
  // of E alone); 1 for tangents.
  double scale = 1.0;
  bool has_state = false;  // `solver` holds the factor of the matrix `key` names, at `u`
  std::vector<double> key;
  std::vector<const void*> terms;
  std::vector<int> free_dofs;
  Eigen::VectorXd u;

  // Solves one at a time: the hold-out folds share the loop's tangents and run side by side,
  // and a factor's solves share CHOLMOD's workspace.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const {
    const std::lock_guard<std::mutex> lock(mutex);
    Eigen::MatrixXd x = solver.solve(rhs);
    if (scale != 1.0) x /= scale;
    return x;
  }
  // Whether this holds the factor of the matrix (key, terms, free_dofs).
  bool holds(const std::vector<double>& k, const std::vector<const void*>& t,
             const std::vector<int>& dofs) const {
    return has_state && key == k && terms == t && free_dofs == dofs;
  }

 private:
  mutable std::mutex mutex;
};

// How many factorised tangents a cache keeps per load case for the state lookup: the current
// model's, and one more (a later round's score tests meet the current model's state again after
// a candidate with other free DOFs, a compliant support, factorised its own).
inline constexpr size_t kKeptTangents = 2;

struct FactorizationCache {
  std::mutex mutex;  // evaluate() is const and may be called from several threads
  // The symbolic analysis (fill-reducing ordering, supernodes) depends on K_ff's pattern only:
  // it is kept for the pattern it was made for and every factorisation of that pattern reuses it.
  std::unique_ptr<CopyableCholmod> cholesky;
  std::vector<int> analysed_outer, analysed_inner;  // the pattern `cholesky` was analysed for
  bool factorized = false;  // `cholesky` holds the factor of `coefficients` (else analysis only)
  std::vector<double> fingerprint;   // of the factorised model's terms and free DOFs
  std::vector<double> coefficients;  // of the factorised K_ff
  // W = K_c^-1 U and G = U^T W for the model's local DOFs B (U: the columns of the identity at
  // B); computed on the first low-rank solve after each factorisation.
  Eigen::MatrixXd w, g;
  bool low_rank_ready = false;
  FactorizationStats stats;
  // What the large-deformation evaluations of the cache's models share, per load case; a
  // nonlinear evaluation holds nonlinear_mutex throughout. A new model's first evaluation starts
  // Newton from the last converged solution (whichever model found it; moved by the change of
  // the linear solution) and, while it has no tangent of its own, takes its chord steps on the
  // last factorised tangent of a model with the same free DOFs. The models of one
  // identification differ by an effect or by which markers count, so both are usually close to
  // their own: from zero, with chords on the linear stiffness, a new model needed up to 7
  // tangents per load case (each 1.25 s on the suite's tube at 5,832 DOFs).
  std::mutex nonlinear_mutex;
  std::vector<Eigen::VectorXd> nonlinear_starts;
  std::vector<Eigen::VectorXd> linear_starts;  // the linear solutions at the same parameters
  // Per load case, the last kKeptTangents factorised or used tangents, most recent first (the
  // first is the one a new model borrows for its chord steps).
  std::vector<std::vector<std::shared_ptr<KeptTangent>>> tangents;
  // Load-case solves that started on another model's tangent (Anderson-accelerated chord steps
  // from its solution), and those of them that converged there without a tangent of their own;
  // tangents factorised, and Jacobians solved on a kept tangent at its own state instead: what
  // tests and profiles read. Load cases run concurrently, hence atomic.
  std::atomic<long> kept_tangent_starts{0}, kept_tangent_converged{0};
  std::atomic<long> tangent_factorizations{0}, kept_state_reuses{0};
  // Factorisations of the linear K_ff of the large-deformation blend (its u_lin).
  std::atomic<long> blend_factorizations{0};
  // Jacobians of the cache's large-deformation models solve on the tangent at hand (the model's
  // last one, else the one it borrowed for its chord steps) instead of one factorised at the
  // solution: the hold-out folds' refits (fold_cache), which start at the loop's fit and move by
  // about a standard error, where the tangent changes by about the relative change of E. A
  // Gauss-Newton refit with such a Jacobian J_k ends where J_k^T r = 0, within that relative
  // change (times the residual's projection, of order one standard error) of where exact
  // Jacobians end; the folds only predict the markers they hold out. Counted per load case.
  bool jacobians_on_kept_tangents = false;
  std::atomic<long> jacobians_on_kept_tangent{0};

  // Load case lc's `tangent` as the most recent, the oldest beyond kKeptTangents dropped.
  void keep_tangent(size_t lc, const std::shared_ptr<KeptTangent>& tangent) {
    auto& list = tangents[lc];
    list.erase(std::remove(list.begin(), list.end(), tangent), list.end());
    list.insert(list.begin(), tangent);
    if (list.size() > kKeptTangents) list.resize(kKeptTangents);
  }

  // Factorises `kff` (numerically only when its pattern is the analysed one); false when it is
  // not positive definite.
  bool factorize(const Eigen::SparseMatrix<double>& kff) {
    factorized = false;
    const auto n = static_cast<size_t>(kff.outerSize());
    const auto nnz = static_cast<size_t>(kff.nonZeros());
    const bool same_pattern =
        cholesky && analysed_outer.size() == n + 1 && analysed_inner.size() == nnz &&
        std::equal(analysed_outer.begin(), analysed_outer.end(), kff.outerIndexPtr()) &&
        std::equal(analysed_inner.begin(), analysed_inner.end(), kff.innerIndexPtr());
    if (!same_pattern) {
      cholesky = std::make_unique<CopyableCholmod>();
      cholesky->analyzePattern(kff);
      analysed_outer.assign(kff.outerIndexPtr(), kff.outerIndexPtr() + n + 1);
      analysed_inner.assign(kff.innerIndexPtr(), kff.innerIndexPtr() + nnz);
      ++stats.analyses;
    }
    cholesky->factorize(kff);
    if (cholesky->info() != Eigen::Success) return false;
    factorized = true;
    ++stats.factorizations;
    return true;
  }

  // This cache's linear state as an independent copy of `other`'s: its analysis, its factor
  // (with the coefficients and fingerprint it was made for) and the low-rank solve's W and G.
  // The caller holds other.mutex. Nothing is copied when `other` has no factor; a copy that
  // fails (memory) leaves this cache as it was, to factorise on its own.
  void copy_factorization(const FactorizationCache& other) {
    if (!(other.factorized && other.cholesky)) return;
    // Everything that allocates first: a failure (std::bad_alloc) leaves this cache unchanged.
    auto copy = std::make_unique<CopyableCholmod>();
    if (!copy->copy_from(*other.cholesky)) return;
    std::vector<int> outer = other.analysed_outer, inner = other.analysed_inner;
    std::vector<double> copied_fingerprint = other.fingerprint,
                        copied_coefficients = other.coefficients;
    Eigen::MatrixXd copied_w = other.w, copied_g = other.g;
    cholesky = std::move(copy);
    analysed_outer = std::move(outer);
    analysed_inner = std::move(inner);
    factorized = true;
    fingerprint = std::move(copied_fingerprint);
    coefficients = std::move(copied_coefficients);
    w = std::move(copied_w);
    g = std::move(copied_g);
    low_rank_ready = other.low_rank_ready;
  }

  // s with c_j = s * coefficients_j to 1e-13 of c_j for every term with local[j] false (all
  // terms when local is empty), or 0 when there is no such s. One scale for every term, each to
  // 1e-13 of itself: a term far stiffer than the others (a support spring of 1e12 against
  // E = 1e9) must not hide a change in the others, which a badly conditioned K would amplify.
  double scale_to(const std::vector<double>& model_fingerprint, const std::vector<double>& c,
                  const std::vector<bool>& local) const {
    if (!factorized || model_fingerprint != fingerprint || c.size() != coefficients.size())
      return 0.0;
    auto global = [&](size_t j) { return local.empty() || !local[j]; };
    double s = 0.0;
    for (size_t j = 0; j < c.size(); ++j)
      if (global(j) && coefficients[j] != 0.0) {
        s = c[j] / coefficients[j];
        break;
      }
    if (!(s > 0.0)) return 0.0;
    for (size_t j = 0; j < c.size(); ++j)
      if (global(j) && std::abs(c[j] - s * coefficients[j]) > 1e-13 * std::abs(c[j])) return 0.0;
    return s;
  }
};

}  // namespace isospring::fitting
