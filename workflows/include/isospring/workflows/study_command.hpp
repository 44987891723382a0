#pragma once
// The use case behind `isospring study` as one library call: a uniform k-refinement study of a
// case. Level l has elements * 2^l per direction (the case's discretisation is level 0). Errors
// are against the case's analytic solution (relative L2 and energy norms) when it names one. A
// scalar (study_quantity.hpp) is followed at every level and, from 3 levels on,
// Richardson-extrapolated from the last three (observed order and mesh-independent value);
// without an analytic solution its relative error to the extrapolated value (or to the finest
// level when the sequence is not monotone) is the error. Rates are least-squares fits over the
// last three levels (benchmarks.md).
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/richardson.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/study_quantity.hpp"

namespace isospring::workflows {

struct StudyCommandOptions {
  int levels = 4;                                            // 1 .. 8
  std::vector<int> degrees;                                  // empty: the case's degree
  std::string load_case;                                     // empty: the first
  std::string quantity = "strain_energy", point, component;  // parse_study_quantity's text
  io::CaseLimits limits;  // the finest level of each degree must fit before the first solve
};

struct StudyRow {
  int degree = 0, level = 0, elements = 0, dofs = 0;
  double h = 0, l2 = NAN, energy = NAN, quantity = 0, quantity_error = NAN;
  double quantity_exact_error = NAN;  // relative to the analytic value of the quantity
  double assembly = 0, factorization = 0, solve = 0;
  double error() const { return std::isnan(l2) ? quantity_error : l2; }
};

struct StudyCommandResult {
  std::filesystem::path input;  // the case file
  std::string case_name;
  nlohmann::json case_summary;
  std::string load_case;      // its id
  std::string analytic_type;  // the case's analytic solution ("" without one)
  std::string quantity_label;
  std::optional<double> exact_quantity;
  std::vector<int> degrees;
  std::vector<StudyRow> rows;                                       // by degree, then level
  std::vector<std::optional<analysis::Richardson>> extrapolations;  // per degree
  bool analytic() const { return !analytic_type.empty(); }
};

/// Solves every level of every degree. Throws nurbs::InputError for bad options (naming the
/// command-line option) and when the finest level would not fit options.limits.
StudyCommandResult run_study(const io::Case& c, const StudyCommandOptions& options,
                             const io::Progress& progress);

/// report.json (without the warnings), report.md and study.csv of a study.
struct StudyReport {
  nlohmann::json json;
  io::MarkdownReport markdown;
  std::string csv;
};
StudyReport study_report(const StudyCommandResult& r);

/// The files write_study_outputs writes.
std::vector<std::string> study_output_files();

/// Writes study.csv, report.json, report.md (with the progress's warnings) and convergence.png
/// (gnuplot; a warning when it is missing) into `out_dir`.
void write_study_outputs(const std::filesystem::path& out_dir, const StudyCommandResult& r,
                         const io::Progress& progress);

}  // namespace isospring::workflows
