#pragma once
// The use case behind `isospring simulate` as one library call: a dynamic run of a spring model
// from rest under a constant load (a model.json load case and/or gravity), written as a ParaView
// time series OUT/series.pvd (one .vtp per frame in OUT/series/ with "displacement" and
// "velocity") while it runs, and compared at the end with the static equilibrium of the same load
// (analysis::solve_spring_newton), which a damped run approaches.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "isospring/io/model_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct SimulateCommandOptions {
  double dt = 0.0;  // [s], > 0
  int steps = 100;
  int every = 1;  // a frame every `every` steps (and the last)
  /// A load case of the model (its forces plus the model's gravity); empty: the model's first
  /// load case, unless `gravity` is given (then the gravity forces alone).
  std::string load_case;
  std::string gravity;  // "gx,gy,gz" [m/s^2]: replaces the model's gravity
  /// implicit | verlet | reduced (analysis::ReducedSpringModel: `modes` lowest modes plus the
  /// load's static shape, stepped in that subspace; the report gets its error against the full
  /// network under the same load and steps)
  std::string integrator = "implicit";
  int modes = 32;
  std::string model_file;  // the spring model (model.json)
};

/// Reads the model, runs, writes OUT/series.pvd and its frames and returns report.json's content
/// (the caller writes it and adds "total_seconds"). Throws nurbs::InputError for bad options or
/// no load, std::runtime_error when the run diverges.
nlohmann::json run_simulate(const SimulateCommandOptions& options,
                            const std::filesystem::path& out_dir, const io::Progress& progress);

}  // namespace isospring::workflows
