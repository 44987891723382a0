// `isospring study CASE.json -o OUTDIR --levels N --degrees 2,3,4`: uniform k-refinement study.
// Level l has elements * 2^l per direction (the case's discretisation is level 0). Errors are
// against the case's analytic solution (relative L2 and energy norms) when it names one. A scalar
// (`--quantity`: strain energy, max control displacement, or a displacement at `--point`) is
// followed at every level and, from 3 levels on, Richardson-extrapolated from the last three
// (observed order and mesh-independent value); without an analytic solution its relative error to
// the extrapolated value (or to the finest level when the sequence is not monotone) is the error.
// Rates are least-squares fits over the last three levels (benchmarks.md). Writes report.json,
// report.md, study.csv and convergence.png (gnuplot; skipped with a warning when missing).
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/richardson.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "study_quantity.hpp"

namespace isospring::apps {
namespace {

struct StudyOptions {
  std::string case_file, output, degrees, load_case;
  std::string quantity = "strain_energy", point, component;
  int levels = 4;
  bool quiet = false;
};

struct StudyRow {
  int degree = 0, level = 0, elements = 0, dofs = 0;
  double h = 0, l2 = NAN, energy = NAN, quantity = 0, quantity_error = NAN;
  double quantity_exact_error = NAN;  // relative to the analytic value of the quantity
  double assembly = 0, factorization = 0, solve = 0;
  double error() const { return std::isnan(l2) ? quantity_error : l2; }
};

/// Levels a rate is fitted over: the last ones, where the error is closest to asymptotic.
constexpr size_t kFittedLevels = 3;

/// Least-squares slope of log(error) against log(h) over the last kFittedLevels rows with a
/// positive error.
double fitted_rate(const std::vector<const StudyRow*>& rows, double (*error)(const StudyRow&)) {
  std::vector<const StudyRow*> used;
  for (const StudyRow* r : rows)
    if (error(*r) > 0) used.push_back(r);
  if (used.size() > kFittedLevels) used.erase(used.begin(), used.end() - kFittedLevels);
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const StudyRow* r : used) {
    const double e = error(*r);
    const double x = std::log(r->h), y = std::log(e);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  if (n < 2) return NAN;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// |value - reference| / |reference| (absolute when the reference is 0).
double relative_difference(double value, double reference) {
  const double d = std::abs(value - reference);
  return reference == 0.0 ? d : d / std::abs(reference);
}

/// A table cell: "-" for what a level does not have (NaN).
std::string cell(double value, int digits) {
  return std::isnan(value) ? "-" : io::format_number(value, digits);
}

double l2_of(const StudyRow& r) {
  return r.l2;
}
double energy_of(const StudyRow& r) {
  return r.energy;
}
double quantity_of(const StudyRow& r) {
  return r.quantity_error;
}

/// "; quantity: Richardson order 2.01, extrapolated 1.234" for the markdown summary.
std::string richardson_line(const nlohmann::json& entry) {
  if (!entry.contains("richardson")) return "";
  const auto& r = entry["richardson"];
  const std::string status = r["status"].get<std::string>();
  if (status != "extrapolated") return "; quantity " + status + " over the last three levels";
  return "; quantity: Richardson order " + io::format_number(r["order"].get<double>(), 3) +
         ", extrapolated " + io::format_number(r["value"].get<double>(), 10) + " (finest off by " +
         io::format_number(r["finest_error_estimate"].get<double>(), 3) + ")";
}

void plot(const std::filesystem::path& out_dir, const std::vector<StudyRow>& rows, bool analytic,
          const io::Progress& progress) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    progress.warn("gnuplot is not installed; skipping convergence.png (install gnuplot-nox)");
    return;
  }
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("isospring-study-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string script = "set terminal pngcairo size 900,650\nset output '" +
                       (dir / "convergence.png").string() +
                       "'\nset logscale xy\nset grid\nset key bottom right\n"
                       "set xlabel 'relative element size h'\nset ylabel '" +
                       (analytic ? "relative error (L2: solid, energy: dashed)"
                                 : "relative error of the study quantity") +
                       "'\nplot ";
  std::vector<int> degrees;
  for (const StudyRow& r : rows)
    if (degrees.empty() || degrees.back() != r.degree) degrees.push_back(r.degree);
  bool first = true;
  for (int p : degrees) {
    const std::string data = (dir / ("p" + std::to_string(p) + ".dat")).string();
    std::ofstream out(data);
    for (const StudyRow& r : rows)
      if (r.degree == p && r.error() > 0)
        out << r.h << ' ' << r.error() << ' ' << (analytic ? r.energy : r.error()) << '\n';
    script += std::string(first ? "" : ", ") + "'" + data +
              "' using 1:2 with linespoints lw 2 title 'p = " + std::to_string(p) + "'";
    if (analytic)
      script += ", '" + data + "' using 1:3 with linespoints dt 2 title 'p = " + std::to_string(p) +
                " energy'";
    first = false;
  }
  std::ofstream(dir / "plot.gp") << script << "\n";
  const std::string command = "gnuplot '" + (dir / "plot.gp").string() + "' > /dev/null 2>&1";
  if (std::system(command.c_str()) == 0 && std::filesystem::exists(dir / "convergence.png")) {
    io::write_via_temporary(out_dir / "convergence.png", [&](const std::filesystem::path& tmp) {
      std::filesystem::copy_file(dir / "convergence.png", tmp,
                                 std::filesystem::copy_options::overwrite_existing);
    });
  } else {
    progress.warn("gnuplot failed; convergence.png was not written");
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

void run_study(const StudyOptions& options) {
  const io::Progress progress("study", options.quiet);
  if (options.levels < 1 || options.levels > 8)
    throw nurbs::InputError("--levels " + std::to_string(options.levels) + ": give 1 to 8 levels");
  const std::vector<std::string> outputs{"report.json", "report.md", "study.csv",
                                         "convergence.png"};
  const std::filesystem::path out_dir = output_folder(options.output, {options.case_file}, outputs);
  const io::CaseLimits limits = solve_limits(0);
  const io::Case c = io::read_case_file(options.case_file, limits);
  io::check_outputs_spare_inputs(case_inputs(c), in_folder(out_dir, outputs));
  std::vector<int> degrees;
  if (options.degrees.empty()) {
    degrees.push_back(c.discretization.degree[0]);
  } else {
    for (double p : parse_number_list(options.degrees, "--degrees")) {
      if (p != std::floor(p) || p < 1 || p > 10)
        throw nurbs::InputError("--degrees: " + std::to_string(p) + " is not a degree 1..10");
      degrees.push_back(static_cast<int>(p));
    }
  }
  size_t load_case = 0;
  if (!options.load_case.empty()) {
    load_case = c.problem.load_cases.size();
    for (size_t i = 0; i < c.problem.load_cases.size(); ++i)
      if (c.problem.load_cases[i].id == options.load_case) load_case = i;
    if (load_case == c.problem.load_cases.size())
      throw nurbs::InputError("--load-case " + options.load_case + ": no such load case in " +
                              options.case_file);
  }
  const StudyQuantity quantity =
      parse_study_quantity(options.quantity, options.point, options.component, c);
  const std::optional<double> exact_quantity = quantity.exact(c);
  const bool analytic = c.analytic.has_value();
  std::vector<StudyRow> rows;
  std::vector<std::optional<analysis::Richardson>> extrapolations;
  // Level l splits every element of the case 2^l times along each direction.
  const auto discretization_at = [&c](int degree, int level) {
    io::CaseDiscretization disc = c.discretization;
    for (int d = 0; d < 3; ++d) {
      disc.degree[d] = degree;
      disc.elements[d] = c.discretization.elements[d] << level;
    }
    return disc;
  };
  // The finest level of each degree must fit before the first solve, not after hours.
  for (int p : degrees) io::check_solve_fits(c, discretization_at(p, options.levels - 1), limits);
  for (int p : degrees) {
    const size_t first = rows.size();
    for (int level = 0; level < options.levels; ++level) {
      const io::CaseDiscretization disc = discretization_at(p, level);
      const analysis::Problem problem = io::problem_at(c, disc);
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

  nlohmann::json report = io::report_header("study", ISOSPRING_VERSION, options.case_file);
  report["case"] = io::case_summary(c, c.problem);
  report["load_case"] = c.problem.load_cases[load_case].id;
  report["reference"] = analytic ? "analytic:" + c.analytic->type
                                 : "Richardson extrapolation of the quantity (else finest level)";
  report["quantity"] = quantity.label;
  if (exact_quantity) report["exact_quantity"] = *exact_quantity;
  io::MarkdownReport md;
  md.heading(1, "isospring study: " + c.name);
  io::add_case_summary(md, report["case"]);
  md.paragraph(
      "Load case `" + c.problem.load_cases[load_case].id + "`; errors against " +
      report["reference"].get<std::string>() +
      ". Level l has (case elements) x 2^l per direction; h is relative to the patch. "
      "Study quantity: " +
      quantity.label +
      (exact_quantity ? " (exact " + io::format_number(*exact_quantity, 10) + ")" : std::string()) +
      ".");
  std::string csv =
      "degree,level,elements_u,dofs,h,relative_l2_error,relative_energy_error,quantity,"
      "quantity_error,assembly_seconds,factorization_seconds,solve_seconds\n";
  std::vector<std::vector<std::string>> table;
  for (size_t di = 0; di < degrees.size(); ++di) {
    const int p = degrees[di];
    std::vector<const StudyRow*> of_degree;
    for (const StudyRow& r : rows)
      if (r.degree == p) of_degree.push_back(&r);
    nlohmann::json entry{{"degree", p}};
    for (size_t i = 0; i < of_degree.size(); ++i) {
      const StudyRow& r = *of_degree[i];
      auto pair_rate = [&](double (*error)(const StudyRow&)) -> double {
        if (i == 0) return NAN;
        const double a = error(*of_degree[i - 1]), b = error(r);
        return a > 0 && b > 0 ? std::log(a / b) / std::log(of_degree[i - 1]->h / r.h) : NAN;
      };
      const double rate = pair_rate(analytic ? l2_of : quantity_of);
      const double energy_rate = analytic ? pair_rate(energy_of) : NAN;
      entry["levels"].push_back({{"level", r.level},
                                 {"elements", r.elements},
                                 {"dofs", r.dofs},
                                 {"h", r.h},
                                 {"relative_l2_error", r.l2},
                                 {"relative_energy_error", r.energy},
                                 {"quantity", r.quantity},
                                 {"quantity_error", r.quantity_error},
                                 {"quantity_exact_error", r.quantity_exact_error},
                                 {"rate", rate},
                                 {"energy_rate", energy_rate},
                                 {"assembly_seconds", r.assembly},
                                 {"factorization_seconds", r.factorization},
                                 {"solve_seconds", r.solve}});
      char line[512];
      std::snprintf(line, sizeof(line),
                    "%d,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.6g,%.6g,%.6g\n", p, r.level,
                    r.elements, r.dofs, r.h, r.l2, r.energy, r.quantity, r.quantity_error,
                    r.assembly, r.factorization, r.solve);
      csv += line;
      table.push_back({std::to_string(p), std::to_string(r.level), std::to_string(r.dofs),
                       cell(r.error(), 4), cell(rate, 3), cell(r.energy, 4), cell(energy_rate, 3),
                       io::format_number(r.quantity, 8),
                       io::format_number(r.assembly + r.factorization + r.solve, 3)});
    }
    entry["fitted_rate"] = fitted_rate(of_degree, analytic ? l2_of : quantity_of);
    if (analytic) entry["fitted_energy_rate"] = fitted_rate(of_degree, energy_of);
    entry["fitted_quantity_rate"] = fitted_rate(of_degree, quantity_of);
    if (const auto& r = extrapolations[di])
      entry["richardson"] = {{"status", analysis::status_name(r->status)},
                             {"order", r->order},
                             {"value", r->value},
                             {"finest_error_estimate", r->error_estimate}};
    report["degrees"].push_back(entry);
  }
  md.heading(2, "Convergence");
  md.table({"p", "level", "DOFs", analytic ? "L2 error" : "quantity error", "rate", "energy error",
            "energy rate", "quantity", "time [s]"},
           table);
  std::vector<std::string> fits;
  for (const auto& entry : report["degrees"])
    fits.push_back(
        "p = " + entry["degree"].dump() + ": fitted rate " +
        io::format_number(
            entry["fitted_rate"].is_number() ? entry["fitted_rate"].get<double>() : NAN, 3) +
        (analytic ? ", energy " + io::format_number(entry["fitted_energy_rate"].is_number()
                                                        ? entry["fitted_energy_rate"].get<double>()
                                                        : NAN,
                                                    3)
                  : std::string()) +
        (analytic ? " (expected p+1 and p)" : "") + richardson_line(entry));
  md.bullets(fits);
  md.paragraph("![convergence](convergence.png)");
  io::write_file_atomically(out_dir / "study.csv", csv);
  io::add_warnings(report, md, progress);
  io::write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  plot(out_dir, rows, analytic, progress);
  progress("wrote " + (out_dir / "report.json").string() + ", report.md, study.csv");
}

void setup_study(CLI::App& app) {
  auto options = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "Refinement study of a case: errors, observed convergence rates and timings");
  cmd->footer(
      "Level l has the case's elements x 2^l per direction, at each degree (k-refinement).\n"
      "Errors: relative L2 and energy norms against the case's \"analytic\" solution. A scalar\n"
      "(--quantity) is followed at every level; with 3+ levels the last three give a Richardson\n"
      "extrapolation q* = q3 + (q3 - q2) / (2^r - 1) with observed order\n"
      "r = log2((q2 - q1) / (q3 - q2)) (report.json: degrees[].richardson). Without an analytic\n"
      "solution the error of each level is |q - q*| / |q*| (against the finest level when the\n"
      "last three are not monotone). Rates are fitted over the last three levels.\n"
      "Writes OUTDIR/report.json, report.md, study.csv and convergence.png (gnuplot).");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder")->required();
  cmd->add_option("--levels", options->levels, "Refinement levels (default 4)");
  cmd->add_option("--degrees", options->degrees, "Degrees, e.g. 2,3,4 (default: the case's)");
  cmd->add_option("--load-case", options->load_case, "Load case id (default: the first)");
  cmd->add_option("--quantity", options->quantity,
                  "Scalar followed and Richardson-extrapolated: strain_energy (default; converges "
                  "monotonically at 2p), max_displacement (max |u| over the control points: "
                  "O(h^2) at best), displacement (at --point)");
  cmd->add_option("--point", options->point,
                  "PATCH:U,V[,W] parametric point of --quantity displacement, e.g. 0:1,0.5");
  cmd->add_option("--component", options->component,
                  "x, y, z or magnitude (default) of --quantity displacement");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_study(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(45, setup_study);
}  // namespace isospring::apps
