// Where and why the large-deformation spring models lose their equilibrium (docs/calibration.md,
// large-deformation calibration): for the cube and the square of bench_large_deformation, each
// calibration (linear, large deformation at %eps_G 5 then 20) and each held-out and fitted load,
//   - the rest stiffness of the fitted network on the free DOFs (smallest / largest eigenvalue:
//     a mechanism at rest shows as ~0),
//   - the load path from rest in 256 equal steps solved by Newton on |r| with backtracking (the
//     solver the fit used before energy minimisation): the load fraction reached, and at the
//     last equilibrium the smallest tangent eigenvalue (relative to the rest one), the smallest
//     net-cell volume ratio V/V0 and the smallest spring length ratio,
//   - the library's spring_equilibrium (energy-minimising Newton with load stepping): whether it
//     finds an equilibrium, its error against the reference and the same cell and tangent
//     numbers there,
//   - the reference's own stability: the smallest eigenvalue of the neo-Hookean IGA tangent at
//     the reference on the free DOFs, relative to its value at rest.
// One iteration per object; prints one line per load. `fit_path` takes the square with volume
// and shear terms apart: its fit's cost from rest at the starts and the end, along the segment
// between them, each amplitude fitted alone from several starts, the case that leaves the
// solid's branch fitted alone; `fit_without` the continuation without some training cases.
#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <cstdio>
#include <limits>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/fitting/nonlinear_displacement_fit.hpp"
#include "large_deformation_models.hpp"

namespace isospring {
namespace {

using analysis::FreeDofSet;
using analysis::SpringNetwork;
using fitting::SpringModelOnProblem;

struct State {
  double lambda_min = 0, cell_ratio = 0, length_ratio = 0;
};

// Smallest and largest eigenvalue of the free block of a symmetric sparse matrix (dense: the
// benches' nets have at most a few hundred DOFs).
Eigen::Vector2d extreme_eigenvalues(const Eigen::SparseMatrix<double>& m) {
  const Eigen::MatrixXd dense(m);
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                                 0.5 * (dense + dense.transpose()), Eigen::EigenvaluesOnly)
                                 .eigenvalues();
  return {ev.minCoeff(), ev.maxCoeff()};
}

State state_at(const SpringNetwork& network, const SpringNetwork& cells, const FreeDofSet& dofs,
               const Eigen::VectorXd& x, double lambda_rest) {
  State s;
  s.lambda_min =
      extreme_eigenvalues(dofs.restrict(analysis::tangent_stiffness(network, x)))[0] / lambda_rest;
  s.cell_ratio = 1e300;
  for (const auto& t : cells.volumes)
    if (t.kind == analysis::CellEnergy::kVolume)
      s.cell_ratio =
          std::min(s.cell_ratio, analysis::cell_volume(t, x, network.dimension) / t.rest_volume);
  s.length_ratio = 1e300;
  const int d = network.dimension;
  for (const auto& sp : network.springs)
    s.length_ratio = std::min(
        s.length_ratio, (x.segment(sp.j * d, d) - x.segment(sp.i * d, d)).norm() / sp.rest_length);
  return s;
}

// Newton on |r| with backtracking, 50 iterations (the fit's former solver).
bool residual_newton(const SpringNetwork& network, const FreeDofSet& dofs,
                     const Eigen::VectorXd& x0, const Eigen::VectorXd& force, Eigen::VectorXd& u) {
  auto residual = [&](const Eigen::VectorXd& v) {
    return dofs.restrict(Eigen::VectorXd(force + analysis::spring_forces(network, x0 + v)));
  };
  const double scale = std::max(dofs.restrict(force).norm(), 1e-300);
  Eigen::VectorXd r = residual(u);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  for (int it = 0; it < 50 && r.norm() > 1e-13 * scale; ++it) {
    solver.compute(dofs.restrict(analysis::tangent_stiffness(network, x0 + u)));
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd delta = dofs.expand(solver.solve(r));
    if (!delta.allFinite()) break;
    double t = 1.0;
    Eigen::VectorXd trial = residual(u + delta);
    while (!(trial.norm() < r.norm()) && t > 1e-4) {
      t *= 0.5;
      trial = residual(u + t * delta);
    }
    if (!(trial.norm() < r.norm())) break;
    u += t * delta;
    r = trial;
  }
  return r.norm() <= 1e-10 * scale && u.allFinite();
}

// Smallest eigenvalue of the neo-Hookean tangent on the free DOFs at u, relative to rest.
double reference_stability(const analysis::Problem& problem, const Eigen::VectorXd& u) {
  const analysis::DofMap dofs(problem);
  const analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  const FreeDofSet free(dofs.num_dofs(), constraints.dofs);
  const analysis::NeoHookeanAssembler assembler(problem, dofs);
  const auto moduli = analysis::neo_hookean_parameters(problem.material, problem.formulation);
  auto lambda_min = [&](const Eigen::VectorXd& v) {
    Eigen::SparseMatrix<double> upper;
    assembler.internal_force(v, moduli, &upper);
    const Eigen::SparseMatrix<double> full = upper.selfadjointView<Eigen::Upper>();
    return extreme_eigenvalues(free.restrict(full))[0];
  };
  return lambda_min(u) / lambda_min(Eigen::VectorXd::Zero(u.size()));
}

void diagnose(const char* label, const analysis::Problem& problem,
              const std::vector<Eigen::VectorXd>& references, const SpringModelOnProblem& model,
              const SpringNetwork& cells) {
  const SpringNetwork& network = model.network;
  const FreeDofSet dofs(static_cast<int>(network.positions.size()) * network.dimension,
                        analysis::constrained_dofs(network, model.extra_constrained));
  const Eigen::VectorXd x0 = analysis::flat_positions(network);
  const Eigen::Vector2d rest =
      extreme_eigenvalues(dofs.restrict(analysis::tangent_stiffness(network, x0)));
  std::printf("  %s: rest tangent eigenvalues min %.3e max %.3e (ratio %.2e)\n", label, rest[0],
              rest[1], rest[0] / rest[1]);
  const auto forces = fitting::particle_loads(problem, model);
  const auto evaluated = fitting::evaluate_large_deformation(problem, model, references);
  for (size_t c = 0; c < forces.size(); ++c) {
    const int steps = 256;
    Eigen::VectorXd u = Eigen::VectorXd::Zero(forces[c].size()), last = u;
    int reached = 0;
    for (int s = 1; s <= steps; ++s) {
      if (!residual_newton(network, dofs, x0, forces[c] * (double(s) / steps), u)) break;
      reached = s;
      last = u;
    }
    const State path = state_at(network, cells, dofs, x0 + last, rest[0]);
    std::printf(
        "    %-22s ref lambda_min %.3f | |r|-Newton 256 steps: reached %.3f, there lambda_min "
        "%.3f, min V/V0 %.3f, min l/L0 %.3f",
        problem.load_cases[c].id.c_str(), reference_stability(problem, references[c]),
        double(reached) / steps, path.lambda_min, path.cell_ratio, path.length_ratio);
    Eigen::VectorXd v;
    if (fitting::spring_equilibrium(network, forces[c], model.extra_constrained, v)) {
      const State eq = state_at(network, cells, dofs, x0 + v, rest[0]);
      std::printf(" | library: %%e_rms %.2f, lambda_min %.3f, min V/V0 %.3f, min l/L0 %.3f\n",
                  evaluated[c].control.percent_e_rms, eq.lambda_min, eq.cell_ratio,
                  eq.length_ratio);
    } else {
      std::printf(" | library: no equilibrium\n");
    }
    std::fflush(stdout);
  }
}

void run_object(benchmark::State& state, int dims, int elements) {
  for (auto _ : state) {
    std::vector<std::string> training, test;
    const analysis::Problem suite = bench_large::suite_problem(dims, elements, training, test);
    const double strains[3] = {0.03, 0.15, 0.30}, degrees[3] = {5, 20, 40};
    std::vector<bench_large::HeldOut> held;
    for (int a = 0; a < 3; ++a)
      held.push_back(bench_large::held_out(suite, test, strains[a], degrees[a]));
    // The net cells of the control net, for V/V0 whatever the model's terms.
    fitting::SpringMeshOptions cell_options;
    cell_options.volume_terms = true;
    const SpringNetwork cells = fitting::build_spring_mesh(suite, cell_options).network;
    // The training cases at %eps_G 20, where the springs-only fit stopped.
    analysis::Problem at20 = suite;
    at20.load_cases.clear();
    for (const auto& lc : suite.load_cases)
      if (std::find(training.begin(), training.end(), lc.id) != training.end())
        at20.load_cases.push_back(lc);
    const std::vector<double> factors = fitting::load_factors_for_eps_g(at20, {}, 20.0);
    for (size_t c = 0; c < factors.size(); ++c)
      at20.load_cases[c] =
          fitting::scaled_load_case(at20.load_cases[c], factors[c], at20.load_cases[c].id + "@20");
    const std::vector<Eigen::VectorXd> at20_references =
        fitting::finite_strain_references(at20, analysis::HyperelasticMaterial::kNeoHookean);
    for (bool terms : {false, true}) {
      fitting::CalibrationSettings settings;
      settings.gamma = 0.2;
      settings.field_metrics = false;
      settings.fit_cases = training;
      settings.mesh.volume_terms = terms;
      settings.mesh.shear_terms = terms;
      std::printf("%dD %s\n", dims, terms ? "springs + volume + shear" : "springs only");
      const fitting::CalibrationResult linear = fitting::calibrate(suite, settings);
      fitting::LargeDeformationSettings large;
      large.amplitudes = {5.0, 20.0};
      const fitting::LargeDeformationResult nonlinear =
          fitting::calibrate_large_deformation(suite, settings, large);
      std::printf("  large deformation: reached %%eps_G %g %s; groups:",
                  nonlinear.reached_amplitude, nonlinear.stopped.c_str());
      for (size_t g = 0; g < nonlinear.fit.group_stiffness.size(); ++g)
        std::printf(" %.3g (linear start %.3g)", nonlinear.fit.group_stiffness[g],
                    nonlinear.start.fit_result.group_stiffness[g]);
      std::printf("\n");
      const SpringModelOnProblem models[2] = {fitting::spring_model_of(suite, linear),
                                              nonlinear.model};
      for (int m = 0; m < 2; ++m)
        diagnose(m ? "large-deformation model, training cases at %eps_G 20"
                   : "linear model, training cases at %eps_G 20",
                 at20, at20_references, models[m], cells);
      for (int m = 0; m < 2; ++m)
        for (int a = 0; a < 3; ++a) {
          const std::string what = std::string(m ? "large-deformation" : "linear") +
                                   " model, held-out amplitude " + std::to_string(a);
          diagnose(what.c_str(), held[static_cast<size_t>(a)].problem,
                   held[static_cast<size_t>(a)].references, models[m], cells);
        }
    }
  }
}

// ---- The square's springs + volume + shear fit: where Levenberg-Marquardt ends against its start.

// The nonlinear objective (1/2 sum of squared residuals, as Ceres reports it) of the first
// `cases` fitted cases at log-stiffnesses theta, every equilibrium from rest; per-case %e_rms
// into `percent`. Infinity when an equilibrium is not found.
double cost_from_rest(const fitting::DisplacementFitData& data, size_t cases,
                      const fitting::Grouping& grouping, const Eigen::VectorXd& theta,
                      std::vector<double>* percent = nullptr) {
  fitting::DisplacementFitData first = data;
  first.loads.resize(cases);
  first.references.resize(cases);
  Eigen::VectorXd r;
  if (!fitting::nonlinear_displacement_residuals(first, grouping, theta, r, nullptr))
    return std::numeric_limits<double>::infinity();
  if (percent) {
    percent->clear();
    const Eigen::Index rows = r.size() / static_cast<Eigen::Index>(cases);
    for (size_t c = 0; c < cases; ++c)
      percent->push_back(100.0 * r.segment(static_cast<Eigen::Index>(c) * rows, rows).norm());
  }
  return 0.5 * r.squaredNorm();
}

Eigen::VectorXd log_of(const std::vector<double>& k) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(k.size()));
  for (size_t g = 0; g < k.size(); ++g) theta[static_cast<Eigen::Index>(g)] = std::log(k[g]);
  return theta;
}

void print_point(const char* label, const fitting::DisplacementFitData& data, size_t per_amplitude,
                 const fitting::Grouping& grouping, const Eigen::VectorXd& theta) {
  std::vector<double> percent;
  std::printf("  %-34s k [", label);
  for (Eigen::Index g = 0; g < theta.size(); ++g) std::printf(" %.3g", std::exp(theta[g]));
  std::printf(" ]\n");
  for (size_t stage = 1; stage * per_amplitude <= data.loads.size(); ++stage) {
    const double cost = cost_from_rest(data, stage * per_amplitude, grouping, theta, &percent);
    std::printf("    cases up to amplitude %zu: cost %.5g, %%e_rms", stage, cost);
    for (double p : percent) std::printf(" %.1f", p);
    std::printf("\n");
  }
  std::fflush(stdout);
}

// The training cases of `suite` scaled to every amplitude (amplitude-major, ids "id@amplitude"),
// as calibrate_large_deformation scales them.
analysis::Problem scaled_training(const analysis::Problem& suite,
                                  const std::vector<std::string>& training,
                                  const std::vector<double>& amplitudes,
                                  const fitting::SpringMeshOptions& mesh) {
  analysis::Problem fitted = suite, scaled = suite;
  fitted.load_cases.clear();
  scaled.load_cases.clear();
  for (const auto& lc : suite.load_cases)
    if (std::find(training.begin(), training.end(), lc.id) != training.end())
      fitted.load_cases.push_back(lc);
  for (double amplitude : amplitudes) {
    const std::vector<double> f = fitting::load_factors_for_eps_g(fitted, mesh, amplitude);
    for (size_t c = 0; c < f.size(); ++c) {
      char id[64];
      std::snprintf(id, sizeof id, "%s@%g", fitted.load_cases[c].id.c_str(), amplitude);
      scaled.load_cases.push_back(fitting::scaled_load_case(fitted.load_cases[c], f[c], id));
    }
  }
  return scaled;
}

void print_fit(const char* label, const fitting::DisplacementFitData& data,
               const fitting::DisplacementFitOptions& options) {
  try {
    const fitting::DisplacementFitResult fit = fitting::fit_displacements_nonlinear(data, options);
    std::printf("    %s: cost %.4g, %d iterations, %d at the lower bound, %%e_rms", label, fit.cost,
                fit.iterations, fit.groups_at_lower_bound);
    for (double p : fit.percent_e_rms) std::printf(" %.1f", p);
    std::printf("\n");
  } catch (const std::exception& e) {
    std::printf("    %s: failed (%s)\n", label, e.what());
  }
  std::fflush(stdout);
}

// The square with volume and shear terms (bench_large_deformation's object): the continuation's
// costs from rest at its two linear starts and its end, the cost along the segment from the
// start to the end, each amplitude's cases fitted alone from several starts, self-weight along
// x at %eps_G 20 fitted alone.
void fit_path(benchmark::State& state) {
  for (auto _ : state) {
    std::vector<std::string> training, test;
    const analysis::Problem suite = bench_large::suite_problem(2, 3, training, test);
    fitting::CalibrationSettings settings;
    settings.gamma = 0.2;
    settings.field_metrics = false;
    settings.fit_cases = training;
    settings.mesh.volume_terms = true;
    settings.mesh.shear_terms = true;
    fitting::LargeDeformationSettings large;
    large.amplitudes = {5.0, 10.0, 20.0};
    const fitting::LargeDeformationResult result =
        fitting::calibrate_large_deformation(suite, settings, large);
    std::printf("  continuation: reached %g %s; started from the %s\n", result.reached_amplitude,
                result.stopped.c_str(),
                result.started_from_linear_references ? "linear references' calibration"
                                                      : "finite-strain references' fit");
    const analysis::Problem scaled =
        scaled_training(suite, training, large.amplitudes, settings.mesh);
    fitting::DisplacementFitData data;
    data.network = result.model.network;
    data.constrained_dofs = result.model.extra_constrained;
    data.particle_of_node = result.model.particle_of_node;
    data.loads = fitting::particle_loads(scaled, result.model);
    data.references =
        fitting::finite_strain_references(scaled, analysis::HyperelasticMaterial::kNeoHookean);
    const size_t per_amplitude = training.size();
    const fitting::Grouping& grouping = result.start.grouping;
    fitting::CalibrationSettings plain = settings;
    plain.fit_cases.clear();
    const fitting::CalibrationResult on_linear = fitting::calibrate(scaled, plain);
    const std::vector<double>* starts[3] = {&result.start.fit_result.group_stiffness,
                                            &on_linear.fit_result.group_stiffness,
                                            &result.fit.group_stiffness};
    const char* start_label[3] = {"finite-strain references' fit", "linear references' calibration",
                                  "continuation's fit"};
    for (int s = 0; s < 3; ++s)
      print_point(start_label[s], data, per_amplitude, grouping, log_of(*starts[s]));
    const Eigen::VectorXd from = log_of(*starts[result.started_from_linear_references ? 1 : 0]);
    const Eigen::VectorXd to = log_of(result.fit.group_stiffness);
    for (size_t stage = 1; stage <= 3; ++stage) {
      std::printf(
          "  cost from rest along the segment start -> continuation's fit, cases up to "
          "amplitude %zu:",
          stage);
      for (int i = 0; i <= 10; ++i)
        std::printf(" %.4g", cost_from_rest(data, stage * per_amplitude, grouping,
                                            from + 0.1 * i * (to - from)));
      std::printf("\n");
    }
    for (size_t k = 0; k < 3; ++k) {
      std::printf("  amplitude %g alone (its %zu cases), from each start:\n", large.amplitudes[k],
                  per_amplitude);
      fitting::DisplacementFitData alone = data;
      alone.loads.assign(data.loads.begin() + k * per_amplitude,
                         data.loads.begin() + (k + 1) * per_amplitude);
      alone.references.assign(data.references.begin() + k * per_amplitude,
                              data.references.begin() + (k + 1) * per_amplitude);
      for (int s = 0; s < 3; ++s) {
        fitting::DisplacementFitOptions options;
        options.grouping = grouping;
        options.initial = *starts[s];
        print_fit(start_label[s], alone, options);
      }
    }
    const size_t gravity_x =
        std::find(training.begin(), training.end(), "gravity_x") - training.begin();
    std::printf("  gravity_x@20 alone, from each start:\n");
    fitting::DisplacementFitData one = data;
    one.loads = {data.loads[2 * per_amplitude + gravity_x]};
    one.references = {data.references[2 * per_amplitude + gravity_x]};
    for (int s = 0; s < 3; ++s) {
      fitting::DisplacementFitOptions options;
      options.grouping = grouping;
      options.initial = *starts[s];
      print_fit(start_label[s], one, options);
    }
  }
}

// The square's continuation (volume and shear terms, %eps_G 5, 10, 20) without the training
// cases `dropped`: where it stops, its fitted cases and the held-out end loads.
void fit_without(benchmark::State& state, std::vector<std::string> dropped) {
  for (auto _ : state) {
    std::vector<std::string> training, test;
    const analysis::Problem suite = bench_large::suite_problem(2, 3, training, test);
    fitting::CalibrationSettings settings;
    settings.gamma = 0.2;
    settings.field_metrics = false;
    settings.mesh.volume_terms = true;
    settings.mesh.shear_terms = true;
    for (const auto& id : training)
      if (std::find(dropped.begin(), dropped.end(), id) == dropped.end())
        settings.fit_cases.push_back(id);
    fitting::LargeDeformationSettings large;
    large.amplitudes = {5.0, 10.0, 20.0};
    std::printf("  continuation without");
    for (const auto& id : dropped) std::printf(" %s", id.c_str());
    try {
      const auto r = fitting::calibrate_large_deformation(suite, settings, large);
      std::printf(": reached %g %s; fitted %%e_rms", r.reached_amplitude, r.stopped.c_str());
      for (const auto& c : r.fitted) std::printf(" %s %.1f", c.id.c_str(), c.control.percent_e_rms);
      std::printf("\n  held out (worst of stretch, bending, in-plane moment):");
      const double strains[3] = {0.03, 0.15, 0.30}, degrees[3] = {5, 20, 40};
      for (int a = 0; a < 3; ++a) {
        const bench_large::HeldOut h = bench_large::held_out(suite, test, strains[a], degrees[a]);
        double worst = 0.0;
        int failed = 0;
        for (const auto& c : fitting::evaluate_large_deformation(h.problem, r.model, h.references))
          c.solved ? void(worst = std::max(worst, c.control.percent_e_rms)) : void(++failed);
        std::printf(" %.2f (%d without equilibrium)", worst, failed);
      }
      std::printf("\n");
    } catch (const std::exception& e) {
      std::printf(": failed: %s\n", e.what());
    }
    std::fflush(stdout);
  }
}

BENCHMARK(fit_path)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(fit_without, gravity_x, std::vector<std::string>{"gravity_x"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(fit_without, gravity, std::vector<std::string>{"gravity_x", "gravity_y"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(fit_without, gravity_x_and_edge_y,
                  std::vector<std::string>{"gravity_x", "p0_v0_y", "p0_v1_y"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

BENCHMARK_CAPTURE(run_object, cube, 3, 1)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(run_object, square, 2, 3)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace isospring

BENCHMARK_MAIN();
