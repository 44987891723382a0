// Cost of the large-deformation laws per assembly: the neo-Hookean and SVK internal force and
// tangent on the same part and deformation (a 2 x 0.5 x 0.5 block, degree 3, 16 x 4 x 4 elements,
// 2793 DOFs), one thread, and one whole neo-Hookean solve (a 30 % end stretch of the block
// clamped at x = 0).
#include <benchmark/benchmark.h>

#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring {
namespace {

using Eigen::Vector3d;

analysis::Problem clamped_block() {
  const Vector3d size(2.0, 0.5, 0.5);
  std::vector<Vector3d> corners;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) corners.emplace_back(i * size.x(), j * size.y(), k * size.z());
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  nurbs::Patch patch = nurbs::elevate_degree(nurbs::Patch({linear, linear, linear}, corners), 2);
  const int elements[3] = {16, 4, 4};
  for (int d = 0; d < 3; ++d) patch = nurbs::refine_uniform(patch, d, elements[d]);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {1000.0, 0.3, 0.0, 1.0};
  problem.patches.push_back(patch);
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::Support pull;
  pull.side = {0, 0, 1};
  pull.fixed = {true, false, false};
  pull.value = {0.6, 0, 0};
  problem.supports.push_back(pull);
  analysis::LoadCase load;
  load.id = "stretch";
  problem.load_cases.push_back(load);
  return problem;
}

// 20 % stretch along x with a lateral contraction of 5 %.
Eigen::VectorXd stretched(const analysis::Problem& problem, const analysis::DofMap& dofs) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs.num_dofs());
  const auto& points = problem.patches[0].control_points();
  for (size_t a = 0; a < points.size(); ++a) {
    const int i = static_cast<int>(a);
    u[dofs.dof(0, i, 0)] = 0.2 * points[a].x();
    u[dofs.dof(0, i, 1)] = -0.05 * points[a].y();
    u[dofs.dof(0, i, 2)] = -0.05 * points[a].z();
  }
  return u;
}

void BM_NeoHookeanTangent(benchmark::State& state) {
  const analysis::Problem problem = clamped_block();
  const analysis::DofMap dofs(problem);
  analysis::NeoHookeanAssembler assembler(problem, dofs);
  assembler.set_threads(1);
  const auto moduli = analysis::neo_hookean_parameters(problem.material, problem.formulation);
  const Eigen::VectorXd u = stretched(problem, dofs);
  Eigen::SparseMatrix<double> tangent;
  for (auto _ : state) {
    const Eigen::VectorXd r = assembler.internal_force(u, moduli, &tangent);
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_NeoHookeanTangent)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SvkTangentSamePart(benchmark::State& state) {
  const analysis::Problem problem = clamped_block();
  const analysis::DofMap dofs(problem);
  analysis::SvkAssembler assembler(problem, dofs);
  assembler.set_threads(1);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  const Eigen::VectorXd u = stretched(problem, dofs);
  Eigen::SparseMatrix<double> tangent;
  for (auto _ : state) {
    const Eigen::VectorXd r = assembler.internal_force(u, lame, &tangent);
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_SvkTangentSamePart)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_NeoHookeanForce(benchmark::State& state) {
  const analysis::Problem problem = clamped_block();
  const analysis::DofMap dofs(problem);
  analysis::NeoHookeanAssembler assembler(problem, dofs);
  assembler.set_threads(1);
  const auto moduli = analysis::neo_hookean_parameters(problem.material, problem.formulation);
  const Eigen::VectorXd u = stretched(problem, dofs);
  for (auto _ : state) {
    const Eigen::VectorXd r = assembler.internal_force(u, moduli);
    benchmark::DoNotOptimize(r.data());
  }
}
BENCHMARK(BM_NeoHookeanForce)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_NeoHookeanClampedStretchSolve(benchmark::State& state) {
  const analysis::Problem problem = clamped_block();
  analysis::NonlinearOptions options;
  options.material = analysis::HyperelasticMaterial::kNeoHookean;
  options.threads = 1;
  int iterations = 0;
  for (auto _ : state) {
    const auto result = analysis::solve_static_nonlinear(problem, options);
    iterations = result[0].iterations;
    benchmark::DoNotOptimize(result.data());
  }
  state.counters["newton_iterations"] = iterations;
}
BENCHMARK(BM_NeoHookeanClampedStretchSolve)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace isospring

BENCHMARK_MAIN();
