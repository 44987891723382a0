// `isospring study CASE.json -o OUTDIR --levels N --degrees 2,3,4`: uniform k-refinement study.
// Level l has elements * 2^l per direction (the case's discretisation is level 0). Errors are
// against the case's analytic solution (relative L2 and energy norms) when it names one, else the
// relative difference of the maximum control displacement to the finest level's. Writes
// report.json, report.md, study.csv and convergence.png (gnuplot; skipped with a warning when
// gnuplot is missing).
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct StudyOptions {
  std::string case_file, output, degrees, load_case;
  int levels = 4;
  bool quiet = false;
};

struct StudyRow {
  int degree = 0, level = 0, elements = 0, dofs = 0;
  double h = 0, l2 = NAN, energy = NAN, quantity = 0, quantity_error = NAN;
  double assembly = 0, factorization = 0, solve = 0;
  double error() const { return std::isnan(l2) ? quantity_error : l2; }
};

/// Least-squares slope of log(error) against log(h) over the rows with a positive error.
double fitted_rate(const std::vector<const StudyRow*>& rows, double (*error)(const StudyRow&)) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const StudyRow* r : rows) {
    const double e = error(*r);
    if (!(e > 0)) continue;
    const double x = std::log(r->h), y = std::log(e);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  if (n < 2) return NAN;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
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
                                 : "relative difference of max |u| to the finest level") +
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
  const std::filesystem::path out_dir(options.output);
  if (options.levels < 1 || options.levels > 8)
    throw nurbs::InputError("--levels " + std::to_string(options.levels) + ": give 1 to 8 levels");
  const io::Case c = io::read_case_file(options.case_file);
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
  const bool analytic = c.analytic.has_value();
  std::vector<StudyRow> rows;
  for (int p : degrees) {
    const size_t first = rows.size();
    for (int level = 0; level < options.levels; ++level) {
      io::CaseDiscretization disc = c.discretization;
      for (int d = 0; d < 3; ++d) {
        disc.degree[d] = p;
        disc.elements[d] = c.discretization.elements[d] << level;
      }
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
      row.quantity = lc.max_displacement;
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
    if (!analytic)  // against the finest level of this degree
      for (size_t i = first; i < rows.size(); ++i)
        rows[i].quantity_error =
            std::abs(rows[i].quantity - rows.back().quantity) / std::abs(rows.back().quantity);
  }

  nlohmann::json report = io::report_header("study", ISOSPRING_VERSION, options.case_file);
  report["case"] = io::case_summary(c, c.problem);
  report["load_case"] = c.problem.load_cases[load_case].id;
  report["reference"] = analytic ? "analytic:" + c.analytic->type : "finest level (max |u|)";
  io::MarkdownReport md;
  md.heading(1, "isospring study: " + c.name);
  io::add_case_summary(md, report["case"]);
  md.paragraph("Load case `" + c.problem.load_cases[load_case].id + "`; errors against " +
               report["reference"].get<std::string>() +
               ". Level l has (case elements) x 2^l per direction; h is relative to the patch.");
  std::string csv =
      "degree,level,elements_u,dofs,h,relative_l2_error,relative_energy_error,max_displacement,"
      "max_displacement_error,assembly_seconds,factorization_seconds,solve_seconds\n";
  std::vector<std::vector<std::string>> table;
  for (int p : degrees) {
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
                                 {"max_displacement", r.quantity},
                                 {"max_displacement_error", r.quantity_error},
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
                       io::format_number(r.error(), 4), io::format_number(rate, 3),
                       io::format_number(r.energy, 4), io::format_number(energy_rate, 3),
                       io::format_number(r.assembly + r.factorization + r.solve, 3)});
    }
    entry["fitted_rate"] = fitted_rate(of_degree, analytic ? l2_of : quantity_of);
    if (analytic) entry["fitted_energy_rate"] = fitted_rate(of_degree, energy_of);
    report["degrees"].push_back(entry);
  }
  md.heading(2, "Convergence");
  md.table({"p", "level", "DOFs", analytic ? "L2 error" : "max abs(u) error", "rate",
            "energy error", "energy rate", "time [s]"},
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
        (analytic ? " (expected p+1 and p)" : ""));
  md.bullets(fits);
  md.paragraph("![convergence](convergence.png)");
  io::write_file_atomically(out_dir / "study.csv", csv);
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
      "Errors: relative L2 and energy norms against the case's \"analytic\" solution, or the\n"
      "relative difference of the maximum control displacement to the finest level.\n"
      "Writes OUTDIR/report.json, report.md, study.csv and convergence.png (gnuplot).");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output folder")->required();
  cmd->add_option("--levels", options->levels, "Refinement levels (default 4)");
  cmd->add_option("--degrees", options->degrees, "Degrees, e.g. 2,3,4 (default: the case's)");
  cmd->add_option("--load-case", options->load_case, "Load case id (default: the first)");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_study(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(45, setup_study);
}  // namespace isospring::apps
