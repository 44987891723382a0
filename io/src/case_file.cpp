#include "isospring/io/case_file.hpp"

#include <algorithm>
#include <chrono>

#include <numeric>
#include "case_file_conditions.hpp"
#include "case_file_json.hpp"
#include "case_volumetric.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_geometry.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::io {
using case_json::Field;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const char* const kDirection[] = {"u", "v", "w"};

std::string file_label(const fs::path& case_file) {
  return case_file.filename().string();
}

/// 2 for plane geometry (surfaces with z = 0), 3 for volumes; anything else cannot be analysed.
int geometry_dimension(const std::vector<nurbs::Patch>& patches, const Field& geometry) {
  if (patches.empty()) geometry.fail(": the geometry has no patches");
  const int param_dim = patches.front().param_dim();
  for (size_t p = 0; p < patches.size(); ++p) {
    const nurbs::Patch& patch = patches[p];
    if (patch.param_dim() != param_dim)
      geometry.fail(": patch " + std::to_string(p) + " has parametric dimension " +
                    std::to_string(patch.param_dim()) + " but patch 0 has " +
                    std::to_string(param_dim) + "; all patches must be surfaces or all volumes");
    if (param_dim == 2 && patch.physical_dim() != 2)
      geometry.fail(": patch " + std::to_string(p) +
                    " is a surface that is not in the plane z = 0; plane analyses need z = 0 and "
                    "shells are not supported: give a volume (e.g. a thickness) instead");
  }
  if (param_dim < 2)
    geometry.fail(": curves cannot be analysed; give a surface (2D) or a volume (3D)");
  return param_dim;
}

/// An int for all directions, or one int per parametric direction.
std::array<int, 3> read_per_direction(const Field& field, int param_dim, int minimum) {
  std::array<int, 3> out{0, 0, 0};
  if (field.json().is_number()) {
    const int value = field.integer();
    for (int d = 0; d < param_dim; ++d) out[d] = value;
  } else {
    const std::vector<Field> entries = field.elements();
    if (static_cast<int>(entries.size()) != param_dim)
      field.fail(" must be one integer or " + std::to_string(param_dim) +
                 " integers (one per parametric direction), got " + std::to_string(entries.size()));
    for (int d = 0; d < param_dim; ++d) out[d] = entries[static_cast<size_t>(d)].integer();
  }
  for (int d = 0; d < param_dim; ++d)
    if (out[d] < minimum)
      field.fail(" must be >= " + std::to_string(minimum) + " in every direction, got " +
                 std::to_string(out[d]) + " for " + kDirection[d]);
  return out;
}

/// Without "discretization": the geometry as it is (largest degree and span count per direction).
CaseDiscretization read_discretization(const Field& root,
                                       const std::vector<nurbs::Patch>& patches) {
  const int param_dim = patches.front().param_dim();
  CaseDiscretization disc;
  for (int d = 0; d < param_dim; ++d)
    for (const nurbs::Patch& patch : patches) {
      disc.degree[d] = std::max(disc.degree[d], patch.degree(d));
      disc.elements[d] = std::max(disc.elements[d], patch.knots(d).num_elements());
    }
  if (!root.has("discretization")) return disc;
  const Field field = root.at("discretization");
  field.expect_object({"degree", "elements"});
  if (field.has("degree")) disc.degree = read_per_direction(field.at("degree"), param_dim, 1);
  if (field.has("elements")) disc.elements = read_per_direction(field.at("elements"), param_dim, 1);
  for (int d = 0; d < param_dim; ++d)
    if (disc.degree[d] > 10 || disc.elements[d] > 100000)
      field.fail(": degree " + std::to_string(disc.degree[d]) + " or elements " +
                 std::to_string(disc.elements[d]) + " along " + kDirection[d] +
                 " is beyond what isospring supports (degree <= 10, elements <= 100000)");
  return disc;
}

/// The coarsest discretisation with one degree and one element count in every direction: the
/// largest degree of any patch and direction, and the least common multiple of their span counts
/// (so every span is split equally and interfaces stay conforming).
CaseDiscretization uniform_discretization(const std::vector<nurbs::Patch>& patches) {
  int degree = 1, elements = 1;
  for (const nurbs::Patch& patch : patches)
    for (int d = 0; d < patch.param_dim(); ++d) {
      degree = std::max(degree, patch.degree(d));
      elements = std::lcm(elements, patch.knots(d).num_elements());
    }
  CaseDiscretization disc;
  for (int d = 0; d < patches.front().param_dim(); ++d) {
    disc.degree[d] = degree;
    disc.elements[d] = elements;
  }
  return disc;
}

analysis::Material read_material(const Field& root) {
  const Field field = root.at("material");
  field.expect_object({"E", "nu", "density", "model"});
  analysis::Material material;
  material.youngs_modulus = field.at("E").number();
  if (!(material.youngs_modulus > 0))
    field.at("E").fail(" must be > 0 (Young's modulus in Pa), got " +
                       json(material.youngs_modulus).dump());
  material.poisson_ratio = field.at("nu").number();
  if (!(material.poisson_ratio > -1 && material.poisson_ratio < 0.5))
    field.at("nu").fail(
        " must be in (-1, 0.5) (Poisson's ratio; 0.5 is incompressible, which "
        "displacement elements cannot represent), got " +
        json(material.poisson_ratio).dump());
  if (field.has("density")) {
    material.density = field.at("density").number();
    if (material.density < 0)
      field.at("density").fail(" must be >= 0 (kg/m^3), got " + json(material.density).dump());
  }
  return material;
}

/// "material": "model": "linear" (default), "neo_hookean" or "svk"; the finite-strain laws need
/// plane strain or a solid (plane stress would need the thickness stretch as an unknown).
std::optional<analysis::HyperelasticMaterial> read_material_model(
    const Field& root, analysis::Formulation formulation) {
  const Field material = root.at("material");
  if (!material.has("model")) return std::nullopt;
  const Field field = material.at("model");
  const std::string name = field.string();
  std::optional<analysis::HyperelasticMaterial> law;
  if (name == "neo_hookean") {
    law = analysis::HyperelasticMaterial::kNeoHookean;
  } else if (name == "svk") {
    law = analysis::HyperelasticMaterial::kSaintVenantKirchhoff;
  } else if (name != "linear") {
    const std::string suggestion = case_json::closest_word(name, {"linear", "neo_hookean", "svk"});
    field.fail(": unknown material model '" + name + "'" +
               (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?") +
               " Use \"linear\" (default), \"neo_hookean\" or \"svk\"");
  }
  if (law && formulation == analysis::Formulation::kPlaneStress)
    field.fail(": '" + name +
               "' needs plane strain or a solid; in plane stress the finite-strain law would need "
               "the thickness stretch as an unknown. Set \"analysis\": {\"type\": "
               "\"plane_strain\"} or use \"linear\"");
  return law;
}

/// "analysis": plane_stress (default for 2D, thickness 1 m), plane_strain or solid (3D only).
analysis::Formulation read_formulation(const Field& root, int dimension,
                                       analysis::Material& material, int& quadrature_points,
                                       analysis::Volumetric& volumetric) {
  analysis::Formulation formulation =
      dimension == 3 ? analysis::Formulation::kSolid : analysis::Formulation::kPlaneStress;
  if (!root.has("analysis")) return formulation;
  const Field field = root.at("analysis");
  field.expect_object({"type", "thickness", "quadrature_points", "volumetric"});
  if (field.has("type")) {
    const Field type = field.at("type");
    const std::string name = type.string();
    if (name == "plane_stress") {
      formulation = analysis::Formulation::kPlaneStress;
    } else if (name == "plane_strain") {
      formulation = analysis::Formulation::kPlaneStrain;
    } else if (name == "solid") {
      formulation = analysis::Formulation::kSolid;
    } else {
      const std::string suggestion =
          case_json::closest_word(name, {"plane_stress", "plane_strain", "solid"});
      type.fail(": unknown analysis type '" + name + "'" +
                (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?") +
                " Use plane_stress, plane_strain (2D geometry) or solid (3D geometry)");
    }
    if (dimension == 3 && formulation != analysis::Formulation::kSolid)
      type.fail(": '" + name +
                "' needs 2D geometry (a surface in z = 0); this geometry is 3D, "
                "use \"solid\"");
    if (dimension == 2 && formulation == analysis::Formulation::kSolid)
      type.fail(
          ": \"solid\" needs 3D geometry (volumes); this geometry is 2D, use "
          "\"plane_stress\" or \"plane_strain\"");
  }
  if (field.has("thickness")) {
    if (dimension == 3)
      field.at("thickness").fail(": only 2D analyses have a thickness; 3D geometry has its own");
    material.thickness = field.at("thickness").positive();
  }
  if (field.has("quadrature_points")) {
    quadrature_points = field.at("quadrature_points").integer();
    if (quadrature_points < 1 || quadrature_points > 20)
      field.at("quadrature_points").fail(" must be 1..20 Gauss points per direction");
  }
  volumetric = case_json::read_volumetric(field, formulation);
  return formulation;
}

std::optional<CaseMeasurements> read_measurements(const Field& root, const fs::path& case_file) {
  if (!root.has("measurements")) return std::nullopt;
  const Field field = root.at("measurements");
  if (!field.json().is_object()) field.fail(" must be an object {\"file\": ...}");
  // Only "file" is the case reader's business; the measured-data loop validates the rest.
  const Field file = field.at("file");
  CaseMeasurements measurements;
  measurements.file = case_file.parent_path() / file.string();
  if (!fs::is_regular_file(measurements.file))
    file.fail(": '" + file.string() + "' does not exist (looked for " + measurements.file.string() +
              "; paths are relative to the case file's folder)");
  measurements.raw = field.json();
  return measurements;
}

Field root_field(const json& document, const fs::path& case_file) {
  Field root(document, file_label(case_file), "");
  if (!document.is_object())
    throw nurbs::InputError(file_label(case_file) + ": a case file is a JSON object {...}");
  root.expect_object({"schema_version", "name", "description", "units", "geometry",
                      "discretization", "analysis", "material", "boundary", "load_cases",
                      "analytic", "measurements", "calibration", "output"});
  return root;
}

/// Supports and load cases on `patches`.
void add_conditions(const Case& c, const std::vector<nurbs::Patch>& patches,
                    analysis::Problem& problem) {
  const Field root = root_field(c.raw, c.file);
  case_conditions::Context context;
  context.dimension = c.dimension;
  context.patches = &patches;
  context.analytic = c.analytic ? &*c.analytic : nullptr;
  context.density = c.problem.material.density;
  problem.supports = case_conditions::read_supports(root.at("boundary"), context);
  problem.load_cases =
      case_conditions::read_load_cases(root.at("load_cases"), problem.supports, context);
}

}  // namespace

namespace {
// The discretised patches' sizes, computed without refining.
std::vector<analysis::PatchSize> discretized_sizes(const std::vector<nurbs::Patch>& exact,
                                                   const CaseDiscretization& disc) {
  std::vector<analysis::PatchSize> sizes;
  for (const nurbs::Patch& patch : exact) {
    std::array<int, 3> elevate{0, 0, 0};
    std::array<double, 3> splits{1, 1, 1};
    for (int d = 0; d < patch.param_dim(); ++d) {
      const auto i = static_cast<size_t>(d);
      elevate[i] = std::max(0, disc.degree[i] - patch.degree(d));
      splits[i] = std::max(1, disc.elements[i] / patch.knots(d).num_elements());
    }
    sizes.push_back(analysis::refined_size(patch, elevate, {0, 0, 0}, splits));
  }
  return sizes;
}

double total_points(const std::vector<analysis::PatchSize>& sizes) {
  double points = 0;
  for (const auto& s : sizes) points += s.total_points();
  return points;
}

std::string elements_text(const CaseDiscretization& disc, int param_dim) {
  std::string text;
  for (int d = 0; d < param_dim; ++d)
    text += (d ? " x " : "") + std::to_string(disc.elements[static_cast<size_t>(d)]);
  return text;
}

// Refuses a discretisation whose refined control nets alone exceed the available memory
// (refining would run until the machine gives up).
void check_geometry_fits(const std::vector<nurbs::Patch>& exact, const CaseDiscretization& disc,
                         const std::string& where) {
  const auto sizes = discretized_sizes(exact, disc);
  const double needed = analysis::geometry_bytes(sizes),
               available = analysis::available_memory_bytes();
  if (available > 0 && needed > available)
    throw nurbs::InputError(
        where + ": discretization: " + elements_text(disc, exact.front().param_dim()) +
        " elements give " + io::format_number(total_points(sizes), 3) +
        " control points, which alone need " + analysis::format_bytes(needed) + " but " +
        analysis::format_bytes(available) + " are available (MemAvailable); use fewer elements");
}

}  // namespace

void check_solve_fits(const Case& c, const CaseDiscretization& disc, const CaseLimits& limits) {
  if (limits.solve_memory_bytes <= 0) return;
  const auto sizes = discretized_sizes(c.geometry, disc);
  const analysis::SolveEstimate e = analysis::estimate_static_solve(sizes, c.dimension);
  if (e.bytes > limits.solve_memory_bytes)
    throw nurbs::InputError(
        file_label(c.file) + ": discretization: " +
        elements_text(disc, c.geometry.front().param_dim()) + " elements give " +
        io::format_number(e.dofs, 3) + " DOFs and " + io::format_number(e.nonzeros, 3) +
        " stiffness nonzeros (each basis function couples with (2p+1)^d others); the solve "
        "needs at least " +
        analysis::format_bytes(e.bytes) + " but the limit is " +
        analysis::format_bytes(limits.solve_memory_bytes) + " (" + limits.solve_memory_source +
        "); use fewer elements or a lower degree");
}
std::vector<nurbs::Patch> discretize_patches(const std::vector<nurbs::Patch>& exact,
                                             const CaseDiscretization& disc,
                                             const std::string& where) {
  check_geometry_fits(exact, disc, where);
  std::vector<nurbs::Patch> out;
  out.reserve(exact.size());
  for (size_t p = 0; p < exact.size(); ++p) {
    const nurbs::Patch& patch = exact[p];
    std::array<int, 3> degree{1, 1, 1};
    std::array<int, 3> splits{1, 1, 1};
    for (int d = 0; d < patch.param_dim(); ++d) {
      const std::string at =
          where + ": discretization along " + kDirection[d] + " (patch " + std::to_string(p) + ")";
      if (disc.degree[d] < patch.degree(d))
        throw nurbs::InputError(at + ": degree " + std::to_string(disc.degree[d]) +
                                " is below the exact geometry's degree " +
                                std::to_string(patch.degree(d)) + "; use at least that");
      const int spans = patch.knots(d).num_elements();
      if (disc.elements[d] % spans != 0)
        throw nurbs::InputError(at + ": " + std::to_string(disc.elements[d]) +
                                " elements is not a multiple of the " + std::to_string(spans) +
                                " knot spans of the exact geometry; every span is split equally, "
                                "so use a multiple of " +
                                std::to_string(spans));
      degree[d] = disc.degree[d];
      splits[d] = disc.elements[d] / spans;
    }
    out.push_back(nurbs::k_refine(patch, degree, splits));
  }
  return out;
}

analysis::Problem problem_at(const Case& c, const CaseDiscretization& discretization) {
  analysis::Problem problem;
  problem.formulation = c.problem.formulation;
  problem.material = c.problem.material;
  problem.quadrature_points = c.problem.quadrature_points;
  problem.patches = discretize_patches(c.geometry, discretization, file_label(c.file));
  add_conditions(c, problem.patches, problem);
  return problem;
}

Case build_case_from_json(const json& document, const fs::path& case_file,
                          const CaseLimits& limits) {
  const Field root = root_field(document, case_file);
  Case c;
  c.file = case_file;
  c.raw = document;

  if (root.has("schema_version")) {
    const Field version = root.at("schema_version");
    if (version.integer() != 1)
      version.fail(": this isospring reads schema version 1, got " + version.json().dump() +
                   "; remove the field or set it to 1");
  }
  c.name = root.at("name").string();
  if (c.name.empty()) root.at("name").fail(" must not be empty");
  if (root.has("description")) root.at("description").string();
  if (root.has("units")) {
    const Field units = root.at("units");
    if (units.string() != "SI")
      units.fail(": '" + units.string() +
                 "' is not supported; isospring works in SI units (metres, pascals, kg/m^3, "
                 "newtons, seconds): convert the case and write \"units\": \"SI\"");
  }

  const Field geometry = root.at("geometry");
  c.geometry = build_case_geometry(geometry.json(), case_file.parent_path(), file_label(case_file));
  c.dimension = geometry_dimension(c.geometry, geometry);

  c.problem.material = read_material(root);
  c.problem.formulation = read_formulation(root, c.dimension, c.problem.material,
                                           c.problem.quadrature_points, c.problem.volumetric);
  c.nonlinear_material = read_material_model(root, c.problem.formulation);
  if (root.has("analytic"))
    c.analytic = make_analytic_solution(root.at("analytic").json(), c.problem.material,
                                        c.problem.formulation, root.at("analytic").where());
  c.measurements = read_measurements(root, case_file);
  if (root.has("calibration")) {
    if (!root.at("calibration").json().is_object())
      root.at("calibration").fail(" must be an object {...}");
    c.calibration = root.at("calibration").json();
  }
  if (root.has("output")) {
    // What `analyze` writes; the command-line flag wins over it.
    const Field output = root.at("output");
    output.expect_object({"vtk_samples"});
    if (output.has("vtk_samples")) c.vtk_samples = output.at("vtk_samples").integer_within(0, 64);
  }
  // Checked here although used in add_conditions, so a missing section is reported before the
  // (possibly slow) refinement.
  root.at("boundary");
  root.at("load_cases");

  c.discretization = read_discretization(root, c.geometry);
  check_solve_fits(c, c.discretization, limits);
  const auto refinement_start = std::chrono::steady_clock::now();
  c.problem.patches = discretize_patches(c.geometry, c.discretization, file_label(case_file));
  if (!root.has("discretization") && c.geometry.size() > 1 &&
      !analysis::DofMap(c.problem).unglued_interfaces().empty()) {
    // The largest degree and span count per direction refine patches of different orientations
    // differently (a CAD block's ring patches run along other axes than its boxes), which
    // breaks their interfaces; one degree and one element count for every direction keep them.
    c.discretization = uniform_discretization(c.geometry);
    check_solve_fits(c, c.discretization, limits);
    c.problem.patches = discretize_patches(c.geometry, c.discretization, file_label(case_file));
  }
  c.refinement_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - refinement_start).count();
  add_conditions(c, c.problem.patches, c.problem);
  return c;
}

Case read_case_file(const fs::path& path, const CaseLimits& limits) {
  const std::string text = read_text_file(path, "case file");
  return build_case_from_json(parse_json_text(text, path.string(), "case file"), path, limits);
}

}  // namespace isospring::io
