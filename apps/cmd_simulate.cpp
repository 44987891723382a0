// `isospring simulate MODEL.json -o OUTDIR --dt DT [--steps N] [--every K] [--load-case ID]
// [--gravity gx,gy,gz] [--integrator implicit|verlet|reduced]`: a dynamic run of a spring model
// from rest under a constant load (a model.json load case and/or gravity), written as a ParaView
// time series OUTDIR/series.pvd (one .vtp per frame in OUTDIR/series/ with "displacement" and
// "velocity") plus OUTDIR/report.json comparing the last frame with the static equilibrium of
// the same load (analysis::solve_spring_newton), which a damped run approaches ("static": null
// when the network is a mechanism at rest and Newton has no linear start). The work is
// workflows::run_simulate (isospring/workflows/simulate_command.hpp).
#include <chrono>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/simulate_command.hpp"

namespace isospring::apps {
namespace {

struct SimulateOptions {
  std::string output;
  bool quiet = false;
  workflows::SimulateCommandOptions run;
};

void run_simulate(const SimulateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const io::Progress progress("simulate", options.quiet);
  const std::filesystem::path out_dir =
      output_folder(options.output, {options.run.model_file}, {"series.pvd", "report.json"});
  nlohmann::json report = workflows::run_simulate(options.run, out_dir, progress);
  report["total_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::write_json_report(out_dir / "report.json", report);
  const nlohmann::json& equilibrium = report["static"];
  progress("wrote " + (out_dir / "series.pvd").string() + " (" + report["frames"].dump() +
           " frames); last frame max |u| " +
           io::format_number(report["final_max_displacement"].get<double>()) + " m" +
           (equilibrium.is_null()
                ? std::string()
                : ", static " + io::format_number(equilibrium["max_displacement"].get<double>()) +
                      " m"));
}

void setup_simulate(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run a spring model (model.json) dynamically from rest; ParaView time series");
  cmd->add_option("MODEL", options->run.model_file, "Spring model (model.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_option("--dt", options->run.dt, "Time step [s]")->required();
  cmd->add_option("--steps", options->run.steps, "Number of time steps")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--every", options->run.every, "Write every K-th step as a frame (and the last)")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--load-case", options->run.load_case,
                  "A load case of model.json (its forces plus the model's gravity; default: the "
                  "first, unless --gravity is given)");
  cmd->add_option("--gravity", options->run.gravity,
                  "Gravity gx,gy,gz [m/s^2]; replaces the model's (default: the model's)");
  cmd->add_option("--integrator", options->run.integrator,
                  "implicit (backward Euler: stable, dissipative), verlet (explicit, "
                  "symplectic: dt below the stability limit) or reduced (the lowest --modes "
                  "modes plus the load's static shape: O(r^2) a step, docs/reduced_model.md)")
      ->capture_default_str()
      ->check(CLI::IsMember({"implicit", "verlet", "reduced"}));
  cmd->add_option("--modes", options->run.modes,
                  "reduced: lowest natural modes in the basis; the report gives the error "
                  "against the full network")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->footer(
      "Writes OUTDIR/series.pvd + OUTDIR/series/frame_NNNNNN.vtp (the network at its deformed\n"
      "positions with displacement and velocity per particle, one file per frame, frame 0 at\n"
      "rest) and OUTDIR/report.json (last frame against the static equilibrium of the same load).\n"
      "Exit status 3 when the run diverges or a Newton step fails.");
  cmd->callback([options] { run_simulate(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(82, setup_simulate);
}  // namespace isospring::apps
