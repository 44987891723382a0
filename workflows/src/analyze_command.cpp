// run_analyze and its outputs (see analyze_command.hpp).
#include "isospring/workflows/analyze_command.hpp"

#include "analyze_vtk.hpp"
#include "isospring/analysis/petsc_solver.hpp"
#include "isospring/io/analyze_timings.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/analyze_immersed.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

nlohmann::json vector_json(const Eigen::Vector3d& v, int dimension) {
  nlohmann::json out = nlohmann::json::array();
  for (int c = 0; c < dimension; ++c) out.push_back(v[c]);
  return out;
}

analysis::SolverOptions::Method solver_method(const std::string& name) {
  using Method = analysis::SolverOptions::Method;
  if (name == "auto") return Method::kAuto;
  if (name == "cholesky") return Method::kCholesky;
  if (name == "cg") return Method::kConjugateGradient;
  if (name == "amg") return Method::kAmg;
  throw nurbs::InputError("analyze: unknown solver \"" + name + "\" (auto, cholesky, cg or amg)");
}

/// The immersed path (analyze_immersed.hpp) when the case's geometry is {"type": "immersed"}.
bool run_immersed_if_asked(const AnalyzeCommandOptions& options, const Progress& progress,
                           const std::function<void(const Case&)>& before_solve,
                           AnalyzeCommandResult& r) {
  const nlohmann::json document = parse_json_text(read_text_file(options.case_file, "case file"),
                                                  options.case_file, "case file");
  if (!is_immersed_case(document)) return false;
  if (options.backend != "serial")
    throw nurbs::InputError("analyze: --backend " + options.backend +
                            ": an immersed case is solved serially; drop --backend");
  const ImmersedCase ic = read_immersed_case(options.case_file);
  r.c.name = ic.name;
  r.c.file = ic.file;
  r.c.raw = ic.raw;
  if (before_solve) before_solve(r.c);
  r.immersed = std::make_shared<const ImmersedAnalysis>(
      run_analyze_immersed(ic, solver_method(options.solver), progress));
  return true;
}

}  // namespace

std::string solver_name(analysis::SolverOptions::Method method) {
  using Method = analysis::SolverOptions::Method;
  return method == Method::kConjugateGradient ? "cg"
         : method == Method::kAuto            ? "auto"
         : method == Method::kAmg             ? "amg"
                                              : "cholesky";
}

AnalyzeCommandResult run_analyze(const AnalyzeCommandOptions& options, const Progress& progress,
                                 const std::function<void(const Case&)>& before_solve) {
  const bool petsc = options.backend == "petsc";
  progress("reading " + options.case_file);
  AnalyzeCommandResult r;
  const auto read_start = std::chrono::steady_clock::now();
  if (run_immersed_if_asked(options, progress, before_solve, r)) return r;
  r.c = read_case_file(options.case_file, options.limits);
  r.read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
  if (before_solve) before_solve(r.c);
  progress("solving " + std::to_string(r.c.problem.load_cases.size()) + " load case(s)" +
           (petsc ? " with PETSc" : ""));
  if (petsc) {
    analysis::PetscSolverOptions solver;
    solver.preconditioner = options.preconditioner;
    solver.relative_tolerance = options.tolerance;
    solver.threads = options.threads > 0 ? options.threads : 1;
    r.result = analysis::solve_static_petsc(r.c.problem, solver);
  } else {
    analysis::SolverOptions solver;
    solver.method = solver_method(options.solver);
    solver.threads = options.threads;
    r.result = analysis::solve_static(r.c.problem, solver);
  }
  r.blas = analysis::loaded_blas();
  progress(std::to_string(r.result.dofs) + " DOFs: assembly " +
           format_number(r.result.assembly_seconds, 3) + " s, " +
           (petsc || r.result.method != analysis::SolverOptions::Method::kCholesky
                ? "preconditioner setup "
                : "factorisation ") +
           format_number(r.result.factorization_seconds, 3) + " s");
  return r;
}

std::vector<std::string> analyze_csv_names(const Case& c) {
  std::vector<std::string> names;
  for (const auto& load : c.problem.load_cases)
    names.push_back(load.id + "_control_displacements.csv");
  return names;
}

nlohmann::json write_analyze_outputs(const AnalyzeCommandResult& r,
                                     const AnalyzeCommandOptions& options,
                                     const std::filesystem::path& out_dir, const Progress& progress,
                                     std::chrono::steady_clock::time_point start) {
  if (r.immersed) return write_immersed_outputs(*r.immersed, out_dir, progress, start);
  const Case& c = r.c;
  const analysis::StaticResult& result = r.result;
  const bool petsc = options.backend == "petsc";
  nlohmann::json report = report_header("analyze", isospring_version(), options.case_file);
  report["case"] = case_summary(c, c.problem);
  // The solver used; with --solver auto also what was asked and why this one was chosen.
  const std::string used = petsc ? "petsc" : solver_name(result.method);
  report["solver"] = used;
  if (!petsc && options.solver == "auto") {
    report["solver_requested"] = options.solver;
    report["solver_reason"] = result.method_reason;
  }
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
  const analysis::BlasRuntime& blas = r.blas;
  report["blas"] = {{"name", blas.name},     {"library", blas.library}, {"lapack", blas.lapack},
                    {"config", blas.config}, {"threads", blas.threads}, {"loaded", blas.loaded}};

  AnalyzeTimings timings;
  timings.refinement_seconds = c.refinement_seconds;
  timings.read_seconds = r.read_seconds - c.refinement_seconds;
  add_solver_timings(result, timings);

  MarkdownReport md;
  md.heading(1, "isospring analyze: " + c.name);
  add_case_summary(md, report["case"]);
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < result.load_cases.size(); ++i) {
    const analysis::LoadCaseResult& lc = result.load_cases[i];
    progress("load case " + lc.id + " (" + std::to_string(i + 1) + "/" +
             std::to_string(result.load_cases.size()) +
             "): max |u| = " + format_number(lc.max_displacement) + " m");
    const std::string csv = lc.id + "_control_displacements.csv";
    timed_output(out_dir, csv, timings, [&] {
      write_control_displacements_csv(out_dir / csv, c.problem.patches, lc.control_displacements);
    });
    nlohmann::json entry = {{"id", lc.id},
                            {"max_displacement", lc.max_displacement},
                            {"strain_energy", lc.strain_energy},
                            {"reaction_sum", vector_json(lc.reaction_sum, c.dimension)},
                            {"solve_seconds", lc.solve_seconds},
                            {"control_displacements_file", csv}};
    if (petsc || result.method == analysis::SolverOptions::Method::kConjugateGradient ||
        result.method == analysis::SolverOptions::Method::kAmg) {
      entry["iterations"] = lc.iterations;
      entry["relative_residual"] = lc.relative_residual;
    }
    report["load_cases"].push_back(std::move(entry));
    std::string reaction;
    for (int d = 0; d < c.dimension; ++d)
      reaction += (d ? ", " : "") + format_number(lc.reaction_sum[d]);
    rows.push_back({lc.id, format_number(lc.max_displacement), format_number(lc.strain_energy),
                    "(" + reaction + ")", format_number(lc.solve_seconds, 3), "`" + csv + "`"});
  }

  // One ParaView file for the whole run (analyze_vtk.hpp); the evaluated fields are the
  // library's own post-processing (analysis::evaluate_field) at the sampled parameters.
  const bool vtk = detail::analyze_writes_vtk(options, c);
  std::string vtk_text;
  if (vtk) {
    const size_t first = timings.outputs.size();
    vtk_text = detail::write_analyze_vtk(r, options, out_dir, timings);
    double seconds = 0;
    for (size_t i = first; i < timings.outputs.size(); ++i) seconds += timings.outputs[i].seconds;
    report["vtk_file"] = "result.vtm";
    report["vtk_seconds"] = seconds;
  }
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report["total_seconds"] = total;

  md.heading(2, "Results");
  md.table({"load case", "max abs(u) [m]", "strain energy [J]", "reaction sum [N]", "solve [s]",
            "control displacements"},
           rows);
  const std::string method =
      petsc ? "PETSc " + result.preconditioner + " on " + std::to_string(result.ranks) +
                  " MPI rank(s)"
            : used + (result.method_reason.empty()
                          ? std::string()
                          : ", chosen by --solver auto: " + result.method_reason);
  md.paragraph(
      std::to_string(result.dofs) + " DOFs (" + method + "); assembly " +
      format_number(result.assembly_seconds, 3) + " s, " +
      (petsc || r.result.method != analysis::SolverOptions::Method::kCholesky
           ? "preconditioner setup "
           : "factorisation ") +
      format_number(result.factorization_seconds, 3) + " s, total " + format_number(total, 3) +
      " s; BLAS/LAPACK: " +
      (blas.name.empty() ? std::string("none loaded") : blas.name + " (`" + blas.library + "`)") +
      ". Reaction sums are the forces the supports " +
      "exert (K u - f summed over supported DOFs); they balance the applied loads.");
  if (vtk) md.paragraph(vtk_text);
  timed_output(out_dir, "report.md", timings, [&] { md.write(out_dir / "report.md"); });
  // Every file but report.json itself, which holds them.
  report["timings"] = timings_json(timings);
  write_json_report(out_dir / "report.json", report);
  progress("wrote " + (out_dir / "report.json").string() + ", report.md and " +
           std::to_string(result.load_cases.size()) + " displacement table(s)" +
           (vtk ? " and result.vtm" : ""));
  return report;
}

}  // namespace isospring::workflows
