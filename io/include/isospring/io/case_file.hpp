#pragma once
// Case files: one JSON document describing a whole analysis (schema version 1; every field is
// documented field by field in docs/case-files.md).
//
//   {"name": "cantilever", "units": "SI",
//    "geometry": {"type": "box", "size": [0.1, 0.02, 0.02]},
//    "discretization": {"degree": [2, 2, 2], "elements": [20, 4, 4]},
//    "material": {"E": 50000.0, "nu": 0.45, "density": 1100.0},
//    "boundary": [{"side": "u0", "fix": ["x", "y", "z"]}],
//    "load_cases": [{"id": "L1", "tractions": [{"side": "u1", "value": [0, 0, -100.0]}]}]}
//
// The reader validates everything it can before any computation: unknown fields (with a
// suggestion), missing or mistyped fields, NaN/inf, material ranges, side names, duplicate ids,
// loads on fully fixed sides, empty load cases. Every problem is a nurbs::InputError whose message
// starts with the case file's name and the field's path, e.g.
//   "case.json: load_cases[0].traction: unknown field; did you mean 'tractions'?".
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::io {

/// Degree and number of elements per parametric direction (entries beyond the geometry's
/// parametric dimension are unused). Discretising elevates the exact geometry to `degree` and then
/// splits every existing knot span of a direction into elements[d] / (existing spans) equal spans,
/// so each patch has exactly elements[d] elements along d.
struct CaseDiscretization {
  std::array<int, 3> degree{0, 0, 0};
  std::array<int, 3> elements{1, 1, 1};
};

/// A closed-form solution the case reproduces (`"analytic"`), used by `study` for errors and by
/// boundary conditions written as "value": "analytic". Fields are functions of the position x.
struct AnalyticSolution {
  std::string type;       // kirsch, lame_cylinder, timoshenko, hollow_sphere
  nlohmann::json fields;  // the case file's object, as written
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> displacement;
  std::function<Eigen::Matrix3d(const Eigen::Vector3d&)> stress;  // Cauchy stress tensor
};

/// `"measurements"`: the data file (resolved against the case file's folder; it must exist) and
/// the whole object for the measured-data loop, which validates its own sub-fields.
struct CaseMeasurements {
  std::filesystem::path file;
  nlohmann::json raw;
};

struct Case {
  std::string name;
  std::filesystem::path file;          // the case file (as given)
  nlohmann::json raw;                  // the document as read
  int dimension = 3;                   // 2 (plane) or 3 (solid)
  std::vector<nurbs::Patch> geometry;  // exact geometry, before discretisation
  CaseDiscretization discretization;
  analysis::Problem problem;  // at `discretization`
  /// `material.model`: empty for "linear" (the default, small-strain elasticity); otherwise the
  /// hyperelastic law ("neo_hookean", "svk") of analysis::solve_static_nonlinear, refused in plane
  /// stress (neither law is exact there at finite strain).
  std::optional<analysis::HyperelasticMaterial> nonlinear_material;
  std::optional<AnalyticSolution> analytic;
  std::optional<CaseMeasurements> measurements;
  nlohmann::json calibration;  // `"calibration"` as written (null when absent); its users validate
  /// `"output": {"vtk_samples": N}`: sample points per element and direction of analyze's
  /// sampled volume (0: no ParaView output); -1 when the case does not say.
  int vtk_samples = -1;
  double refinement_seconds = 0;  // of reading it: elevating and splitting the geometry
};

/// Limits checked while reading, before the discretisation is built. The refined control nets
/// must always fit in the available memory (analysis::geometry_bytes).
struct CaseLimits {
  /// > 0: also refuse a case whose static solve needs more (analysis::estimate_static_solve).
  double solve_memory_bytes = 0;
  /// Where that limit comes from, for the message ("--max-memory 2 GB").
  std::string solve_memory_source;
};

/// Reads, validates and discretises a case file.
Case read_case_file(const std::filesystem::path& path, const CaseLimits& limits = {});

/// The same from a parsed document; `case_file` names it in messages and anchors relative paths.
Case build_case_from_json(const nlohmann::json& document, const std::filesystem::path& case_file,
                          const CaseLimits& limits = {});

/// The case's problem at another discretisation (refinement studies): same geometry, material,
/// supports and loads. Throws InputError when the discretisation is not possible (degree below the
/// geometry's, elements not a multiple of the existing spans, a control point index out of range).
analysis::Problem problem_at(const Case& c, const CaseDiscretization& discretization);

/// With limits.solve_memory_bytes > 0: throws InputError with the estimate (DOFs, stiffness
/// nonzeros, bytes) when the static solve of `c` at `discretization` needs more, checked from
/// the sizes alone, before refining (analysis::estimate_static_solve).
void check_solve_fits(const Case& c, const CaseDiscretization& discretization,
                      const CaseLimits& limits);

/// Elevates and splits exact patches as described at CaseDiscretization; `where` prefixes errors.
std::vector<nurbs::Patch> discretize_patches(const std::vector<nurbs::Patch>& exact,
                                             const CaseDiscretization& discretization,
                                             const std::string& where);

/// The closed-form solution named by an `"analytic"` object, for the given material and
/// formulation. `where` prefixes errors ("case.json: analytic").
AnalyticSolution make_analytic_solution(const nlohmann::json& analytic,
                                        const analysis::Material& material,
                                        analysis::Formulation formulation,
                                        const std::string& where);

}  // namespace isospring::io
