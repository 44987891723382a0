// The phases of `isospring identify` that dominate its 3D runs, on a clamped box
// (0.2 x 0.04 x 0.04 m) k-refined to degree 3, 12 x 4 x 4 elements (2,205 DOFs, clamped at x = 0):
// - LameAssembly: the Lame-split stiffness (make_setup, stiffness_gradient's weighted parts),
//   element products on one thread;
// - ForwardModelRefactorisation: one evaluation (with Jacobian) of a model whose nu changes at
//   every call, i.e. one numeric Cholesky factorisation each, on the symbolic analysis made for
//   the first (counters: analyses, factorisations per evaluation);
// - SvkTangent/threads: the large-deformation candidate's internal force and tangent (St.
//   Venant-Kirchhoff, every element's dense products) on 1 and 2 threads; the colours keep the
//   sums in one order, so both give the same matrix;
// - SvkForce: the internal force alone, what a chord (modified Newton) step assembles;
// - SvkAssembly/dim/degree/tangent: the same assemblies at the size of the score test on the
//   tissue-like datasets (8,019 DOFs in 3D), and in 2D and at degree 2, on one thread;
// - ForwardModelJacobianSolves: an evaluation with its Jacobian without a factorisation (the
//   solves and right-hand sides of a graded model under three load cases);
// - StiffnessAssembly/threads: analysis::assemble_stiffness of the box on 1 and 2 threads;
// - ForwardModelLowRankSprings: an evaluation with its Jacobian of the box on springs at its
//   clamped side whose stiffness changes at every call: a Woodbury update of the cached factor;
// - FactorizationCopy: the copy of a factorisation that a hold-out fold starts from (against
//   ForwardModelRefactorisation's factorisation of the same K).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/lame_stiffness.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/thread_scope.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"

namespace {

using namespace isospring;

analysis::Problem box_problem() {
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {1e9, 0.3, 7800, 1.0};
  problem.patches.push_back(
      nurbs::k_refine(geometry::box(0.2, 0.04, 0.04)[0], {3, 3, 3}, {12, 4, 4}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::LoadCase load;
  load.id = "bend";
  load.tractions.push_back({{0, 0, 1}, {0, 2e4, 0}, {}});
  problem.load_cases.push_back(load);
  return problem;
}

void BM_LameAssembly(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  for (auto _ : state) {
    const fitting::LameMatrices parts = fitting::assemble_lame_stiffness(problem, dofs);
    benchmark::DoNotOptimize(parts.mu_part.nonZeros());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_LameAssembly)->Unit(benchmark::kMillisecond);

// The linear stiffness (analysis::assemble_stiffness) of the same box, on 1 and 2 threads.
void BM_StiffnessAssembly(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  const analysis::ThreadScope threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const Eigen::SparseMatrix<double> k = analysis::assemble_stiffness(problem, dofs);
    benchmark::DoNotOptimize(k.valuePtr());
  }
}
BENCHMARK(BM_StiffnessAssembly)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ForwardModelRefactorisation(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  const fitting::LameMatrices parts = fitting::assemble_lame_stiffness(problem, dofs);
  const double e = problem.material.youngs_modulus;
  fitting::ModelTerms terms;
  terms.num_parameters = 2;  // E / E_prior, nu
  auto lame = [e](bool lambda) -> fitting::Coefficient {
    return [e, lambda](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
      const double nu = t[1], den = (1.0 + nu) * (1.0 - 2.0 * nu);
      const double per_e = lambda ? nu / den : 0.5 / (1.0 + nu);
      const double d_nu =
          lambda ? (1.0 + 2.0 * nu * nu) / (den * den) : -0.5 / ((1.0 + nu) * (1.0 + nu));
      if (g) *g = Eigen::Vector2d(e * per_e, e * t[0] * d_nu);
      return e * t[0] * per_e;
    };
  };
  terms.stiffness.push_back({parts.lambda_part, lame(true)});
  terms.stiffness.push_back({parts.mu_part, lame(false)});
  terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                         fitting::constant_coefficient(1.0)});
  // Observations: every 7th DOF.
  fitting::Observation obs;
  std::vector<Eigen::Triplet<double>> triplets;
  for (int d = 0; d < dofs.num_dofs(); d += 7)
    triplets.emplace_back(static_cast<int>(triplets.size()), d, 1.0);
  obs.operator_.resize(static_cast<Eigen::Index>(triplets.size()), dofs.num_dofs());
  obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const fitting::ForwardModel model(terms, {obs}, constraints.dofs, constraints.values,
                                    dofs.num_dofs(), 1);
  double nu = 0.3;
  for (auto _ : state) {
    nu = nu > 0.3 ? 0.29 : 0.31;  // a new coefficient ratio: a factorisation per evaluation
    const fitting::ModelEvaluation eval = model.evaluate(Eigen::Vector2d(1.0, nu), true);
    benchmark::DoNotOptimize(eval.predictions[0].data());
  }
  const fitting::FactorizationStats stats = model.factorization_stats();
  state.counters["dofs"] = dofs.num_dofs();
  state.counters["analyses"] = static_cast<double>(stats.analyses);
  state.counters["factorisations"] = static_cast<double>(stats.factorizations);
}
BENCHMARK(BM_ForwardModelRefactorisation)->Unit(benchmark::kMillisecond);

// One evaluation with its Jacobian of a graded model (E and a stiffness gradient along each
// axis: 8 stiffness terms, 4 parameters) under three load cases, at fixed parameters: the
// factorisation is reused, so this is the solves and the right-hand sides dK/dtheta u.
void BM_ForwardModelJacobianSolves(benchmark::State& state) {
  analysis::Problem problem = box_problem();
  for (const Eigen::Vector3d& traction : {Eigen::Vector3d(0, 0, 2e4), Eigen::Vector3d(2e5, 0, 0)}) {
    analysis::LoadCase load;
    load.id = "load " + std::to_string(problem.load_cases.size());
    load.tractions.push_back({{0, 0, 1}, traction, {}});
    problem.load_cases.push_back(load);
  }
  const analysis::DofMap dofs(problem);
  std::vector<analysis::SpatialWeight> weights = {analysis::SpatialWeight()};
  for (int c = 0; c < 3; ++c)
    weights.emplace_back([c](const Eigen::Vector3d& x) { return x[c] / 0.2; });
  const auto parts = analysis::assemble_lame_stiffness(problem, dofs, weights);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  fitting::ModelTerms terms;
  terms.num_parameters = 4;  // E / E_prior, gradient per axis
  for (size_t w = 0; w < weights.size(); ++w)
    for (const bool lambda : {true, false}) {
      const double modulus = lambda ? lame.lambda : lame.mu;
      const fitting::Coefficient coefficient =
          w == 0 ? fitting::linear_coefficient(0, modulus)
                 : fitting::product(fitting::linear_coefficient(0, modulus),
                                    fitting::linear_coefficient(static_cast<int>(w)));
      terms.stiffness.push_back({lambda ? parts[w].lambda_part : parts[w].mu_part, coefficient});
    }
  std::vector<fitting::Observation> observations;
  for (size_t l = 0; l < problem.load_cases.size(); ++l) {
    terms.loads.push_back({static_cast<int>(l),
                           analysis::assemble_load(problem, dofs, problem.load_cases[l]),
                           fitting::constant_coefficient(1.0)});
    fitting::Observation obs;  // every 7th DOF
    std::vector<Eigen::Triplet<double>> triplets;
    for (int d = 0; d < dofs.num_dofs(); d += 7)
      triplets.emplace_back(static_cast<int>(triplets.size()), d, 1.0);
    obs.operator_.resize(static_cast<Eigen::Index>(triplets.size()), dofs.num_dofs());
    obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
    observations.push_back(obs);
  }
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const fitting::ForwardModel model(terms, observations, constraints.dofs, constraints.values,
                                    dofs.num_dofs(), static_cast<int>(observations.size()));
  const Eigen::Vector4d theta(1.0, 0.1, -0.05, 0.02);
  for (auto _ : state) {
    const fitting::ModelEvaluation eval = model.evaluate(theta, true);
    benchmark::DoNotOptimize(eval.predictions[0].data());
  }
  state.counters["dofs"] = dofs.num_dofs();
  state.counters["factorisations"] =
      static_cast<double>(model.factorization_stats().factorizations);
}
BENCHMARK(BM_ForwardModelJacobianSolves)->Unit(benchmark::kMillisecond);

// A smooth displacement of the box (bending along y, 1 % of its length at the tip).
Eigen::VectorXd bent(const analysis::Problem& problem, const analysis::DofMap& dofs) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs.num_dofs());
  const auto& points = problem.patches[0].control_points();
  for (size_t a = 0; a < points.size(); ++a) {
    const double s = points[a].x() / 0.2;
    u[dofs.dof(0, static_cast<int>(a), 1)] = 2e-3 * s * s;
  }
  return u;
}

void BM_SvkTangent(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  analysis::SvkAssembler assembler(problem, dofs);
  assembler.set_threads(static_cast<int>(state.range(0)));
  const Eigen::VectorXd u = bent(problem, dofs);
  Eigen::SparseMatrix<double> tangent;
  for (auto _ : state) {
    const Eigen::VectorXd r = assembler.internal_force(u, {5.8e8, 3.8e8}, &tangent);
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_SvkTangent)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SvkForce(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  analysis::SvkAssembler assembler(problem, dofs);
  assembler.set_threads(static_cast<int>(state.range(0)));
  const Eigen::VectorXd u = bent(problem, dofs);
  for (auto _ : state) {
    const Eigen::VectorXd r = assembler.internal_force(u, {5.8e8, 3.8e8});
    benchmark::DoNotOptimize(r.data());
  }
}
BENCHMARK(BM_SvkForce)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The score test's size in `isospring identify` on the tissue-like datasets: a 0.1 x 0.02 x
// 0.02 m cantilever, degree 3, 30 x 6 x 6 elements (8,019 DOFs); in 2D (plane strain) the same
// length and height with 120 x 24 elements. Args: dimension, degree, tangent (1) or force only
// (0); one thread, CPU time per assembly (the solve of the Newton step is not included).
analysis::Problem svk_size_problem(int dim, int degree) {
  analysis::Problem problem;
  problem.material = {1e9, 0.45, 7800, 1.0};
  if (dim == 3) {
    problem.formulation = analysis::Formulation::kSolid;
    problem.patches.push_back(
        nurbs::k_refine(geometry::box(0.1, 0.02, 0.02)[0], {degree, degree, degree}, {30, 6, 6}));
  } else {
    problem.formulation = analysis::Formulation::kPlaneStrain;
    problem.patches.push_back(
        nurbs::k_refine(geometry::rectangle(0.1, 0.02)[0], {degree, degree}, {120, 24}));
  }
  return problem;
}

void BM_SvkAssembly(benchmark::State& state) {
  const analysis::Problem problem =
      svk_size_problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const analysis::DofMap dofs(problem);
  analysis::SvkAssembler assembler(problem, dofs);
  assembler.set_threads(1);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(dofs.num_dofs());
  const auto& points = problem.patches[0].control_points();
  for (size_t a = 0; a < points.size(); ++a) {  // bending, 1 % of the length at the tip
    const double s = points[a].x() / 0.1;
    u[dofs.dof(0, static_cast<int>(a), 1)] = 1e-3 * s * s;
  }
  Eigen::SparseMatrix<double> tangent;
  for (auto _ : state) {
    const Eigen::VectorXd r =
        assembler.internal_force(u, {2.2e9, 3.4e8}, state.range(2) ? &tangent : nullptr);
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_SvkAssembly)
    ->Args({3, 3, 1})
    ->Args({3, 3, 0})
    ->Args({3, 2, 1})
    ->Args({3, 2, 0})
    ->Args({2, 3, 1})
    ->Args({2, 3, 0})
    ->Args({2, 2, 1})
    ->Args({2, 2, 0})
    ->Unit(benchmark::kMillisecond);

// The box on springs at its clamped side (the side released, springs k exp(t1) there): theta =
// (E / E_prior, log spring scale). `cache`: the factorisation cache the model solves with.
fitting::ForwardModel spring_box_model(const analysis::Problem& problem,
                                       const analysis::DofMap& dofs,
                                       std::shared_ptr<fitting::FactorizationCache> cache) {
  const fitting::LameMatrices parts = fitting::assemble_lame_stiffness(problem, dofs);
  const auto lame = analysis::lame_parameters(problem.material, problem.formulation);
  const fitting::SideSpringMatrices springs =
      fitting::assemble_side_springs(problem, dofs, problem.supports[0].side);
  fitting::ModelTerms terms;
  terms.num_parameters = 2;
  terms.stiffness.push_back({parts.lambda_part, fitting::linear_coefficient(0, lame.lambda)});
  terms.stiffness.push_back({parts.mu_part, fitting::linear_coefficient(0, lame.mu)});
  const double k = 1e3 * problem.material.youngs_modulus / 0.2;
  terms.stiffness.push_back(
      {springs.normal + springs.tangential, [k](const Eigen::VectorXd& t, Eigen::VectorXd* g) {
         if (g) {
           g->setZero(t.size());
           (*g)[1] = k * std::exp(t[1]);
         }
         return k * std::exp(t[1]);
       }});
  terms.loads.push_back({0, analysis::assemble_load(problem, dofs, problem.load_cases[0]),
                         fitting::constant_coefficient(1.0)});
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  terms.released_dofs = constraints.dofs;
  fitting::Observation obs;  // every 7th DOF
  std::vector<Eigen::Triplet<double>> triplets;
  for (int d = 0; d < dofs.num_dofs(); d += 7)
    triplets.emplace_back(static_cast<int>(triplets.size()), d, 1.0);
  obs.operator_.resize(static_cast<Eigen::Index>(triplets.size()), dofs.num_dofs());
  obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
  return fitting::ForwardModel(terms, {obs}, constraints.dofs, constraints.values, dofs.num_dofs(),
                               1, std::move(cache));
}

void BM_ForwardModelLowRankSprings(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  const fitting::ForwardModel model = spring_box_model(problem, dofs, nullptr);
  model.evaluate(Eigen::Vector2d(1.0, 0.0), true);  // the factorisation the updates start from
  double log_k = 0.0;
  for (auto _ : state) {
    log_k = log_k > 0.0 ? -0.5 : 0.5;  // only the springs change: a low-rank update each
    const fitting::ModelEvaluation eval = model.evaluate(Eigen::Vector2d(1.0, log_k), true);
    benchmark::DoNotOptimize(eval.predictions[0].data());
  }
  const fitting::FactorizationStats stats = model.factorization_stats();
  state.counters["dofs"] = dofs.num_dofs();
  state.counters["factorisations"] = static_cast<double>(stats.factorizations);
  state.counters["low_rank_updates"] = static_cast<double>(stats.low_rank_updates);
}
BENCHMARK(BM_ForwardModelLowRankSprings)->Unit(benchmark::kMillisecond);

void BM_FactorizationCopy(benchmark::State& state) {
  const analysis::Problem problem = box_problem();
  const analysis::DofMap dofs(problem);
  const auto cache = fitting::make_factorization_cache();
  const fitting::ForwardModel model = spring_box_model(problem, dofs, cache);
  model.evaluate(Eigen::Vector2d(1.0, 0.0), false);
  for (auto _ : state) {
    const auto copy = fitting::copy_factorization_cache(*cache);
    benchmark::DoNotOptimize(copy.get());
  }
  state.counters["dofs"] = dofs.num_dofs();
}
BENCHMARK(BM_FactorizationCopy)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
