#pragma once
// The forward model of the identification: marker displacements as a function of parameters,
// with exact first derivatives.
//
//   K(theta) = sum_j c_j(theta) K_j            (stiffness terms)
//   f_l(theta) = sum_j d_j(theta) f_j           (load terms of load case l)
//   u_l = K^-1 f_l on the free DOFs (supports prescribed), y_l = H_l u_l + sum_j o_j(theta) g_j
//   du_l/dtheta = K^-1 (df_l/dtheta - dK/dtheta u_l)      (one factorisation per theta)
//
// where H_l evaluates the NURBS displacement at the load case's markers and g_j are offsets in
// observation space (rigid motions of the measuring frame). The coefficients are scalar functions
// of theta with their gradients; effects (effect.hpp) contribute terms.
//
// Nonlinear terms (geometric nonlinearity) add internal forces of higher order in u:
//   K(theta) u + sum_k e_k(theta) n_k(u) = f_l(theta),   n_k(u) = O(|u|^2)
// solved by Newton from the linear solution (load stepping when that fails), and
//   du_l/dtheta = K_T^-1 (df_l/dtheta - dK/dtheta u_l - sum_k n_k(u_l) de_k/dtheta)
// with the tangent K_T = K + sum_k e_k dn_k/du at the converged state
// (identify_model_nonlinear.cpp).
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <functional>
#include <memory>
#include <vector>

namespace isospring::fitting {

/// A scalar coefficient of theta: returns the value and writes the gradient (sized like theta).
using Coefficient = std::function<double(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient)>;

/// c(theta) = theta[index] (gradient e_index) times `scale`.
Coefficient linear_coefficient(int index, double scale = 1.0);
/// c(theta) = value.
Coefficient constant_coefficient(double value);
/// c(theta) = a(theta) * b(theta).
Coefficient product(Coefficient a, Coefficient b);

struct MatrixTerm {
  Eigen::SparseMatrix<double> matrix;  // full symmetric, over all DOFs
  Coefficient coefficient;
};

struct VectorTerm {
  int load_case = -1;  // -1: every load case
  Eigen::VectorXd vector;
  Coefficient coefficient;
};

/// Internal force beyond the linear stiffness terms: sum_k coefficients[k](theta) n_k(u).
/// evaluate(u, e, parts, tangent) sets parts[k] = n_k(u) (all DOFs) and, when `tangent` is not
/// null, *tangent = sum_k e[k] dn_k/du (symmetric, all DOFs; only its upper triangle is read, so
/// it may hold that alone), e the coefficients' values.
struct NonlinearTerm {
  std::vector<Coefficient> coefficients;
  std::function<void(const Eigen::VectorXd& u, const std::vector<double>& e,
                     std::vector<Eigen::VectorXd>& parts, Eigen::SparseMatrix<double>* tangent)>
      evaluate;
  /// Threads the model may solve its load cases on, one Newton solve each (evaluate is then
  /// called from several threads at once, and runs its own element loops serially there).
  int threads = 1;
  /// What n_k are: terms with the same non-null identity compute the same n_k, so that models
  /// sharing a cache can tell that their tangents are the same matrix (and one model's
  /// factorised tangent serves another's Jacobian). Null: a model's tangents are its own.
  const void* identity = nullptr;
};

struct ModelTerms {
  int num_parameters = 0;
  std::vector<MatrixTerm> stiffness;
  std::vector<VectorTerm> loads;         // DOF space
  std::vector<VectorTerm> offsets;       // observation space of the load case
  std::vector<int> released_dofs;        // supported DOFs an effect frees (replaced by springs)
  std::vector<NonlinearTerm> nonlinear;  // empty: the linear model
  int nonlinear_weight = -1;  // theta index of w in u = (1 - w) u_lin + w u_nl; -1: w = 1
};

/// One load case's observations: y = H u (+ offsets), H is (markers * components) x DOFs.
struct Observation {
  Eigen::SparseMatrix<double, Eigen::RowMajor> operator_;
};

struct ModelEvaluation {
  std::vector<Eigen::VectorXd> predictions;    // per load case, observation space
  std::vector<Eigen::MatrixXd> jacobians;      // per load case, observations x parameters
  std::vector<Eigen::VectorXd> displacements;  // per load case, all DOFs
};

/// The last factorisation of a linear model's K_ff (and the last large-deformation solution per
/// load case, the Newton start of a new model), shareable between forward models: the
/// candidate models of one identification differ in loads and offsets far more often than in
/// their stiffness, and a model whose stiffness terms, free DOFs and coefficients (up to a common
/// scale) match the cached ones solves with it instead of factorising again. When only the
/// coefficients of terms confined to a few DOFs B differ (support springs: |B| a few hundred
/// against thousands of free DOFs), K = s (K_cached + U C U^T) with U selecting B, and solves use
/// the Woodbury identity (K_c + U C U^T)^-1 = K_c^-1 - W C (I + G C)^-1 U^T K_c^-1, with
/// W = K_c^-1 U and G = U^T W computed once per factorisation (|B| solves).
struct FactorizationCache;
std::shared_ptr<FactorizationCache> make_factorization_cache();
/// A new cache whose factorisation is an independent copy of `cache`'s (CHOLMOD's analysis and
/// factor, the low-rank solve's W and G): its models solve without factorising the same K again.
std::shared_ptr<FactorizationCache> copy_factorization_cache(FactorizationCache& cache);

/// What a cache did so far: for benchmarks, tests and the report's timing notes.
struct FactorizationStats {
  long factorizations = 0;    // sparse Cholesky factorisations
  long reuses = 0;            // solves with the cached factor as it is (scaled)
  long low_rank_updates = 0;  // solves through a Woodbury update of the cached factor
  long analyses = 0;          // symbolic analyses (orderings): one per pattern of K_ff
};
FactorizationStats factorization_stats(const FactorizationCache& cache);

class ForwardModel {
 public:
  /// `constrained_dofs`/`constrained_values`: the supports (analysis::build_constraints).
  /// `cache`: shared with other models (make_factorization_cache); null: a cache of its own.
  ForwardModel(ModelTerms terms, std::vector<Observation> observations,
               const std::vector<int>& constrained_dofs,
               const std::vector<double>& constrained_values, int num_dofs, int num_load_cases,
               std::shared_ptr<FactorizationCache> cache = nullptr);

  int num_parameters() const { return terms_.num_parameters; }
  /// Whether the model has nonlinear terms (each evaluation is a Newton solve).
  bool nonlinear() const { return !terms_.nonlinear.empty(); }
  /// The counts of the (possibly shared) cache this model solves with.
  FactorizationStats factorization_stats() const;
  /// Predictions (and Jacobians when `with_jacobian`) at theta. Throws std::runtime_error when
  /// K(theta) is not positive definite (parameters outside the physical range) or, with nonlinear
  /// terms, when Newton does not converge.
  ModelEvaluation evaluate(const Eigen::VectorXd& theta, bool with_jacobian) const;
  /// The screen of a blended large-deformation model (ModelTerms::nonlinear_weight) at w = 0,
  /// without Newton: the linear predictions and their exact Jacobian in every parameter but w,
  /// and for w the first-order change dy/dw = -H K^-1 sum_k e_k n_k(u_lin), one back-substitution
  /// per load case with the linear factor. It is the exact derivative at w = 0 of the model
  /// K u + w sum_k e_k n_k(u) = f (the nonlinear force switched on gradually), and differs from
  /// the blend's u_nl - u_lin = -K^-1 sum_k e_k n_k(u_nl) by n_k(u_nl) - n_k(u_lin), of third
  /// order in the displacement. That difference is small only while the series of the
  /// switched-on model's solution in w converges fast at w = 1, which a slender body in bending
  /// leaves already at small rotations (the linear solution's spurious stretching makes
  /// n_k(u_lin) large). `second_order_ratio` (when not null) receives the ratio of that series'
  /// second term, -H K^-1 Dn(u_lin) v, to its first, H v, over all load cases (observation-space
  /// norms): the column is trustworthy only where it is small. Throws std::logic_error without a
  /// blend weight or at w != 0.
  ModelEvaluation evaluate_linearised(const Eigen::VectorXd& theta,
                                      double* second_order_ratio = nullptr) const;

 private:
  // Load case l's nodal force at theta and, when with_jacobian, its derivative (columns: the
  // parameters); shared by the linear and the nonlinear evaluation.
  void load_vector(int l, const Eigen::VectorXd& theta, bool with_jacobian, Eigen::VectorXd& force,
                   Eigen::MatrixXd& dforce) const;
  // Adds load case l's observation offsets (e.g. a rigid motion of the measurement frame) to the
  // predictions y and, when with_jacobian, their derivatives to jac.
  void add_offsets(int l, const Eigen::VectorXd& theta, bool with_jacobian, Eigen::VectorXd& y,
                   Eigen::MatrixXd& jac) const;
  // evaluate() with nonlinear terms (identify_model_nonlinear.cpp), whose stages are those of
  // a NonlinearEvaluation.
  ModelEvaluation observe(const Eigen::MatrixXd& displacements,
                          const Eigen::MatrixXd& derivatives_free, const Eigen::VectorXd& theta,
                          bool with_jacobian) const;
  ModelEvaluation evaluate_nonlinear(const Eigen::VectorXd& theta, bool with_jacobian,
                                     bool linearised = false, double* series = nullptr) const;
  class NonlinearEvaluation;
  // The last converged nonlinear solution per load case: Newton's start at the next theta (a
  // least-squares solver evaluates nearby parameters, often the same ones twice).
  struct NonlinearCache;
  static std::shared_ptr<NonlinearCache> make_nonlinear_cache();
  std::shared_ptr<NonlinearCache> nonlinear_cache_;
  // The last factorisation of the linear K_ff: a least-squares solver evaluates many theta that
  // only change E (every stiffness coefficient scaled alike, K = s K_cached) or only loads and
  // offsets (gravity, load factors, rigid motions), which need no new factorisation.
  std::shared_ptr<FactorizationCache> linear_cache_;
  std::vector<double> fingerprint_;  // identifies the stiffness terms and free DOFs in the cache

  ModelTerms terms_;
  std::vector<Observation> observations_;
  int num_dofs_ = 0;
  int num_load_cases_ = 0;
  std::vector<int> free_index_;  // DOF -> free index or -1
  std::vector<int> free_dofs_;
  Eigen::VectorXd prescribed_;
  std::vector<Eigen::SparseMatrix<double>> free_blocks_;  // upper triangles of K_j,ff
  // The union of the free blocks' patterns (values unused), and for each term the position in
  // it of each stored entry: K_ff(theta) is a linear combination of value arrays, and CHOLMOD's
  // symbolic analysis of the pattern serves every theta. Made on the model's first
  // factorisation (under the cache's lock): models that only reuse the cache never need it.
  void make_pattern() const;
  mutable bool pattern_ready_ = false;
  mutable Eigen::SparseMatrix<double> pattern_;
  mutable std::vector<std::vector<int>> positions_;
  // Terms confined to a few free DOFs (support springs): a change of their coefficients alone is
  // a low-rank update of the cached factorisation (Woodbury) instead of a new one.
  std::vector<bool> local_term_;
  std::vector<int> local_dofs_;                // free indices touched by local terms
  std::vector<Eigen::MatrixXd> local_blocks_;  // K_j restricted to local_dofs_ (full)
};

}  // namespace isospring::fitting
