// Natural modes by shift-invert Lanczos (Spectra) on the free DOFs.
#include "isospring/analysis/modal.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>
#include <Eigen/CholmodSupport>
#include <cmath>
#include <string>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/validation.hpp"
#include "isospring/nurbs/error.hpp"
#include "reduced_system.hpp"

namespace isospring::analysis {

namespace {

// (K - sigma M)^-1 x for Spectra, factorised by CHOLMOD (both matrices upper-triangular).
class ShiftInvertOperator {
 public:
  using Scalar = double;
  ShiftInvertOperator(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m)
      : k_(k), m_(m) {}
  Eigen::Index rows() const { return k_.rows(); }
  Eigen::Index cols() const { return k_.cols(); }
  void set_shift(double sigma) {
    solver_.compute(k_ - sigma * m_);
    if (solver_.info() != Eigen::Success)
      throw std::runtime_error("modal analysis: K - sigma M could not be factorised");
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    y = solver_.solve(x);
  }

 private:
  const Eigen::SparseMatrix<double>& k_;
  const Eigen::SparseMatrix<double>& m_;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Upper> solver_;
};

}  // namespace

GeneralizedModes lowest_generalized_modes(const Eigen::SparseMatrix<double>& k,
                                          const Eigen::SparseMatrix<double>& m, int count,
                                          double tolerance) {
  const Eigen::Index n = k.rows();
  if (count < 1 || count > n - 1)
    throw nurbs::InputError("modal analysis: " + std::to_string(count) +
                            " modes asked of a model with " + std::to_string(n) +
                            " free DOFs; ask for 1 to " + std::to_string(n - 1));
  // Shift just below zero, scaled by the typical K/M ratio: keeps K - sigma M positive definite.
  const double sigma = -1e-6 * k.diagonal().mean() / m.diagonal().mean();
  ShiftInvertOperator op(k, m);
  Spectra::SparseSymMatProd<double, Eigen::Upper> mass_op(m);
  const int ncv = static_cast<int>(std::min<Eigen::Index>(n, std::max(2 * count + 1, 20)));
  Spectra::SymGEigsShiftSolver<ShiftInvertOperator, Spectra::SparseSymMatProd<double, Eigen::Upper>,
                               Spectra::GEigsMode::ShiftInvert>
      solver(op, mass_op, count, ncv, sigma);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, 1000, tolerance, Spectra::SortRule::SmallestAlge);
  if (solver.info() != Spectra::CompInfo::Successful)
    throw std::runtime_error("modal analysis: the eigensolver did not converge");
  return {solver.eigenvalues(), solver.eigenvectors()};
}

ModalResult compute_modes(const Problem& problem, const ModalOptions& options) {
  validate_problem(problem, {.require_load_cases = false, .require_density = true});
  const DofMap dofs(problem);
  Constraints constraints = build_constraints(problem, dofs);
  std::fill(constraints.values.begin(), constraints.values.end(), 0.0);
  const Eigen::SparseMatrix<double> stiffness = assemble_stiffness(problem, dofs);
  Eigen::SparseMatrix<double> mass;
  if (options.lumped_mass) {
    const Eigen::VectorXd node_mass = lumped_node_mass(problem, dofs);
    mass.resize(dofs.num_dofs(), dofs.num_dofs());
    std::vector<Eigen::Triplet<double>> diagonal;
    for (int d = 0; d < dofs.num_dofs(); ++d)
      diagonal.emplace_back(d, d, node_mass[d / dofs.dofs_per_node()]);
    mass.setFromTriplets(diagonal.begin(), diagonal.end());
  } else {
    mass = assemble_consistent_mass(problem, dofs);
  }
  const detail::ReducedSystem k(stiffness, constraints);
  const detail::ReducedSystem m(mass, constraints);
  const Eigen::Index n = k.free_matrix.rows();
  const int count = static_cast<int>(std::min<Eigen::Index>(options.modes, n - 1));
  if (count < 1) throw nurbs::InputError("modal analysis: the model has fewer than 2 free DOFs");
  const GeneralizedModes modes = lowest_generalized_modes(k.free_matrix, m.free_matrix, count);
  ModalResult result;
  result.dofs = dofs.num_dofs();
  result.eigenvalues = modes.eigenvalues;
  result.frequencies_hz = result.eigenvalues.unaryExpr(
      [](double lambda) { return std::sqrt(std::max(lambda, 0.0)) / (2.0 * M_PI); });
  const Eigen::MatrixXd& free_shapes = modes.vectors;
  result.shapes = Eigen::MatrixXd::Zero(dofs.num_dofs(), free_shapes.cols());
  for (size_t j = 0; j < k.free_dofs.size(); ++j)
    result.shapes.row(k.free_dofs[j]) = free_shapes.row(static_cast<Eigen::Index>(j));
  return result;
}

}  // namespace isospring::analysis
