// kAuto's rule (static_solver.hpp): which solver a problem gets, from its traits and a cost model
// of each solver. The constants are measurements on the 2-core reference machine
// (bench/bench_solvers.cpp, README "Performance", docs/performance.md); only their ratios
// matter for the choice.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {

// The reference problem of the constants: the clamped p = 2 unit cube, 32^3 elements, nu 0.3.
constexpr double kReferenceDofs = 114444;
// CHOLMOD supernodal with OpenBLAS: factorisation seconds at the reference size; in 3D the
// nested-dissection factor costs N^2 (48.9-55.5 s CPU measured), in 2D N^1.5.
constexpr double kCholeskySeconds = 50.0;
// Block-Jacobi CG at the reference: seconds per iteration and iterations to 1e-10; iterations
// grow as N^(1/3) (mesh size), as the aspect ratio (the bending mode's stiffness falls as the
// square of slenderness) and as sqrt(1 / (1 - 2 nu)) (the volumetric stiffness).
constexpr double kCgSecondsPerIteration = 0.0127;
constexpr double kCgIterations = 189;
// PETSc GAMG-preconditioned CG on one process at the reference: setup (its own assembly
// included) and seconds per iteration; its iteration count grows slowly with the mesh and the
// conditioning (exponents below).
constexpr double kAmgSetupSeconds = 8.0;
constexpr double kAmgSecondsPerIteration = 0.25;
constexpr double kAmgIterations = 40;
constexpr double kAmgAspectExponent = 0.5;
constexpr double kAmgPoissonExponent = 0.5;

// 1 / (1 - 2 nu) relative to nu = 0.3.
double volumetric_factor(double poisson) {
  return (1 - 2 * 0.3) / std::max(1e-6, 1 - 2 * poisson);
}

std::string format(double seconds) {
  std::ostringstream out;
  out.precision(seconds < 10 ? 2 : 3);
  out << seconds << " s";
  return out.str();
}

}  // namespace

SolverTraits solver_problem_traits(const Problem& problem, const DofMap& dofs,
                                   const Constraints& constraints) {
  SolverTraits traits;
  traits.dimension = spatial_dimension(problem.formulation);
  traits.free_dofs =
      static_cast<double>(dofs.num_dofs()) - static_cast<double>(constraints.dofs.size());
  traits.load_cases = std::max(1, static_cast<int>(problem.load_cases.size()));
  traits.poisson = problem.material.poisson_ratio;
  traits.amg_available = petsc_available();
  // Principal extents of the control points (node positions, so shared points count once).
  const auto& x = dofs.node_positions();
  if (x.size() > 1) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : x) mean += p;
    mean /= static_cast<double>(x.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto& p : x) covariance += (p - mean) * (p - mean).transpose();
    const int d = traits.dimension;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
        covariance.topLeftCorner(d, d).eval());
    const Eigen::VectorXd lambda = eigen.eigenvalues();  // increasing
    if (lambda(0) > 0) traits.aspect = std::sqrt(lambda(d - 1) / lambda(0));
  }
  return traits;
}

SolverChoice choose_solver(const SolverTraits& traits) {
  using Method = SolverOptions::Method;
  SolverChoice choice;
  const double n = traits.free_dofs;
  const double threshold = traits.dimension == 3 ? kAutoIterativeDofs3d : kAutoIterativeDofs2d;
  std::ostringstream reason;
  reason << static_cast<long long>(n) << " free DOFs in " << traits.dimension << "D";
  if (n <= threshold) {
    reason << " at or below " << static_cast<long long>(threshold)
           << ": sparse Cholesky (fast at this size, and robust)";
    choice.reason = reason.str();
    return choice;
  }
  const double size = n / kReferenceDofs;
  const double cases = traits.load_cases;
  const double volumetric = volumetric_factor(traits.poisson);
  const double aspect = std::max(1.0, traits.aspect);
  choice.cholesky_seconds =
      kCholeskySeconds * (traits.dimension == 3 ? size * size : std::pow(size, 1.5));
  const double cg_iterations = kCgIterations * std::cbrt(size) * aspect * std::sqrt(volumetric);
  choice.cg_seconds = cases * cg_iterations * kCgSecondsPerIteration * size;
  const double amg_iterations = kAmgIterations * std::pow(size, 1.0 / 6.0) *
                                std::pow(aspect, kAmgAspectExponent) *
                                std::pow(volumetric, kAmgPoissonExponent / 2);
  choice.amg_seconds =
      traits.amg_available
          ? (kAmgSetupSeconds + cases * amg_iterations * kAmgSecondsPerIteration) * size
          : 0;
  // In 2D the direct solver is kept up to its threshold only (its memory, not its time, limits it).
  const bool direct = traits.dimension == 3;
  choice.method = Method::kConjugateGradient;
  double best = choice.cg_seconds;
  if (traits.amg_available && choice.amg_seconds < best) {
    choice.method = Method::kAmg;
    best = choice.amg_seconds;
  }
  if (direct && choice.cholesky_seconds < best) {
    choice.method = Method::kCholesky;
    best = choice.cholesky_seconds;
  }
  reason << " above " << static_cast<long long>(threshold) << "; " << traits.load_cases
         << " load case(s), nu " << traits.poisson << ", aspect ratio "
         << std::round(aspect * 10) / 10 << "; estimated: ";
  if (direct) reason << "sparse Cholesky " << format(choice.cholesky_seconds) << ", ";
  reason << "block-Jacobi CG " << format(choice.cg_seconds) << " ("
         << static_cast<long long>(cg_iterations) << " iterations per load case)";
  if (traits.amg_available)
    reason << ", AMG CG " << format(choice.amg_seconds);
  else
    reason << ", AMG not built (no PETSc)";
  reason << ": "
         << (choice.method == Method::kCholesky            ? "sparse Cholesky"
             : choice.method == Method::kConjugateGradient ? "block-Jacobi conjugate gradients"
                                                           : "AMG-preconditioned CG");
  choice.reason = reason.str();
  return choice;
}

SolverChoice choose_solver(int dimension, double free_dofs) {
  SolverTraits traits;
  traits.dimension = dimension;
  traits.free_dofs = free_dofs;
  return choose_solver(traits);
}

}  // namespace isospring::analysis
