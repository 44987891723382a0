#pragma once
// The NMSM response of the displacement objective, u_c(k) = K(k)^-1 f_c, prepared once per fit.
//
// Everything that does not depend on the stiffnesses is computed in the constructor: the free
// DOFs, K's sparsity pattern (upper triangle, free DOFs), every spring's scatter positions and
// coefficients n_a n_b in that pattern, and CHOLMOD's symbolic analysis (fill-reducing ordering,
// supernodes). An evaluation then only scatters k (O(springs)), factorises numerically and
// solves. Before this, every evaluation copied the network, assembled K from triplets and redid
// the AMD ordering: ~60% of a grouped fit's time was ordering and simplicial factorisation.
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/Sparse>
#include <vector>

#include "isospring/analysis/spring_static.hpp"
#include "isospring/fitting/displacement_fit.hpp"

namespace isospring::fitting::detail {

// CHOLMOD's supernodal LL^T and the pivot ratio of its factor, (min L_ii / max L_ii)^2
// (cholmod_rcond): the ratio of the smallest to the largest pivot that the spring solves
// (analysis/src/spring_static.cpp) take as singular below 1e-13.
class PivotCheckedCholmod
    : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> {
 public:
  double pivot_ratio() { return cholmod_rcond(this->m_cholmodFactor, &this->cholmod()); }
};

class DisplacementModel {
 public:
  /// Throws nurbs::InputError when the data or grouping are inconsistent.
  DisplacementModel(const DisplacementFitData& data, const Grouping& grouping);
  DisplacementModel(const DisplacementModel&) = delete;
  DisplacementModel& operator=(const DisplacementModel&) = delete;

  int num_residuals() const { return static_cast<int>(scale_.size()) * rows_per_case_; }
  int num_parameters() const { return groups_; }

  /// Residuals (and, when `jacobian` is not null, d residuals / d theta) at theta, k_g =
  /// exp(theta_g). Returns false, leaving the outputs unspecified, when a stiffness or a
  /// displacement is not finite or K(k) is not positive definite: the caller (Ceres or the dual
  /// LM) treats that as a failed trial step and retries a shorter one.
  bool evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                Eigen::MatrixXd* jacobian);

  /// J W J^T (W = diag(weight), one weight per parameter) at the point of the last evaluation
  /// with a Jacobian through the adjoint form (many parameters), from K^-1 and a sparse spring
  /// matrix instead of the dense J. Only for one spring per parameter; false otherwise (or when
  /// no such evaluation happened), then the caller forms J W J^T itself.
  bool gram(const Eigen::VectorXd& weight, Eigen::MatrixXd& result);

  /// The dual LM system in K form, for the last evaluation with a Jacobian in the adjoint form
  /// when it had one load case, one spring per parameter and `rows` (the residual rows the LM
  /// keeps) observe every free DOF exactly once (P: that row -> free DOF permutation). Then
  /// a I + J W J^T = K_r^-1 (a K_r^2 + G_r) K_r^-1 with K_r = P K P^T and G_r = s^2 P B W B^T
  /// P^T (B W B^T: the spring matrix of gram()), so the LM factorises a K_r^2 + G_r and needs no
  /// K^-1 G K^-1 (a solve with one right-hand side per free DOF). Fills the dense K_r, K_r^2 and
  /// G_r; false when the conditions do not hold (the caller then uses gram()).
  bool dual_k_form(const Eigen::VectorXd& weight, const std::vector<Eigen::Index>& rows,
                   Eigen::MatrixXd& k, Eigen::MatrixXd& k_squared, Eigen::MatrixXd& g) const;

  /// scale_c u_ref,c for every residual row: residuals = scale_c u_c - scaled_reference().
  const Eigen::VectorXd& scaled_reference() const { return scaled_reference_; }

  /// Percent errors of the last successful evaluation per case: 100 * |u_a - u_ref,a| / o_max for
  /// every node, maximised (the %e_max of the control points).
  std::vector<double> percent_e_max(const Eigen::VectorXd& residuals) const;

 private:
  int num_elements() const { return static_cast<int>(group_of_element_.size()); }
  /// Whether elements e and f have the same free DOFs in the same order.
  bool same_dofs(int e, int f) const;
  /// K's pattern (k_) and the scatter of every element into it (begin_ ... term_coefficient_).
  void build_scatter();

  struct SpringData {
    Eigen::Vector3d n;         // unit rest direction
    int free_i[3], free_j[3];  // free indices of the two particles' components, -1 when held
  };
  std::vector<SpringData> springs_;  // the first elements are the springs

  // Rank-one stiffness elements (springs, then volume terms): K_e = k_e g_e g_e^T with g_e's
  // entries [entry_begin_[e], entry_begin_[e + 1]) of entry_free_ (free index) and entry_value_.
  std::vector<int> group_of_element_;
  std::vector<int> entry_begin_, entry_free_;
  std::vector<double> entry_value_;
  int dim_ = 3;
  int groups_ = 0;
  int rows_per_case_ = 0;
  analysis::FreeDofSet dofs_;
  std::vector<int> row_free_;          // residual row within a case -> free index, -1 when held
  std::vector<double> scale_;          // per case: 1 / (o_max sqrt(n))
  std::vector<Eigen::VectorXd> load_;  // per case, on the free DOFs
  Eigen::VectorXd scaled_reference_;
  // Elements [0, merged_begin_): springs and cell terms, scattered one by one; the rest are
  // strain-point elements, scattered summed per group.
  int merged_begin_ = 0;
  // Scatter of element s < merged_begin_: entries [begin_[s], begin_[s + 1]) of slot_ (position
  // in the value array of k_) and coefficient_ (g_a g_b).
  std::vector<int> begin_, slot_;
  std::vector<double> coefficient_;
  // Scatter of the strain-point elements, summed per group and slot: K[term_slot_[i]] +=
  // k[term_group_[i]] term_coefficient_[i] (K_g's upper triangle, at term_row_, term_col_).
  std::vector<int> term_slot_, term_row_, term_col_, term_group_;  // row <= col (free indices)
  std::vector<double> term_coefficient_;
  bool merged_jacobian_ = false;  // du/dtheta of the non-spring elements from K_g (build_scatter)
  bool one_spring_per_group_ = false;
  // The theta solver_ is factorised at (valid when factored_) and its displacements per case.
  bool factored_ = false;
  Eigen::VectorXd factored_theta_;
  std::vector<Eigen::VectorXd> u_;
  // Kept from the last evaluation with a Jacobian (adjoint form) for gram(): K^-1 and, per case,
  // every spring's k_s (g_s^T u_c).
  Eigen::MatrixXd inverse_;
  // Work matrices of the adjoint form kept between evaluations (no MB-sized allocation each).
  Eigen::MatrixXd identity_, inverse_rows_;
  std::vector<Eigen::Triplet<double>> b_triplets_;  // B_c's entries (work storage)
  Eigen::SparseMatrix<double> b_sparse_;            // B_c, duplicates summed
  bool factor_at_inverse_ = false;  // solver_ still holds the factorisation inverse_ came from
  std::vector<Eigen::VectorXd> spring_force_;
  Eigen::SparseMatrix<double> k_;  // upper triangle on the free DOFs
  PivotCheckedCholmod solver_;
};

}  // namespace isospring::fitting::detail
