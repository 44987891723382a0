// run_study: the refinement study of `isospring study` (see study_command.hpp).
#include <cmath>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/study_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

/// |value - reference| / |reference| (absolute when the reference is 0).
double relative_difference(double value, double reference) {
  const double d = std::abs(value - reference);
  return reference == 0.0 ? d : d / std::abs(reference);
}

}  // namespace

StudyCommandResult run_study(const Case& c, const StudyCommandOptions& options,
                             const Progress& progress) {
  if (options.levels < 1 || options.levels > 8)
    throw nurbs::InputError("--levels " + std::to_string(options.levels) + ": give 1 to 8 levels");
  std::vector<int> degrees = options.degrees;
  if (degrees.empty()) degrees.push_back(c.discretization.degree[0]);
  size_t load_case = 0;
  if (!options.load_case.empty()) {
    load_case = c.problem.load_cases.size();
    for (size_t i = 0; i < c.problem.load_cases.size(); ++i)
      if (c.problem.load_cases[i].id == options.load_case) load_case = i;
    if (load_case == c.problem.load_cases.size())
      throw nurbs::InputError("--load-case " + options.load_case + ": no such load case in " +
                              c.file.string());
  }
  const StudyQuantity quantity =
      parse_study_quantity(options.quantity, options.point, options.component, c);
  const std::optional<double> exact_quantity = quantity.exact(c);
  const bool analytic = c.analytic.has_value();
  std::vector<StudyRow> rows;
  std::vector<std::optional<analysis::Richardson>> extrapolations;
  // Level l splits every element of the case 2^l times along each direction.
  const auto discretization_at = [&c](int degree, int level) {
    CaseDiscretization disc = c.discretization;
    for (int d = 0; d < 3; ++d) {
      disc.degree[d] = degree;
      disc.elements[d] = c.discretization.elements[d] << level;
    }
    return disc;
  };
  // The finest level of each degree must fit before the first solve, not after hours.
  for (int p : degrees)
    check_solve_fits(c, discretization_at(p, options.levels - 1), options.limits);
  for (int p : degrees) {
    const size_t first = rows.size();
    for (int level = 0; level < options.levels; ++level) {
      const CaseDiscretization disc = discretization_at(p, level);
      const analysis::Problem problem = problem_at(c, disc);
      progress("degree " + std::to_string(p) + ", level " + std::to_string(level) + ": " +
               std::to_string(disc.elements[0]) + " elements along u");
      const analysis::StaticResult result = analysis::solve_static(problem);
      const analysis::LoadCaseResult& lc = result.load_cases[load_case];
      StudyRow row;
      row.degree = p;
      row.level = level;
      row.elements = disc.elements[0];
      row.h = 1.0 / disc.elements[0];
      row.dofs = result.dofs;
      row.quantity = quantity.evaluate(problem, lc);
      if (exact_quantity)
        row.quantity_exact_error = relative_difference(row.quantity, *exact_quantity);
      row.assembly = result.assembly_seconds;
      row.factorization = result.factorization_seconds;
      row.solve = lc.solve_seconds;
      if (analytic) {
        const analysis::ErrorNorms norms = analysis::error_norms(
            problem, lc.control_displacements, c.analytic->displacement, c.analytic->stress);
        row.l2 = norms.relative_l2();
        row.energy = norms.relative_energy();
      }
      rows.push_back(row);
    }
    // The quantity's reference: Richardson from the last three levels when they converge
    // monotonically, else the finest level.
    std::optional<analysis::Richardson> extrapolation;
    if (rows.size() - first >= 3) {
      const size_t n = rows.size();
      extrapolation = analysis::richardson_extrapolation(rows[n - 3].quantity, rows[n - 2].quantity,
                                                         rows[n - 1].quantity);
      if (!extrapolation->extrapolated())
        progress.warn("degree " + std::to_string(p) + ": the quantity is " +
                      analysis::status_name(extrapolation->status) +
                      " over the last three levels; its errors are against the finest level");
    }
    extrapolations.push_back(extrapolation);
    const double reference = extrapolation && extrapolation->extrapolated() ? extrapolation->value
                                                                            : rows.back().quantity;
    for (size_t i = first; i < rows.size(); ++i)
      rows[i].quantity_error = relative_difference(rows[i].quantity, reference);
  }

  StudyCommandResult r;
  r.input = c.file;
  r.case_name = c.name;
  r.case_summary = case_summary(c, c.problem);
  r.load_case = c.problem.load_cases[load_case].id;
  r.analytic_type = analytic ? c.analytic->type : "";
  r.quantity_label = quantity.label;
  r.exact_quantity = exact_quantity;
  r.degrees = std::move(degrees);
  r.rows = std::move(rows);
  r.extrapolations = std::move(extrapolations);
  return r;
}

std::vector<std::string> study_output_files() {
  return {"report.json", "report.md", "study.csv", "convergence.png"};
}

}  // namespace isospring::workflows
