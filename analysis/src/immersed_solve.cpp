// Immersed static solve (sparse Cholesky or block-Jacobi CG, as the body-fitted solver) and the
// evaluation of the solution at physical points.
#include <Eigen/CholmodSupport>
#include <chrono>
#include <stdexcept>

#include "immersed_basis.hpp"
#include "immersed_bbar.hpp"
#include "immersed_kernels.hpp"
#include "isospring/analysis/block_cg.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/immersed.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace detail {

Element element_of_cell(const BackgroundBasis& basis, const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& x : points) centroid += x;
  return basis.element_of(centroid / static_cast<double>(points.size()));
}

ImmersedPointValue value_on_element(const BackgroundBasis& basis, const Element& e,
                                    const ImmersedResult& result, const Eigen::Vector3d& x,
                                    BasisAt& at) {
  basis.evaluate(e, x, at);
  ImmersedPointValue out;
  for (size_t a = 0; a < at.control_points.size(); ++a) {
    const Eigen::Vector3d& u =
        result.control_displacements[static_cast<size_t>(at.control_points[a])];
    out.displacement += at.values[static_cast<Eigen::Index>(a)] * u;
    out.gradient.leftCols(basis.dim()) += u * at.gradients.row(static_cast<Eigen::Index>(a));
  }
  return out;
}

}  // namespace detail

namespace {

// Cholesky found the stiffness not positive definite.
struct NotPositiveDefinite : std::runtime_error {
  NotPositiveDefinite() : std::runtime_error("not positive definite") {}
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Eigen::VectorXd solve_system(const ImmersedSystem& system, const ImmersedOptions& options,
                             ImmersedResult& result) {
  result.method = options.method;
  if (options.method == SolverOptions::Method::kAuto)
    result.method = choose_solver(system.dim, static_cast<double>(system.force.size())).method;
  if (result.method == SolverOptions::Method::kConjugateGradient) {
    const SymmetricBlockMatrix matrix(system.stiffness, system.dim);
    BlockCgOptions cg;
    cg.tolerance = options.cg_tolerance;
    Eigen::VectorXd u;
    const BlockCgResult out = block_cg(matrix, system.force, u, cg);
    if (!out.converged)
      throw std::runtime_error("immersed analysis: conjugate gradients did not converge in " +
                               std::to_string(out.iterations) + " iterations (residual " +
                               std::to_string(out.relative_residual) +
                               "); use the Cholesky solver");
    result.iterations = out.iterations;
    result.relative_residual = out.relative_residual;
    return u;
  }
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky;
  cholesky.compute(system.stiffness);
  if (cholesky.info() != Eigen::Success) throw NotPositiveDefinite();
  return cholesky.solve(system.force);
}

// Assembles and solves through assemble_stabilised_immersed (which widens the ghost penalty
// where Cholesky finds the stiffness not positive definite, with a warning in the result).
// Returns the displacement on the DOFs; `system` is the one it came from.
Eigen::VectorXd assemble_and_solve(const geometry::ImmersedDomain& domain,
                                   const ImmersedOptions& options, ImmersedSystem& system,
                                   ImmersedResult& result) {
  Eigen::VectorXd u;
  double solving = 0.0;
  const auto start = std::chrono::steady_clock::now();
  const auto solve = [&](const ImmersedSystem& candidate) {
    const auto begin = std::chrono::steady_clock::now();
    try {
      u = solve_system(candidate, candidate.options, result);
    } catch (const NotPositiveDefinite&) {
      solving += seconds_since(begin);
      return false;
    }
    solving += seconds_since(begin);
    return true;
  };
  system = assemble_stabilised_immersed(domain, options, solve, result.warnings);
  result.solve_seconds += solving;
  result.assembly_seconds += seconds_since(start) - solving;
  return u;
}

ImmersedPointValue point_value(const detail::BackgroundBasis& basis, const ImmersedResult& result,
                               const Eigen::Vector3d& x) {
  detail::BasisAt at;
  return detail::value_on_element(basis, basis.element_of(x), result, x, at);
}

// Over each cell's reduced rule (the energy density is in Q_2p on the cell's element).
double strain_energy(const geometry::ImmersedDomain& domain, const ImmersedResult& result,
                     const ImmersedOptions& options) {
  const detail::BackgroundBasis basis(domain, false);
  double energy = 0;
  const double thickness =
      options.formulation == Formulation::kSolid ? 1.0 : options.material.thickness;
  detail::BasisAt at;
  for (const auto& cell : domain.cells) {
    const detail::Element e = detail::element_of_cell(basis, cell.points);
    const detail::CellRule rule = detail::reduced_cell_rule(basis, e, cell.points, cell.weights);
    for (size_t q = 0; q < rule.points.size(); ++q) {
      const Eigen::Matrix3d grad =
          detail::value_on_element(basis, e, result, rule.points[q], at).gradient;
      const Eigen::Matrix3d strain = 0.5 * (grad + grad.transpose());
      const Eigen::Matrix3d stress =
          stress_from_strain(strain, options.material, options.formulation);
      energy += 0.5 * rule.weights[q] * thickness * (stress.cwiseProduct(strain)).sum();
    }
  }
  return energy;
}

}  // namespace

ImmersedResult solve_immersed(const geometry::ImmersedDomain& domain,
                              const ImmersedOptions& options) {
  ImmersedResult result;
  result.dim = domain.dimension;
  ImmersedSystem system;
  const Eigen::VectorXd u = assemble_and_solve(domain, options, system, result);
  result.ghost_fraction = system.options.ghost_fraction;
  result.max_nitsche_penalty = system.max_nitsche_penalty;
  result.ghost_faces = system.ghost_faces;
  result.dofs = static_cast<int>(system.force.size());
  result.control_displacements.assign(system.node_of_control_point.size(), Eigen::Vector3d::Zero());
  result.active.assign(system.node_of_control_point.size(), false);
  for (size_t node = 0; node < system.control_point_of_node.size(); ++node) {
    const size_t cp = static_cast<size_t>(system.control_point_of_node[node]);
    result.active[cp] = true;
    for (int c = 0; c < system.dim; ++c)
      result.control_displacements[cp][c] = u[static_cast<Eigen::Index>(node) * system.dim + c];
  }
  result.strain_energy = system.options.volumetric == Volumetric::kBbar
                             ? detail::bbar_strain_energy(domain, result, system.options)
                             : strain_energy(domain, result, system.options);
  return result;
}

ImmersedPointValue evaluate_immersed(const geometry::ImmersedDomain& domain,
                                     const ImmersedResult& result, const Eigen::Vector3d& x) {
  const int dim = domain.dimension;
  const double slack = 1e-9 * domain.extent.head(dim).norm();
  const Eigen::Vector3d y = domain.to_grid(x);
  if (((y - domain.origin).head(dim).array() < -slack).any() ||
      ((y - domain.origin - domain.extent).head(dim).array() > slack).any()) {
    std::ostringstream message;
    message << "immersed evaluation: the point (" << x.transpose()
            << ") lies outside the background grid";
    throw nurbs::InputError(message.str());
  }
  if (result.control_displacements.size() != static_cast<size_t>(domain.background.num_points()))
    throw nurbs::InputError(
        "immersed evaluation: the result does not belong to this domain (its control point "
        "count differs)");
  return point_value(detail::BackgroundBasis(domain, false), result, x);
}

Eigen::Matrix3d immersed_stress(const geometry::ImmersedDomain& domain,
                                const ImmersedResult& result, const ImmersedOptions& options,
                                const Eigen::Vector3d& x) {
  const Eigen::Matrix3d grad = evaluate_immersed(domain, result, x).gradient;
  return stress_from_strain(0.5 * (grad + grad.transpose()), options.material, options.formulation);
}

}  // namespace isospring::analysis
