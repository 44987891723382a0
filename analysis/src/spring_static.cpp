// Linear and Newton static solves of spring networks with sparse LDL^T factorisations.
#include "isospring/analysis/spring_static.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "isospring/analysis/spring_mechanics.hpp"

namespace isospring::analysis {

FreeDofSet::FreeDofSet(int num_dofs, const std::vector<int>& constrained)
    : index_(static_cast<size_t>(num_dofs), 0) {
  for (int dof : constrained) index_[static_cast<size_t>(dof)] = -1;
  for (int dof = 0; dof < num_dofs; ++dof)
    if (index_[static_cast<size_t>(dof)] == 0) {
      index_[static_cast<size_t>(dof)] = static_cast<int>(free_.size());
      free_.push_back(dof);
    } else {
      index_[static_cast<size_t>(dof)] = -1;
    }
}

Eigen::SparseMatrix<double> FreeDofSet::restrict(const Eigen::SparseMatrix<double>& matrix) const {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(matrix.nonZeros()));
  for (int col = 0; col < matrix.outerSize(); ++col) {
    const int c = index_[static_cast<size_t>(col)];
    if (c < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, col); it; ++it) {
      const int r = index_[static_cast<size_t>(it.row())];
      if (r >= 0) triplets.emplace_back(r, c, it.value());
    }
  }
  Eigen::SparseMatrix<double> result(num_free(), num_free());
  result.setFromTriplets(triplets.begin(), triplets.end());
  return result;
}

Eigen::VectorXd FreeDofSet::restrict(const Eigen::VectorXd& vector) const {
  Eigen::VectorXd result(num_free());
  for (int f = 0; f < num_free(); ++f) result[f] = vector[free_[static_cast<size_t>(f)]];
  return result;
}

Eigen::VectorXd FreeDofSet::expand(const Eigen::VectorXd& free_vector) const {
  Eigen::VectorXd result = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(index_.size()));
  for (int f = 0; f < num_free(); ++f) result[free_[static_cast<size_t>(f)]] = free_vector[f];
  return result;
}

namespace {

using Factorization = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

// LDL^T of a stiffness. At rest it must be positive definite (a non-positive pivot means a
// mechanism); a deformed tangent may be indefinite (compressed springs), but not singular.
void factorize(Factorization& solver, const Eigen::SparseMatrix<double>& matrix, const char* what,
               bool positive_definite) {
  solver.compute(matrix);
  const double scale = matrix.size() > 0 ? solver.vectorD().cwiseAbs().maxCoeff() : 1.0;
  const bool singular = (solver.vectorD().array().abs() <= 1e-13 * scale).any();
  if (solver.info() != Eigen::Success || singular ||
      (positive_definite && (solver.vectorD().array() <= 0.0).any()))
    throw std::runtime_error(std::string(what) +
                             ": the spring stiffness is singular or indefinite; the fixed "
                             "particles and springs do not hold the network in place");
}

double relative_norm(const Eigen::VectorXd& residual, const Eigen::VectorXd& force) {
  const double scale = force.norm();
  return scale > 0.0 ? residual.norm() / scale : residual.norm();
}

}  // namespace

std::vector<int> constrained_dofs(const SpringNetwork& network, const std::vector<int>& extra) {
  std::vector<int> dofs = fixed_dofs(network);
  dofs.insert(dofs.end(), extra.begin(), extra.end());
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  return dofs;
}

SpringLinearSolver::SpringLinearSolver(const SpringNetwork& network,
                                       const std::vector<int>& extra_constrained)
    : dofs_(static_cast<int>(network.positions.size()) * network.dimension,
            constrained_dofs(network, extra_constrained)),
      k_(dofs_.restrict(rest_stiffness(network))) {
  factorize(solver_, k_, "linear spring solve", true);
}

SpringSolveResult SpringLinearSolver::solve(const Eigen::VectorXd& force) const {
  if (force.size() != static_cast<Eigen::Index>(dofs_.num_dofs()))
    throw std::invalid_argument("linear spring solve: the force vector has " +
                                std::to_string(force.size()) + " entries for " +
                                std::to_string(dofs_.num_dofs()) + " particle components");
  const Eigen::VectorXd f = dofs_.restrict(force);
  const Eigen::VectorXd u = solver_.solve(f);
  SpringSolveResult result;
  result.displacement = dofs_.expand(u);
  result.iterations = 1;
  result.relative_residual = relative_norm(k_ * u - f, f);
  result.converged = true;
  return result;
}

SpringSolveResult solve_spring_linear(const SpringNetwork& network, const Eigen::VectorXd& force,
                                      const std::vector<int>& extra_constrained) {
  return SpringLinearSolver(network, extra_constrained).solve(force);
}

SpringSolveResult solve_spring_newton(const SpringNetwork& network, const Eigen::VectorXd& force,
                                      const SpringSolveOptions& options,
                                      const std::vector<int>& extra_constrained) {
  const FreeDofSet dofs(static_cast<int>(force.size()),
                        constrained_dofs(network, extra_constrained));
  const Eigen::VectorXd x0 = flat_positions(network);
  const int steps = std::max(1, options.load_steps);
  SpringSolveResult result;
  result.displacement = solve_spring_linear(network, force / steps, extra_constrained).displacement;
  Factorization solver;
  for (int step = 1; step <= steps; ++step) {
    const Eigen::VectorXd f = force * (static_cast<double>(step) / steps);
    const Eigen::VectorXd f_free = dofs.restrict(f);
    auto residual_at = [&](const Eigen::VectorXd& u) {
      return Eigen::VectorXd(dofs.restrict(Eigen::VectorXd(f + spring_forces(network, x0 + u))));
    };
    Eigen::VectorXd residual = residual_at(result.displacement);
    result.converged = false;
    for (int it = 0; it < options.max_iterations; ++it) {
      result.relative_residual = relative_norm(residual, f_free);
      if (result.relative_residual <= options.tolerance) {
        result.converged = true;
        break;
      }
      factorize(solver, dofs.restrict(tangent_stiffness(network, x0 + result.displacement)),
                "Newton spring solve", false);
      const Eigen::VectorXd delta = dofs.expand(solver.solve(residual));
      ++result.iterations;
      // Backtracking: halve the step until the residual decreases (large rotations of springs).
      double t = 1.0;
      Eigen::VectorXd trial = residual_at(result.displacement + delta);
      while (trial.norm() > residual.norm() && t > 1e-4) {
        t *= 0.5;
        trial = residual_at(result.displacement + t * delta);
      }
      result.displacement += t * delta;
      residual = trial;
    }
    if (!result.converged) {
      result.relative_residual = relative_norm(residual, f_free);
      result.converged = result.relative_residual <= options.tolerance;
      if (!result.converged) return result;
    }
  }
  return result;
}

}  // namespace isospring::analysis
