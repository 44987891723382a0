// kAuto's rule (static_solver.hpp): which solver a problem gets, from its traits and a cost model
// of each solver (docs/performance.md has the measurements behind it).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/analysis/static_solver.hpp"

namespace isospring::analysis {
namespace {

// The constants are CPU seconds (all threads) of bench/bench_solvers.cpp on the 2-core machine
// while it was shared (load average 15-20, so every figure is inflated alike; only their ratios
// decide). The reference problem: the clamped p = 2 unit cube, 32^3 elements, nu 0.3, own weight,
// 114,444 free DOFs.
constexpr double kReferenceDofs = 114444;
// CHOLMOD supernodal (OpenBLAS): the factorisation at the reference, ~50 s (README "Performance":
// 48.9-55.5 s CPU). In 3D the nested-dissection factor costs N^2; a slender part factorises like
// a band, much cheaper: the 50:1 cantilever (96,300 DOFs, aspect ratio 42.7) took 7.6 s where
// N^2 alone says 35.4 s, hence aspect^-0.41. In 2D the factor costs N^1.5. Each load case adds
// a forward and back substitution.
constexpr double kCholeskySeconds = 50.0;
constexpr double kCholeskyAspectExponent = 0.41;
constexpr double kCholeskySolveSeconds = 0.5;
// Block-Jacobi CG: 260 iterations at the reference to 1e-10, 0.0305 s each; iterations grow as
// N^(1/3) (mesh size), as aspect^0.85 (the cantilever: 5770 iterations) and as
// (1 / (1 - 2 nu))^0.42 (nu 0.49: 909).
constexpr double kCgSecondsPerIteration = 0.0305;
constexpr double kCgIterations = 260;
constexpr double kCgAspectExponent = 0.85;
constexpr double kCgPoissonExponent = 0.42;
// PETSc GAMG-preconditioned CG on one process: 32 iterations at the reference, but 0.59 s each
// (the V-cycle of the p = 2 stiffness, whose coarse operators are dense, costs ~20 CG
// iterations) and 5.7 s of setup beyond CG's; iterations grow as aspect^0.33 (the cantilever:
// 106) and as
// (1 / (1 - 2 nu))^0.50 (nu 0.49: 144): the rigid-body near-null space does not help with
// near-incompressibility.
constexpr double kAmgSetupSeconds = 5.7;
constexpr double kAmgSecondsPerIteration = 0.59;
constexpr double kAmgIterations = 32;
constexpr double kAmgAspectExponent = 0.33;
constexpr double kAmgPoissonExponent = 0.50;

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
      kCholeskySeconds * (traits.dimension == 3
                              ? size * size * std::pow(aspect, -kCholeskyAspectExponent)
                              : std::pow(size, 1.5)) +
      cases * kCholeskySolveSeconds * std::pow(size, 4.0 / 3.0);
  const double cg_iterations = kCgIterations * std::cbrt(size) *
                               std::pow(aspect, kCgAspectExponent) *
                               std::pow(volumetric, kCgPoissonExponent);
  choice.cg_seconds = cases * cg_iterations * kCgSecondsPerIteration * size;
  const double amg_iterations = kAmgIterations * std::pow(size, 1.0 / 6.0) *
                                std::pow(aspect, kAmgAspectExponent) *
                                std::pow(volumetric, kAmgPoissonExponent);
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
