// run_simulate: the dynamic run of `isospring simulate` (see simulate_command.hpp).
#include <cmath>
#include <optional>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/io/vtk_time_series.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/simulate_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

// The last frame is "settled" within this fraction of the static solution's largest displacement.
constexpr double kSettledTolerance = 1e-3;

/// The constant external force: the chosen load case's forces (with the model's gravity); without
/// --load-case and --gravity, the model's first load case (calibrate and demo store the loads the
/// springs were fitted under); with --gravity alone, the gravity forces alone. --gravity replaces
/// the model's gravity.
Eigen::VectorXd external_force(SpringModel& model, SimulateCommandOptions& options) {
  if (options.load_case.empty() && options.gravity.empty() && !model.load_cases.empty())
    options.load_case = model.load_cases.front().id;
  if (!options.gravity.empty()) {
    const std::vector<double> g = parse_number_list(options.gravity, "--gravity");
    if (g.size() != 3) throw nurbs::InputError("--gravity: give three numbers gx,gy,gz in m/s^2");
    model.gravity = {g[0], g[1], g[2]};
  }
  const analysis::SpringNetwork& net = model.network;
  if (!options.load_case.empty()) {
    for (size_t k = 0; k < model.load_cases.size(); ++k)
      if (model.load_cases[k].id == options.load_case) return model_force_vector(model, k, true);
    std::string ids;
    for (const auto& lc : model.load_cases) ids += (ids.empty() ? "" : ", ") + lc.id;
    throw nurbs::InputError(
        "--load-case " + options.load_case + ": " + options.model_file +
        (ids.empty() ? " has no load cases; use --gravity" : " has the load cases " + ids));
  }
  const int dim = net.dimension;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.positions.size()) * dim);
  for (size_t i = 0; i < net.positions.size(); ++i)
    if (!net.fixed[i])
      for (int c = 0; c < dim; ++c)
        f(static_cast<Eigen::Index>(i) * dim + c) = net.masses[i] * model.gravity[c];
  return f;
}

std::vector<Eigen::Vector3d> per_particle(const Eigen::VectorXd& flat, int dim) {
  std::vector<Eigen::Vector3d> out(static_cast<size_t>(flat.size() / dim), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < dim; ++c) out[i][c] = flat(static_cast<Eigen::Index>(i) * dim + c);
  return out;
}

double max_norm(const Eigen::VectorXd& flat, int dim) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < flat.size() / dim; ++i)
    m = std::max(m, flat.segment(i * dim, dim).norm());
  return m;
}

}  // namespace

nlohmann::json run_simulate(const SimulateCommandOptions& given,
                            const std::filesystem::path& out_dir, const Progress& progress) {
  if (!(given.dt > 0.0) || !std::isfinite(given.dt))
    throw nurbs::InputError("--dt: must be a positive time step in s");
  SpringModel model = read_model_json(given.model_file);
  SimulateCommandOptions run = given;  // external_force settles the load case
  const SimulateCommandOptions& options = run;
  const Eigen::VectorXd force = external_force(model, run);
  if (force.norm() == 0.0)
    throw nurbs::InputError("no load: nothing would move; give --load-case ID (" +
                            options.model_file + " load cases) or --gravity gx,gy,gz");
  const analysis::SpringNetwork& net = model.network;
  const int dim = net.dimension;
  analysis::SpringState state = analysis::rest_state(net);
  analysis::check_dynamics_input(net, state);
  const Eigen::VectorXd rest = state.x;
  const bool implicit = options.integrator == "implicit";
  // The reduced model: the lowest modes plus this load's static shape (exact static response).
  std::optional<analysis::ReducedSpringModel> reduced;
  Eigen::VectorXd reduced_force;
  if (options.integrator == "reduced") {
    analysis::ReducedModelOptions ro;
    ro.modes = options.modes;
    ro.load_shapes = {force};
    reduced.emplace(net, options.dt, ro);
    reduced_force = reduced->reduce_force(force);
    progress("reduced model: " + std::to_string(reduced->size()) + " basis vectors (" +
             std::to_string(options.modes) + " modes + the load's static shape)");
  }

  if (!options.load_case.empty()) {
    std::string others;
    for (const auto& lc : model.load_cases)
      if (lc.id != options.load_case) others += (others.empty() ? "" : ", ") + lc.id;
    progress("load case " + options.load_case +
             (others.empty() ? std::string() : " (others, --load-case: " + others + ")"));
  }
  progress(std::to_string(options.steps) + " " + options.integrator + " steps of " +
           format_number(options.dt) + " s on " + std::to_string(net.positions.size()) +
           " particles");
  SpringTimeSeriesWriter series(out_dir / "series.pvd", net);
  series.add_frame(0.0, per_particle(state.x - rest, dim), per_particle(state.v, dim));
  for (int step = 1; step <= options.steps; ++step) {
    const bool frame = step % options.every == 0 || step == options.steps;
    if (reduced) {
      reduced->step(reduced_force);
      // The field costs O(n r): expanded only for the frames written (the last one included).
      if (frame) {
        state.x = rest + reduced->displacement();
        state.v = reduced->basis() * reduced->velocities();
      }
    } else if (implicit)
      analysis::step_backward_euler(net, state, force, options.dt);
    else
      analysis::step_velocity_verlet(net, state, force, options.dt);
    const bool finite =
        reduced ? reduced->coordinates().allFinite() && reduced->velocities().allFinite()
                : state.x.allFinite() && state.v.allFinite();
    if (!finite)
      throw std::runtime_error("the run diverged at step " + std::to_string(step) +
                               " (t = " + format_number(step * options.dt) +
                               " s): reduce --dt below the explicit stability limit or use "
                               "--integrator implicit");
    if (frame)
      series.add_frame(step * options.dt, per_particle(state.x - rest, dim),
                       per_particle(state.v, dim));
  }
  series.finish();

  // The static equilibrium under the same load: where a damped run ends. Best effort: a network
  // that is a mechanism at rest (a hanging chain has no lateral stiffness) has no linear start.
  const Eigen::VectorXd final_u = state.x - rest;
  nlohmann::json comparison = nullptr;
  try {
    analysis::SpringSolveOptions solve;
    solve.load_steps = 4;
    const analysis::SpringSolveResult eq = analysis::solve_spring_newton(net, force, solve);
    const double static_max = max_norm(eq.displacement, dim);
    comparison = {{"max_displacement", static_max},
                  {"converged", eq.converged},
                  {"final_minus_static_relative",
                   max_norm(final_u - eq.displacement, dim) / std::max(static_max, 1e-300)}};
  } catch (const std::runtime_error& e) {
    progress.warn(std::string("no static equilibrium to compare with: ") + e.what());
  }
  // A run meant to settle that has not: say how to make it (the series is still written).
  if (!comparison.is_null() && comparison["converged"].get<bool>() &&
      comparison["final_minus_static_relative"].get<double>() > kSettledTolerance)
    progress.warn("the last frame has not settled: it is " +
                  format_number(100 * comparison["final_minus_static_relative"].get<double>(), 3) +
                  " % (of the static max |u|) from the static equilibrium; run longer (--steps) "
                  "or, with --integrator implicit, with a larger --dt (more numerical damping)");
  nlohmann::json report = report_header("simulate", isospring_version(), options.model_file);
  report["integrator"] = options.integrator;
  report["dt"] = options.dt;
  report["steps"] = options.steps;
  report["frames"] = series.frames();
  report["final_time"] = options.steps * options.dt;
  report["load_case"] =
      options.load_case.empty() ? nlohmann::json(nullptr) : nlohmann::json(options.load_case);
  report["gravity"] = {model.gravity.x(), model.gravity.y(), model.gravity.z()};
  report["final_max_displacement"] = max_norm(final_u, dim);
  report["final_max_speed"] = max_norm(state.v, dim);
  report["static"] = comparison;
  if (reduced) {
    // The same load and steps on the full network (analysis::reduction_error): what the
    // reduction costs, measured, not assumed.
    const analysis::ReductionError e =
        analysis::reduction_error(net, *reduced, force, options.steps);
    const auto finite = [](double x) {
      return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
    };
    report["reduced"] = {{"modes", options.modes},
                         {"basis_size", reduced->size()},
                         {"static_relative", e.static_relative},
                         {"projection_relative", e.projection_relative},
                         {"dynamic_relative", finite(e.dynamic_relative)},
                         {"dynamic_max", finite(e.dynamic_max)},
                         {"full_network_diverged", e.exact_diverged}};
    progress("reduced model against the full network over the same steps: " +
             format_number(100 * e.projection_relative, 3) + " % (linearised), " +
             (e.exact_diverged ? std::string("the full network's run diverged")
                               : format_number(100 * e.dynamic_relative, 3) + " % (exact forces)"));
  }
  report["warnings"] = progress.warnings();
  report["series_file"] = "series.pvd";
  return report;
}

}  // namespace isospring::workflows
