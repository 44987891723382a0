// `isospring analyze CASE.json -o OUTDIR`: the IGA reference solution of every load case.
// Writes OUTDIR/report.json, OUTDIR/report.md, OUTDIR/<id>_control_displacements.csv and
// OUTDIR/result.vtm (ParaView: geometry with displacement, stress, von Mises and strain energy
// density per load case; control net with the control-point displacements).
//
// --backend petsc solves with PETSc on the MPI ranks it is started on (`mpirun -np N isospring
// analyze ...`, analysis/petsc_solver.hpp): every rank reads the case and takes part in the
// solve; rank 0 alone checks the output folder, prints and writes the files.
// The work is workflows::run_analyze and workflows::write_analyze_outputs
// (isospring/workflows/analyze_command.hpp).
#include <chrono>
#include <functional>
#include <iostream>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/io/analyze_timings.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/analyze_command.hpp"

namespace isospring::apps {
namespace {

struct AnalyzeOptions {
  std::string output;
  double max_memory_gb = 0;  // 0: the available memory
  bool quiet = false;
  bool timings = false;
  workflows::AnalyzeCommandOptions run;
};

std::unique_ptr<analysis::PetscSession> start_petsc() {
  try {
    return std::make_unique<analysis::PetscSession>();
  } catch (const nurbs::InputError& e) {
    throw nurbs::InputError(std::string("--backend petsc: ") + e.what());
  }
}

void run_analyze(const AnalyzeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const bool petsc = options.run.backend == "petsc";
  // MPI starts only for the PETSc backend: a serial run needs neither mpirun nor MPI.
  const std::unique_ptr<analysis::PetscSession> session = petsc ? start_petsc() : nullptr;
  const bool root = !session || session->rank() == 0;
  auto on_root = [&](const std::function<void()>& step) {
    if (session)
      session->on_root(step);
    else
      step();
  };
  const io::Progress progress("analyze", options.quiet || !root);
  std::filesystem::path out_dir;
  on_root([&] {
    out_dir = output_folder(options.output, {options.run.case_file},
                            {"report.json", "report.md", "result.vtm", "result.vtp"});
  });
  workflows::AnalyzeCommandOptions run = options.run;
  // The memory estimate of read_case_file is the direct solver's (K and its Cholesky factor on
  // one machine); the distributed backend is checked only against an explicit --max-memory.
  run.limits =
      petsc && options.max_memory_gb <= 0 ? io::CaseLimits{} : solve_limits(options.max_memory_gb);
  // Every rank reads and solves; rank 0 checks before the solve that no output overwrites an
  // input.
  const workflows::AnalyzeCommandResult r =
      workflows::run_analyze(run, progress, [&](const io::Case& c) {
        on_root([&] {
          io::check_outputs_spare_inputs(case_inputs(c),
                                         in_folder(out_dir, workflows::analyze_csv_names(c)));
        });
      });
  if (!root) return;
  const nlohmann::json report = workflows::write_analyze_outputs(r, run, out_dir, progress, start);
  if (options.timings && report.contains("timings"))
    std::cout << io::timings_table(report.at("timings"), report.at("total_seconds").get<double>());
}

void setup_analyze(CLI::App& app) {
  auto options = std::make_shared<AnalyzeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "analyze",
      "Solve every load case of a case file with isogeometric linear elasticity (the reference)");
  cmd->footer(
      "Writes OUTDIR/report.json (per load case: max displacement, strain energy, reaction sum,\n"
      "timings; DOFs; the BLAS/LAPACK library loaded; inputs summary), OUTDIR/report.md and\n"
      "OUTDIR/<load-case-id>_control_displacements.csv (i,x,y,z,ux,uy,uz per control point) and\n"
      "OUTDIR/result.vtm + OUTDIR/result/ (ParaView: the exact Bezier geometry with\n"
      "displacement_<id>; the sampled outer surface (3D) or surface (2D) with displacement_<id>,\n"
      "stress_<id>, von_mises_<id>, strain_energy_density_<id>; control net). report.json\n"
      "\"timings\": seconds per stage and per output file (--timings prints them).\n"
      "Case-file format: docs/case-files.md.");
  cmd->add_option("CASE", options->run.case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_option("--solver", options->run.solver,
                  "auto (default: sparse Cholesky up to 20,000 free DOFs in 3D, 500,000 in 2D; "
                  "above, the cheapest by an estimate from the size, the load cases, nu and the "
                  "aspect ratio; report.json solver_reason gives the numbers), cholesky (sparse "
                  "direct), cg (block-Jacobi conjugate gradients) or amg (CG with PETSc's "
                  "algebraic multigrid on this process, no mpirun)")
      ->check(CLI::IsMember({"auto", "cholesky", "cg", "amg"}));
  cmd->add_option("--backend", options->run.backend,
                  "serial (default) or petsc: PETSc with MPI, distributed over the ranks of "
                  "`mpirun -np N isospring analyze ...` (docs/cluster.md)")
      ->check(CLI::IsMember({"serial", "petsc"}));
  cmd->add_option("--preconditioner", options->run.preconditioner,
                  "--backend petsc: gamg (smoothed aggregation with the rigid-body modes, "
                  "default), hypre (BoomerAMG) or lu (MUMPS, direct)")
      ->check(CLI::IsMember({"gamg", "hypre", "lu"}));
  cmd->add_option("--tolerance", options->run.tolerance,
                  "--backend petsc: relative residual ||f - K u|| / ||f|| at which CG stops "
                  "(default 1e-12)")
      ->check(kPositive);
  cmd->add_option("--vtk-samples", options->run.vtk_samples,
                  "Also write the volume sampled N x N x N per element with the stresses "
                  "(3D; 2D: the surface, default 4). Default: the case file's output.vtk_samples, "
                  "else none in 3D (the exact Bezier volume and the sampled outer surface show "
                  "the result at a size in proportion to the model). 0: no result.vtm")
      ->check(kNonNegative);
  cmd->add_option("--threads", options->run.threads,
                  "Threads for assembly (0 = all; --backend petsc: per rank, default 1)")
      ->check(kNonNegative);
  cmd->add_option("--max-memory", options->max_memory_gb,
                  "Refuse (exit 1) a case whose solve needs more than this many GB (default: the "
                  "available memory)")
      ->check(kPositive);
  cmd->add_flag("--timings", options->timings,
                "Print the seconds of every stage (reading, refinement, assembly, factorisation "
                "or preconditioner setup, solves, post-processing, each output file) on stdout");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_analyze(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(40, setup_analyze);
}  // namespace isospring::apps
