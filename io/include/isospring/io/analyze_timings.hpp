#pragma once
// Where the time of `isospring analyze` goes, stage by stage, for report.json ("timings") and
// `analyze --timings`: reading the case, refining its geometry, assembling K, factorising it or
// setting up the preconditioner, the solves, the post-processing of the solution (K u, reactions,
// energies) and every output file (its fields' evaluation included).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/static_solver.hpp"

namespace isospring::io {

struct OutputTiming {
  std::string file;  // relative to the output folder
  double seconds = 0;
  std::uintmax_t bytes = 0;
};

struct AnalyzeTimings {
  double read_seconds = 0;        // parsing and checking the case file (refinement excluded)
  double refinement_seconds = 0;  // elevating and splitting the geometry
  double assembly_seconds = 0;
  double setup_seconds = 0;  // factorisation (direct) or preconditioner setup (iterative)
  double solve_seconds = 0;  // every load case: load vector and solve
  double post_processing_seconds = 0;
  std::vector<OutputTiming> outputs;
};

/// The solver's stages of `result` (assembly, setup, solves, post-processing).
void add_solver_timings(const analysis::StaticResult& result, AnalyzeTimings& timings);

/// Times `write` and records the file it wrote (size from the disk).
void timed_output(const std::filesystem::path& out_dir, const std::string& file,
                  AnalyzeTimings& timings, const std::function<void()>& write);

/// {"read_seconds", "refinement_seconds", "assembly_seconds", "setup_seconds", "solve_seconds",
///  "post_processing_seconds", "outputs": [{"file", "seconds", "bytes"}], "output_seconds",
///  "output_bytes"}.
nlohmann::json timings_json(const AnalyzeTimings& timings);

/// The table `analyze --timings` prints: one line per stage and per file, seconds and MB, and
/// the total of report.json.
std::string timings_table(const nlohmann::json& timings, double total_seconds);

}  // namespace isospring::io
