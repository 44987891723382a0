// Immersed static solve (sparse Cholesky or block-Jacobi CG, as the body-fitted solver) and the
// evaluation of the solution at physical points.
#include <Eigen/CholmodSupport>
#include <chrono>
#include <sstream>
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

// The largest share of a cell below which solve_immersed's fallback still penalises it: beyond
// it the penalty acts on well-cut cells too and costs accuracy (docs/immersed.md).
constexpr double kLargestGhostFraction = 0.16;

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

std::string fraction_text(double fraction) {
  std::ostringstream text;
  text << fraction;
  return text.str();
}

// Assembles and factorises; when the stiffness is not positive definite, stabilises more cut
// cells (ghost_fraction doubled, up to kLargestGhostFraction) and says so in the result's
// warnings. Returns the displacement on the DOFs; `system` and `used` are those it came from.
Eigen::VectorXd assemble_and_solve(const geometry::ImmersedDomain& domain,
                                   const ImmersedOptions& options, ImmersedSystem& system,
                                   ImmersedOptions& used, ImmersedResult& result) {
  used = options;
  for (;;) {
    auto start = std::chrono::steady_clock::now();
    system = assemble_immersed(domain, used);
    result.assembly_seconds += seconds_since(start);
    start = std::chrono::steady_clock::now();
    try {
      Eigen::VectorXd u = solve_system(system, used, result);
      result.solve_seconds += seconds_since(start);
      return u;
    } catch (const NotPositiveDefinite&) {
      result.solve_seconds += seconds_since(start);
      if (used.ghost_penalty <= 0.0 || used.ghost_fraction >= kLargestGhostFraction)
        throw std::runtime_error(
            "immersed analysis: the stiffness matrix could not be factorised (not positive "
            "definite) with ghost_fraction " +
            fraction_text(used.ghost_fraction) +
            ": a basis function keeps too little of its support in the part; raise "
            "ghost_fraction (the cut cells stabilised by the ghost penalty) or ghost_penalty, "
            "or move the grid (a cell size or margin a little different)");
      const double next = std::min(kLargestGhostFraction,
                                   used.ghost_fraction > 0.0 ? 2.0 * used.ghost_fraction : 0.02);
      result.warnings.push_back(
          "the stiffness was not positive definite with ghost_fraction " +
          fraction_text(used.ghost_fraction) +
          " (a basis function keeps too little of its support in the part); the ghost penalty "
          "now stabilises every cut cell with less than " +
          fraction_text(next) + " of the part");
      used.ghost_fraction = next;
    }
  }
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
  ImmersedOptions used;
  const Eigen::VectorXd u = assemble_and_solve(domain, options, system, used, result);
  result.ghost_fraction = used.ghost_fraction;
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
  result.strain_energy = used.volumetric == Volumetric::kBbar
                             ? detail::bbar_strain_energy(domain, result, used)
                             : strain_energy(domain, result, used);
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
