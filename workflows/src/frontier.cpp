// run_frontier (frontier.hpp): per object, the IGA reference once, every network kind
// calibrated and measured, the reduced model of the most accurate, the Pareto set.
#include "isospring/workflows/frontier.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "frontier_stages.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/pareto.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {

namespace {

const std::vector<std::string> kObjects = {"square", "circle", "ellipse",
                                           "cube",   "torus",  "coupled_spheroid"};

std::string first_line_with(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (key.empty() || line.rfind(key, 0) == 0) return line;
  return "";
}

std::string load_average() {
  std::istringstream in(first_line_with("/proc/loadavg", ""));
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

std::string machine_at_start() {
  std::string cpu = first_line_with("/proc/cpuinfo", "model name");
  if (const size_t colon = cpu.find(':'); colon != std::string::npos) cpu = cpu.substr(colon + 2);
  return (cpu.empty() ? std::string("unknown CPU") : cpu) + ", " +
         std::to_string(std::thread::hardware_concurrency()) +
         " hardware threads; step times in CPU time of one thread; load average (1, 5, 15 min) "
         "at the start " +
         load_average();
}

// Runs one object into result.objects.back(), calling options.on_object after every kind (the
// object marked incomplete until its last).
void run_object(const std::string& name, const std::vector<FrontierKind>& kinds,
                const FrontierOptions& options, const io::Progress& progress,
                FrontierResult& result) {
  const auto start = std::chrono::steady_clock::now();
  frontier::ObjectSetup setup{fitting::thesis_object(name), {}, {}};
  setup.suite = fitting::thesis_load_suite(setup.object);
  progress(name + ": IGA reference of " + std::to_string(setup.suite.problem.load_cases.size()) +
           " load cases (" + std::to_string(setup.suite.training.size()) + " training, " +
           std::to_string(setup.suite.validation.size()) + " validation)");
  for (auto& lc : analysis::solve_static(setup.suite.problem).load_cases)
    setup.reference.push_back(std::move(lc.displacement));

  result.objects.emplace_back();
  FrontierObject& object = result.objects.back();
  object.name = name;
  object.training_cases = setup.suite.training.size();
  object.validation_cases = setup.suite.validation.size();
  object.published_e_rms = setup.object.published_e_rms;
  std::optional<fitting::CalibrationResult> best;
  int best_row = -1;
  auto report = [&] {
    frontier::mark_pareto(object);
    object.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.on_object) options.on_object(result);
  };
  for (const FrontierKind& kind : kinds) {
    if (kind.reduced) continue;
    std::optional<fitting::CalibrationResult> calibration;
    object.rows.push_back(frontier::calibrate_kind(setup, kind, options, progress, calibration));
    const FrontierRow& row = object.rows.back();
    if (calibration &&
        (best_row < 0 || row.worst_validation < object.rows[best_row].worst_validation)) {
      best_row = static_cast<int>(object.rows.size()) - 1;
      best = std::move(calibration);
    }
    report();
  }
  for (const FrontierKind& kind : kinds) {
    if (!kind.reduced) continue;
    FrontierRow row;
    try {
      if (!best) throw std::runtime_error("no network kind was calibrated");
      row =
          frontier::reduced_row(setup, *best, object.rows[static_cast<size_t>(best_row)], options);
      progress(name + ": reduced model (r = " + std::to_string(row.reduced_basis) + ") of " +
               row.reduced_of + ": worst held-out %e_rms " +
               io::format_number(row.worst_validation, 3) + ", step " +
               io::format_number(row.measured_step_us, 3) + " us measured");
    } catch (const std::runtime_error& e) {
      row.kind = kind;
      row.failure = e.what();
      row.worst_validation = row.worst_fitted = row.cross_validation_worst = NAN;
      row.measured_step_us = row.estimated_step_us = NAN;
      progress(name + ": reduced model failed (" + row.failure + ")");
    }
    object.rows.push_back(row);
  }
  object.complete = true;
  report();
}

}  // namespace

namespace frontier {

void mark_pareto(FrontierObject& object) {
  std::vector<fitting::CostError> points;
  for (const FrontierRow& row : object.rows)
    points.push_back({row.failure.empty() ? row.measured_step_us : NAN, row.worst_validation});
  const std::vector<bool> optimal = fitting::pareto_optimal(points);
  for (size_t i = 0; i < object.rows.size(); ++i) object.rows[i].pareto = optimal[i];
}

}  // namespace frontier

std::vector<FrontierKind> frontier_kinds() {
  return {{"springs", false, false, 0, false},
          {"springs + volume terms", true, false, 0, false},
          {"springs + volume + shear terms", true, true, 0, false},
          {"springs + strain points 1/dir", false, false, 1, false},
          {"springs + strain points 2/dir", false, false, 2, false},
          {"springs + strain points 3/dir", false, false, 3, false},
          {"reduced", false, false, 0, true}};
}

FrontierResult run_frontier(const FrontierOptions& options, const io::Progress& progress) {
  for (const std::string& name : options.objects)
    if (std::find(kObjects.begin(), kObjects.end(), name) == kObjects.end())
      throw nurbs::InputError("frontier: no object '" + name +
                              "'; use square, circle, ellipse, cube, torus or coupled_spheroid");
  const std::vector<FrontierKind> kinds = options.kinds.empty() ? frontier_kinds() : options.kinds;
  if (std::none_of(kinds.begin(), kinds.end(), [](const FrontierKind& k) { return !k.reduced; }))
    throw nurbs::InputError(
        "frontier: give at least one network kind (the reduced model reduces one)");
  FrontierResult result;
  result.machine = machine_at_start();
  for (const std::string& name : kObjects) {
    if (!options.objects.empty() &&
        std::find(options.objects.begin(), options.objects.end(), name) == options.objects.end())
      continue;
    run_object(name, kinds, options, progress, result);
  }
  result.machine += "; at the end " + load_average();
  return result;
}

}  // namespace isospring::workflows
