// `isospring analyze CASE.json -o OUTDIR`: the IGA reference solution of every load case.
// Writes OUTDIR/report.json, OUTDIR/report.md, OUTDIR/<id>_control_displacements.csv and
// OUTDIR/result.vtm (ParaView: geometry with displacement, stress, von Mises and strain energy
// density per load case; control net with the control-point displacements).
//
// --backend petsc solves with PETSc on the MPI ranks it is started on (`mpirun -np N isospring
// analyze ...`, analysis/petsc_solver.hpp): every rank reads the case and takes part in the
// solve; rank 0 alone checks the output folder, prints and writes the files.
#include <chrono>
#include <functional>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_solution.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct AnalyzeOptions {
  std::string case_file;
  std::string output;
  std::string solver = "cholesky";
  std::string backend = "serial";
  std::string preconditioner = "gamg";
  double tolerance = 1e-12;
  int vtk_samples = 4;  // 0: no result.vtm
  int threads = 0;
  double max_memory_gb = 0;  // 0: the available memory
  bool quiet = false;
};

nlohmann::json vector_json(const Eigen::Vector3d& v, int dimension) {
  nlohmann::json out = nlohmann::json::array();
  for (int c = 0; c < dimension; ++c) out.push_back(v[c]);
  return out;
}

std::unique_ptr<analysis::PetscSession> start_petsc() {
  try {
    return std::make_unique<analysis::PetscSession>();
  } catch (const nurbs::InputError& e) {
    throw nurbs::InputError(std::string("--backend petsc: ") + e.what());
  }
}

void run_analyze(const AnalyzeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const bool petsc = options.backend == "petsc";
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
    out_dir = output_folder(options.output, {options.case_file},
                            {"report.json", "report.md", "result.vtm"});
  });

  progress("reading " + options.case_file);
  // The memory estimate of read_case_file is the direct solver's (K and its Cholesky factor on
  // one machine); the distributed backend is checked only against an explicit --max-memory.
  const io::Case c = io::read_case_file(
      options.case_file,
      petsc && options.max_memory_gb <= 0 ? io::CaseLimits{} : solve_limits(options.max_memory_gb));
  std::vector<std::string> csv_names;
  for (const auto& load : c.problem.load_cases)
    csv_names.push_back(load.id + "_control_displacements.csv");
  on_root([&] { io::check_outputs_spare_inputs(case_inputs(c), in_folder(out_dir, csv_names)); });
  progress("solving " + std::to_string(c.problem.load_cases.size()) + " load case(s)" +
           (session ? " with PETSc on " + std::to_string(session->size()) + " MPI rank(s)" : ""));
  analysis::StaticResult result;
  if (petsc) {
    analysis::PetscSolverOptions solver;
    solver.preconditioner = options.preconditioner;
    solver.relative_tolerance = options.tolerance;
    solver.threads = options.threads > 0 ? options.threads : 1;
    result = analysis::solve_static_petsc(c.problem, solver);
  } else {
    analysis::SolverOptions solver;
    solver.method = options.solver == "cg" ? analysis::SolverOptions::Method::kConjugateGradient
                                           : analysis::SolverOptions::Method::kCholesky;
    solver.threads = options.threads;
    result = analysis::solve_static(c.problem, solver);
  }
  progress(std::to_string(result.dofs) + " DOFs: assembly " +
           io::format_number(result.assembly_seconds, 3) + " s, " +
           (petsc ? "preconditioner setup " : "factorisation ") +
           io::format_number(result.factorization_seconds, 3) + " s");
  if (!root) return;

  nlohmann::json report = io::report_header("analyze", ISOSPRING_VERSION, options.case_file);
  report["case"] = io::case_summary(c, c.problem);
  report["solver"] = petsc ? "petsc" : options.solver;
  report["backend"] = options.backend;
  if (petsc) {
    report["mpi_ranks"] = result.ranks;
    report["petsc"] = {{"method", result.preconditioner},
                       {"relative_tolerance", options.tolerance}};
  }
  report["dofs"] = result.dofs;
  report["assembly_seconds"] = result.assembly_seconds;
  report["factorization_seconds"] = result.factorization_seconds;
  // The BLAS/LAPACK behind CHOLMOD's factorisation as loaded (the alternatives system or
  // LD_LIBRARY_PATH choose it), which decides the factorisation time.
  const analysis::BlasRuntime blas = analysis::loaded_blas();
  report["blas"] = {{"name", blas.name},     {"library", blas.library}, {"lapack", blas.lapack},
                    {"config", blas.config}, {"threads", blas.threads}, {"loaded", blas.loaded}};

  io::MarkdownReport md;
  md.heading(1, "isospring analyze: " + c.name);
  io::add_case_summary(md, report["case"]);
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < result.load_cases.size(); ++i) {
    const analysis::LoadCaseResult& lc = result.load_cases[i];
    progress("load case " + lc.id + " (" + std::to_string(i + 1) + "/" +
             std::to_string(result.load_cases.size()) +
             "): max |u| = " + io::format_number(lc.max_displacement) + " m");
    const std::string csv = lc.id + "_control_displacements.csv";
    io::write_control_displacements_csv(out_dir / csv, c.problem.patches, lc.control_displacements);
    nlohmann::json entry = {{"id", lc.id},
                            {"max_displacement", lc.max_displacement},
                            {"strain_energy", lc.strain_energy},
                            {"reaction_sum", vector_json(lc.reaction_sum, c.dimension)},
                            {"solve_seconds", lc.solve_seconds},
                            {"control_displacements_file", csv}};
    if (petsc) {
      entry["iterations"] = lc.iterations;
      entry["relative_residual"] = lc.relative_residual;
    }
    report["load_cases"].push_back(std::move(entry));
    std::string reaction;
    for (int d = 0; d < c.dimension; ++d)
      reaction += (d ? ", " : "") + io::format_number(lc.reaction_sum[d]);
    rows.push_back({lc.id, io::format_number(lc.max_displacement),
                    io::format_number(lc.strain_energy), "(" + reaction + ")",
                    io::format_number(lc.solve_seconds, 3), "`" + csv + "`"});
  }

  // One ParaView file for the whole run; the evaluated fields are the library's own
  // post-processing (analysis::evaluate_field) at the sampled parameters. --vtk-samples 0 skips
  // it: at 10^6 DOFs the sampled geometry alone is ~2 x 10^7 points, more memory and time than
  // the distributed solve.
  if (options.vtk_samples > 0) {
    const auto vtk_start = std::chrono::steady_clock::now();
    io::VtkScene scene;
    scene.patches = c.problem.patches;
    scene.fields = io::solution_fields(c.problem, result.load_cases);
    scene.samples_per_element = options.vtk_samples;
    io::write_vtk_scene(out_dir / "result.vtm", scene);
    report["vtk_file"] = "result.vtm";
    report["vtk_seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - vtk_start).count();
  }
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report["total_seconds"] = total;

  md.heading(2, "Results");
  md.table({"load case", "max abs(u) [m]", "strain energy [J]", "reaction sum [N]", "solve [s]",
            "control displacements"},
           rows);
  const std::string method = petsc ? "PETSc " + result.preconditioner + " on " +
                                         std::to_string(result.ranks) + " MPI rank(s)"
                                   : options.solver;
  md.paragraph(
      std::to_string(result.dofs) + " DOFs (" + method + "); assembly " +
      io::format_number(result.assembly_seconds, 3) + " s, " +
      (petsc ? "preconditioner setup " : "factorisation ") +
      io::format_number(result.factorization_seconds, 3) + " s, total " +
      io::format_number(total, 3) + " s; BLAS/LAPACK: " +
      (blas.name.empty() ? std::string("none loaded") : blas.name + " (`" + blas.library + "`)") +
      ". Reaction sums are the forces the supports " +
      "exert (K u - f summed over supported DOFs); they balance the applied loads.");
  if (options.vtk_samples > 0)
    md.paragraph(
        "ParaView: open `result.vtm` (geometry sampled " + std::to_string(options.vtk_samples) +
        " x per element and as exact " +
        std::string("Bezier cells, control net) with `displacement_<id>`, `stress_<id>`, ") +
        "`von_mises_<id>` and `strain_energy_density_<id>` per load case.");
  io::write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  progress("wrote " + (out_dir / "report.json").string() + ", report.md and " +
           std::to_string(result.load_cases.size()) + " displacement table(s)" +
           (options.vtk_samples > 0 ? " and result.vtm" : ""));
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
      "OUTDIR/result.vtm + OUTDIR/result/ (ParaView: sampled and Bezier geometry with\n"
      "displacement_<id>, stress_<id>, von_mises_<id>, strain_energy_density_<id>; control net).\n"
      "Case-file format: README.md, section \"Case files\".");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_option("--solver", options->solver,
                  "cholesky (sparse direct, default) or cg (conjugate gradients)")
      ->check(CLI::IsMember({"cholesky", "cg"}));
  cmd->add_option("--backend", options->backend,
                  "serial (default) or petsc: PETSc with MPI, distributed over the ranks of "
                  "`mpirun -np N isospring analyze ...` (README, \"Running on a cluster\")")
      ->check(CLI::IsMember({"serial", "petsc"}));
  cmd->add_option("--preconditioner", options->preconditioner,
                  "--backend petsc: gamg (smoothed aggregation with the rigid-body modes, "
                  "default), hypre (BoomerAMG) or lu (MUMPS, direct)")
      ->check(CLI::IsMember({"gamg", "hypre", "lu"}));
  cmd->add_option("--tolerance", options->tolerance,
                  "--backend petsc: relative residual ||f - K u|| / ||f|| at which CG stops "
                  "(default 1e-12)")
      ->check(kPositive);
  cmd->add_option("--vtk-samples", options->vtk_samples,
                  "Sample points per element and direction of result.vtm's geometry (default 4; "
                  "0: no result.vtm, for very large models)")
      ->check(kNonNegative);
  cmd->add_option("--threads", options->threads,
                  "Threads for assembly (0 = all; --backend petsc: per rank, default 1)")
      ->check(kNonNegative);
  cmd->add_option("--max-memory", options->max_memory_gb,
                  "Refuse (exit 1) a case whose solve needs more than this many GB (default: the "
                  "available memory)")
      ->check(kPositive);
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_analyze(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(40, setup_analyze);
}  // namespace isospring::apps
