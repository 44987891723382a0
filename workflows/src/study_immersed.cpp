// run_study_immersed: the refinement study of an immersed case (see study_immersed.hpp).
#include "isospring/workflows/study_immersed.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "isospring/analysis/immersed_errors.hpp"
#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
using namespace isospring::io;
namespace {

using nurbs::InputError;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double relative_difference(double value, double reference) {
  const double d = std::abs(value - reference);
  return reference == 0.0 ? d : d / std::abs(reference);
}

size_t chosen_load_case(const ImmersedCase& c, const std::string& id) {
  if (id.empty()) return 0;
  for (size_t i = 0; i < c.load_cases.size(); ++i)
    if (c.load_cases[i].id == id) return i;
  throw InputError("--load-case " + id + ": no such load case in " + c.file.string());
}

/// The followed scalar: only the whole-part ones have an immersed meaning (a patch point does
/// not exist on a background grid).
StudyQuantity::Kind chosen_quantity(const StudyCommandOptions& o, std::string& label) {
  if (!o.point.empty() || !o.component.empty() || o.quantity == "displacement")
    throw InputError(
        "--quantity displacement, --point and --component name a point of a body-fitted patch; "
        "an immersed case has no patches: use --quantity strain_energy or max_displacement");
  if (o.quantity == "strain_energy") {
    label = "strain energy";
    return StudyQuantity::Kind::kStrainEnergy;
  }
  if (o.quantity == "max_displacement") {
    label = "max |u| over the active control points";
    return StudyQuantity::Kind::kMaxDisplacement;
  }
  throw InputError("--quantity '" + o.quantity + "': use strain_energy or max_displacement");
}

/// The background grid of a level: the case's immersion options with explicit cells (level 0's
/// times 2^level) and the degree; a Gauss count the user set is raised to the degree's minimum.
geometry::ImmersionOptions level_options(const ImmersedCase& c, const Eigen::Vector3i& cells0,
                                         int degree, int level) {
  geometry::ImmersionOptions o = c.immersion;
  o.degree = degree;
  if (o.gauss != 0) o.gauss = std::max(o.gauss, degree + 1);
  if (cells0.minCoeff() > 0) {
    o.cells = cells0 * (1 << level);
    o.cell_size = 0;
  }
  return o;
}

/// Refuses a study whose finest grid would not fit: the DOFs are at least the part's share of
/// the background grid's (the active basis functions cover the part), so the whole grid's
/// estimate scaled by the part's volume fraction is a floor of the solve's memory.
void check_finest_fits(const ImmersedCase& c, const geometry::ImmersedDomain& level0,
                       double part_volume, int degree, int levels, const CaseLimits& limits) {
  if (limits.solve_memory_bytes <= 0) return;
  analysis::PatchSize size;
  double box = 1;
  for (int d = 0; d < 3; ++d) {
    const int cells = level0.background.knots(d).num_elements() << (levels - 1);
    size.points[static_cast<size_t>(d)] = cells + degree;
    size.degree[static_cast<size_t>(d)] = degree;
    box *= level0.extent[d];
  }
  const analysis::SolveEstimate e = analysis::estimate_static_solve({size}, 3);
  const double fraction = std::min(1.0, part_volume / box);
  if (e.bytes * fraction > limits.solve_memory_bytes)
    throw InputError(c.file.string() + ": the finest level (degree " + std::to_string(degree) +
                     ", " + std::to_string(static_cast<int>(size.points[0]) - degree) +
                     " cells along x) needs at least " +
                     analysis::format_bytes(e.bytes * fraction) + " but the limit is " +
                     analysis::format_bytes(limits.solve_memory_bytes) + " (" +
                     limits.solve_memory_source + "); use fewer --levels or a lower degree");
}

/// The case summary of the reports (the keys of io::case_summary) for an immersed case.
nlohmann::json immersed_summary(const ImmersedCase& c, const geometry::ImmersedDomain& level0,
                                int degree) {
  nlohmann::json s;
  s["name"] = c.name;
  s["file"] = c.file.string();
  s["path"] = "immersed";
  s["part"] = c.part.string();
  s["dimension"] = 3;
  s["formulation"] = "solid";
  s["volumetric"] = volumetric_key(c.volumetric);
  s["material"] = {{"E", c.material.youngs_modulus},
                   {"nu", c.material.poisson_ratio},
                   {"density", c.material.density}};
  nlohmann::json grid;
  int points = 1, cells = 1;
  for (int d = 0; d < 3; ++d) {
    const int n = level0.background.knots(d).num_elements();
    grid["degree"].push_back(degree);
    grid["elements"].push_back(n);
    grid["control_points"].push_back(n + degree);
    points *= n + degree;
    cells *= n;
  }
  s["patches"] = nlohmann::json::array({grid});  // the background grid of level 0
  s["control_points"] = points;
  s["elements"] = cells;
  s["supports"] = c.supports.size();
  for (const ImmersedLoadCase& lc : c.load_cases) s["load_cases"].push_back(lc.id);
  if (c.analytic) s["analytic"] = c.analytic->type;
  return s;
}

double max_control_displacement(const analysis::ImmersedResult& r) {
  double m = 0;
  for (size_t i = 0; i < r.control_displacements.size(); ++i)
    if (r.active[i]) m = std::max(m, r.control_displacements[i].norm());
  return m;
}

/// Immerses and solves one level; fills everything of the row but the quantity's error.
StudyRow solve_level(const ImmersedCase& c, const geometry::ImmersionOptions& grid,
                     const ImmersedLoadCase& load, StudyQuantity::Kind quantity,
                     geometry::ImmersedDomain* domain_out, const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  geometry::ImmersedDomain domain = geometry::immerse_solid(*c.cad, grid);
  const double immersion = seconds_since(start);
  for (const std::string& w : domain.warnings) progress.warn(w);
  analysis::ImmersedOptions o = immersed_options(c, load);
  const analysis::ImmersedResult result = analysis::solve_immersed(domain, o);
  for (const std::string& w : result.warnings) progress.warn(w);
  StudyRow row;
  row.degree = grid.degree;
  row.elements = domain.background.knots(0).num_elements();
  row.h = 1.0 / row.elements;
  row.dofs = result.dofs;
  row.quantity = quantity == StudyQuantity::Kind::kStrainEnergy ? result.strain_energy
                                                                : max_control_displacement(result);
  // The immersion (classification and cut-cell quadrature) is this path's share of assembly.
  row.assembly = immersion + result.assembly_seconds;
  row.solve = result.solve_seconds;
  if (c.analytic) {
    const analysis::ErrorNorms norms = analysis::immersed_error_norms(
        domain, result, o, c.analytic->displacement, c.analytic->stress);
    row.l2 = norms.relative_l2();
    row.energy = norms.relative_energy();
  }
  if (domain_out) *domain_out = std::move(domain);
  return row;
}

}  // namespace

StudyCommandResult run_study_immersed(const ImmersedCase& c, const StudyCommandOptions& options,
                                      const Progress& progress) {
  if (options.levels < 1 || options.levels > 8)
    throw InputError("--levels " + std::to_string(options.levels) + ": give 1 to 8 levels");
  const size_t load_case = chosen_load_case(c, options.load_case);
  StudyCommandResult r;
  const StudyQuantity::Kind quantity = chosen_quantity(options, r.quantity_label);
  r.degrees = options.degrees.empty() ? std::vector<int>{c.immersion.degree} : options.degrees;
  for (int p : r.degrees)
    if (p < 1 || p > 6) throw InputError("--degrees: " + std::to_string(p) + " is not 1..6");
  const ImmersedLoadCase& load = c.load_cases[load_case];
  const double part_volume = geometry::measure_solid(*c.cad).volume;
  Eigen::Vector3i cells0 = c.immersion.cells;  // zero: immerse_solid chooses at level 0
  for (int p : r.degrees) {
    const size_t first = r.rows.size();
    for (int level = 0; level < options.levels; ++level) {
      progress("degree " + std::to_string(p) + ", level " + std::to_string(level) + ": immersing");
      geometry::ImmersedDomain level0;
      StudyRow row = solve_level(c, level_options(c, cells0, p, level), load, quantity,
                                 level == 0 ? &level0 : nullptr, progress);
      if (level == 0) {
        for (int d = 0; d < 3; ++d) cells0[d] = level0.background.knots(d).num_elements();
        if (r.case_summary.is_null()) r.case_summary = immersed_summary(c, level0, p);
        // Only now is the grid known: refuse the finest level before solving it for hours.
        check_finest_fits(c, level0, part_volume, p, options.levels, options.limits);
      }
      row.level = level;
      progress("  " + std::to_string(row.elements) + " cells along x, " + std::to_string(row.dofs) +
               " DOFs" +
               (c.analytic ? ", relative L2 error " + format_number(row.l2, 3) : std::string()));
      r.rows.push_back(row);
    }
    std::optional<analysis::Richardson> extrapolation;
    if (r.rows.size() - first >= 3) {
      const size_t n = r.rows.size();
      extrapolation = analysis::richardson_extrapolation(
          r.rows[n - 3].quantity, r.rows[n - 2].quantity, r.rows[n - 1].quantity);
      if (!extrapolation->extrapolated())
        progress.warn("degree " + std::to_string(p) + ": the quantity is " +
                      analysis::status_name(extrapolation->status) +
                      " over the last three levels; its errors are against the finest level");
    }
    r.extrapolations.push_back(extrapolation);
    const double reference = extrapolation && extrapolation->extrapolated()
                                 ? extrapolation->value
                                 : r.rows.back().quantity;
    for (size_t i = first; i < r.rows.size(); ++i)
      r.rows[i].quantity_error = relative_difference(r.rows[i].quantity, reference);
  }
  r.input = c.file;
  r.case_name = c.name;
  r.load_case = load.id;
  r.analytic_type = c.analytic ? c.analytic->type : "";
  return r;
}

}  // namespace isospring::workflows
