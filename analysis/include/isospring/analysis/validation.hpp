#pragma once
// Checks a Problem before any assembly so bad input ends in one clear nurbs::InputError.
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct ValidationOptions {
  bool require_load_cases = true;  // static solves need at least one load case
  bool require_density = false;    // mass matrices and modes need rho > 0
};

/// Material ranges, patch dimensions against the formulation (plane: surfaces with z = 0; solid:
/// volumes), side/patch/control-point indices of supports and loads, load-case ids, and loads
/// on sides whose every displacement component is fixed (they would only produce reactions).
void validate_problem(const Problem& problem, const ValidationOptions& options = {});

}  // namespace isospring::analysis
