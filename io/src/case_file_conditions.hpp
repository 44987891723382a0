#pragma once
// Boundary conditions and load cases of a case file, translated into analysis types for a given
// discretisation (control-point indices depend on it; sides do not).
#include <optional>
#include <vector>

#include "case_file_json.hpp"
#include "isospring/analysis/problem.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::io::case_conditions {

struct Context {
  int dimension = 3;                           // 2 or 3
  const std::vector<nurbs::Patch>* patches;    // discretised
  const AnalyticSolution* analytic = nullptr;  // null when the case names none
  double density = 0.0;
};

/// `"boundary"` entries -> supports.
std::vector<analysis::Support> read_supports(const case_json::Field& boundary,
                                             const Context& context);

/// `"load_cases"` -> load cases; checks ids are unique, cases are not empty and no traction or
/// pressure acts on a side the supports fix completely.
std::vector<analysis::LoadCase> read_load_cases(const case_json::Field& load_cases,
                                                const std::vector<analysis::Support>& supports,
                                                const Context& context);

}  // namespace isospring::io::case_conditions
