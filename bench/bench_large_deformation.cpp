// What large-deformation calibration buys: a 10 cm cube (3^3 control net; and a 10 cm square in
// plane strain, 5^2)
// clamped on x = 0, spring models calibrated (a) linearly as `calibrate` does and (b) on the
// load suite at %eps_G 5, 10 and 20 against neo-Hookean references, with the nonlinear spring
// equilibrium as the model's response. Held out: the free end's stretch, bending and twist
// (2D: in-plane moment), never fitted, at three amplitudes (end strain 3 / 15 / 30 %, end
// rotation 5 / 20 / 40 degrees, each scaled by the linear solution and then solved by the
// neo-Hookean IGA). Prints the table of docs/calibration.md; one iteration per object.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/fitting/large_deformation_calibration.hpp"
#include "isospring/fitting/load_suite.hpp"
#include "large_deformation_models.hpp"

namespace isospring {
namespace {

using bench_large::HeldOut;
using fitting::SpringModelOnProblem;

// Worst %e_rms over the held-out loads with an equilibrium; counts those without one and those
// whose equilibrium inverts a net cell (V/V0 <= 0: the net folded through itself).
double worst(const HeldOut& h, const SpringModelOnProblem& model, int& failures, int& inverted) {
  fitting::SpringMeshOptions cell_options;
  cell_options.volume_terms = true;
  const auto cells = fitting::build_spring_mesh(h.problem, cell_options).network.volumes;
  const analysis::DofMap dofs(h.problem);
  double w = 0;
  const auto cases = fitting::evaluate_large_deformation(h.problem, model, h.references);
  for (size_t c = 0; c < cases.size(); ++c) {
    if (!cases[c].solved) {
      ++failures;
      continue;
    }
    w = std::max(w, cases[c].control.percent_e_rms);
    std::printf("    [%s %.2f]", cases[c].id.c_str(), cases[c].control.percent_e_rms);
    // The equilibrium's particle positions from the node errors and the reference.
    const Eigen::VectorXd x0 = analysis::flat_positions(model.network);
    Eigen::VectorXd x = x0;
    const int dim = model.network.dimension;
    for (size_t a = 0; a < model.particle_of_node.size(); ++a) {
      Eigen::VectorXd u = h.references[c].segment(static_cast<Eigen::Index>(a) * dim, dim);
      u += cases[c].node_error[a].head(dim);
      x.segment(model.particle_of_node[a] * dim, dim) =
          x0.segment(model.particle_of_node[a] * dim, dim) + u;
    }
    double ratio = 1.0;
    for (const auto& t : cells)
      ratio = std::min(ratio, analysis::cell_volume(t, x, dim) / t.rest_volume);
    if (!(ratio > 0.0)) ++inverted;
  }
  return w;
}

void run_object(benchmark::State& state, int dims, int elements) {
  for (auto _ : state) {
    std::vector<std::string> training, test;
    const analysis::Problem suite = bench_large::suite_problem(dims, elements, training, test);
    const char* label[3] = {"small", "medium", "large"};
    const double strains[3] = {0.03, 0.15, 0.30}, degrees[3] = {5, 20, 40};
    std::vector<HeldOut> held;
    for (int a = 0; a < 3; ++a) {
      held.push_back(bench_large::held_out(suite, test, strains[a], degrees[a]));
      std::printf("held-out %s: %s\n", label[a], held.back().measured.c_str());
      std::fflush(stdout);
    }
    for (bool terms : {false, true}) {
      fitting::CalibrationSettings settings;
      settings.gamma = 0.2;
      settings.field_metrics = false;
      settings.fit_cases = training;
      settings.mesh.volume_terms = terms;
      settings.mesh.shear_terms = terms;
      auto t0 = std::chrono::steady_clock::now();
      const fitting::CalibrationResult linear = fitting::calibrate(suite, settings);
      const double linear_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fitting::LargeDeformationSettings large;
      large.amplitudes = {5.0, 10.0, 20.0};
      t0 = std::chrono::steady_clock::now();
      std::vector<SpringModelOnProblem> models = {fitting::spring_model_of(suite, linear)};
      std::string failure;
      try {
        const fitting::LargeDeformationResult nonlinear =
            fitting::calibrate_large_deformation(suite, settings, large);
        models.push_back(nonlinear.model);
        if (!nonlinear.stopped.empty()) std::printf("  (large: %s)\n", nonlinear.stopped.c_str());
        std::printf("  (large: groups");
        for (size_t g = 0; g < nonlinear.fit.group_stiffness.size(); ++g)
          std::printf(" %.3g (start %.3g, linear %.3g)", nonlinear.fit.group_stiffness[g],
                      nonlinear.start.fit_result.group_stiffness[g],
                      linear.fit_result.group_stiffness[g]);
        std::printf("; %d at the lower bound; started from the %s; fitted %%e_rms per case:",
                    nonlinear.fit.groups_at_lower_bound,
                    nonlinear.started_from_linear_references ? "linear references' calibration"
                                                             : "finite-strain references' fit");
        for (const auto& c : nonlinear.fitted)
          std::printf(" %s %.1f", c.id.c_str(), c.control.percent_e_rms);
        std::printf(")\n");
        std::printf("  (large: %d fitted cases, references %.1f s, fit %.1f s, %d iterations)\n",
                    static_cast<int>(nonlinear.fitted.size()), nonlinear.reference_seconds,
                    nonlinear.fit_seconds, nonlinear.fit.iterations);
      } catch (const std::exception& e) {
        failure = e.what();
      }
      const double large_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double seconds[2] = {linear_s, large_s};
      for (int m = 0; m < 2; ++m) {
        std::printf("| %dD %d^%d %s | %s | %d |", dims, elements + 2, dims,
                    terms ? "springs + volume + shear" : "springs only",
                    m ? "large deformation" : "linear", linear.parameters);
        if (m >= static_cast<int>(models.size())) {
          std::printf(" failed: %s |\n", failure.c_str());
          continue;
        }
        int failures = 0, inverted = 0;
        for (int a = 0; a < 3; ++a)
          std::printf(" %.2f |", worst(held[a], models[m], failures, inverted));
        std::printf(" %.1f s | %d without equilibrium, %d with an inverted net cell |\n",
                    seconds[m], failures, inverted);
        std::fflush(stdout);
      }
    }
    std::fflush(stdout);
  }
}

BENCHMARK_CAPTURE(run_object, cube, 3, 1)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(run_object, square, 2, 3)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace isospring

BENCHMARK_MAIN();
