#pragma once
// The use case behind `isospring analyze CASE.json -o OUTDIR` as library calls: solve every load
// case of a case file (serial CHOLMOD/CG, or PETSc on the MPI ranks of an active
// analysis::PetscSession), then write OUTDIR/report.json, report.md,
// <id>_control_displacements.csv and result.vtm (ParaView: the exact Bezier geometry with the
// displacement; the sampled outer surface (3D) or surface (2D) with displacement, stress, von
// Mises and strain energy density per load case; control net). report.json's "timings" says
// where the time went (analyze_timings.hpp).
// A case whose geometry is {"type": "immersed"} takes the immersed path instead
// (analyze_immersed.hpp: report.json, report.md and result.vtp on the part's surface).
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ImmersedAnalysis;  // analyze_immersed.hpp

struct AnalyzeCommandOptions {
  std::string case_file;
  std::string solver = "auto";          // serial: auto | cholesky | cg
  std::string backend = "serial";       // serial | petsc (needs an analysis::PetscSession)
  std::string preconditioner = "gamg";  // petsc: gamg | hypre | lu
  double tolerance = 1e-12;             // petsc: CG's relative residual
  /// Sample points per element and direction of the sampled geometry in result.vtm. -1: the
  /// case file's "output": {"vtk_samples"}, else automatic (3D: the exact Bezier volume and the
  /// sampled outer surface, no sampled volume; 2D: the surface sampled 4 x 4 per element);
  /// N > 0: also the sampled volume (3D) at N; 0: no result.vtm.
  int vtk_samples = -1;
  int threads = 0;        // 0: all (petsc: 1 per rank)
  io::CaseLimits limits;  // memory limit of the direct solve
};

struct AnalyzeCommandResult {
  io::Case c;
  analysis::StaticResult result;
  analysis::BlasRuntime blas;  // the BLAS/LAPACK loaded (decides the factorisation time)
  double read_seconds = 0;     // reading the case file, its refinement included
  /// Set for a case with an immersed geometry (analyze_immersed.hpp); `c` then holds only the
  /// case file's name, path and document, and `result` is empty.
  std::shared_ptr<const ImmersedAnalysis> immersed;
};

/// Reads the case and solves it (every MPI rank calls it with --backend petsc); `before_solve`
/// runs between the two (the program checks there that no output would overwrite an input, so a
/// long solve is not wasted). Throws nurbs::InputError for a bad case or options.
AnalyzeCommandResult run_analyze(const AnalyzeCommandOptions& options, const io::Progress& progress,
                                 const std::function<void(const io::Case&)>& before_solve = {});

/// The sample points per element and direction of the sampled volume (or, 2D, surface) that
/// `options` and the case ask for: 0 for none (3D default, or no ParaView output at all).
int sampled_volume_samples(const AnalyzeCommandOptions& options, const io::Case& c);

/// "cholesky", "cg" or "auto": the --solver name of a method.
std::string solver_name(analysis::SolverOptions::Method method);

/// The names of the per-load-case CSV files the outputs will hold.
std::vector<std::string> analyze_csv_names(const io::Case& c);

/// Writes the outputs into `out_dir` (rank 0 only); `start` is when the command started, for
/// report.json's total_seconds. Returns report.json's content.
nlohmann::json write_analyze_outputs(const AnalyzeCommandResult& r,
                                     const AnalyzeCommandOptions& options,
                                     const std::filesystem::path& out_dir,
                                     const io::Progress& progress,
                                     std::chrono::steady_clock::time_point start);

}  // namespace isospring::workflows
