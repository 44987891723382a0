// report.json, report.md and study.csv of `isospring study` (see study_command.hpp).
#include <cmath>
#include <cstdio>

#include "isospring/io/report_case.hpp"
#include "isospring/workflows/study_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

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

/// A table cell: "-" for what a level does not have (NaN).
std::string cell(double value, int digits) {
  return std::isnan(value) ? "-" : format_number(value, digits);
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
  return "; quantity: Richardson order " + format_number(r["order"].get<double>(), 3) +
         ", extrapolated " + format_number(r["value"].get<double>(), 10) + " (finest off by " +
         format_number(r["finest_error_estimate"].get<double>(), 3) + ")";
}

}  // namespace

StudyReport study_report(const StudyCommandResult& result) {
  const std::vector<int>& degrees = result.degrees;
  const std::vector<StudyRow>& rows = result.rows;
  const bool analytic = result.analytic();
  const std::optional<double>& exact_quantity = result.exact_quantity;
  nlohmann::json report = report_header("study", isospring_version(), result.input);
  report["case"] = result.case_summary;
  report["load_case"] = result.load_case;
  report["reference"] = analytic ? "analytic:" + result.analytic_type
                                 : "Richardson extrapolation of the quantity (else finest level)";
  report["quantity"] = result.quantity_label;
  if (exact_quantity) report["exact_quantity"] = *exact_quantity;
  MarkdownReport md;
  md.heading(1, "isospring study: " + result.case_name);
  add_case_summary(md, report["case"]);
  md.paragraph(
      "Load case `" + result.load_case + "`; errors against " +
      report["reference"].get<std::string>() +
      ". Level l has (case elements) x 2^l per direction; h is relative to the patch. "
      "Study quantity: " +
      result.quantity_label +
      (exact_quantity ? " (exact " + format_number(*exact_quantity, 10) + ")" : std::string()) +
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
                       format_number(r.quantity, 8),
                       format_number(r.assembly + r.factorization + r.solve, 3)});
    }
    entry["fitted_rate"] = fitted_rate(of_degree, analytic ? l2_of : quantity_of);
    if (analytic) entry["fitted_energy_rate"] = fitted_rate(of_degree, energy_of);
    entry["fitted_quantity_rate"] = fitted_rate(of_degree, quantity_of);
    if (const auto& x = result.extrapolations[di])
      entry["richardson"] = {{"status", analysis::status_name(x->status)},
                             {"order", x->order},
                             {"value", x->value},
                             {"finest_error_estimate", x->error_estimate}};
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
        format_number(entry["fitted_rate"].is_number() ? entry["fitted_rate"].get<double>() : NAN,
                      3) +
        (analytic ? ", energy " + format_number(entry["fitted_energy_rate"].is_number()
                                                    ? entry["fitted_energy_rate"].get<double>()
                                                    : NAN,
                                                3)
                  : std::string()) +
        (analytic ? " (expected p+1 and p)" : "") + richardson_line(entry));
  md.bullets(fits);
  md.paragraph("![convergence](convergence.png)");
  return {report, md, csv};
}

}  // namespace isospring::workflows
