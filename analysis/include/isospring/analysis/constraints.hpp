#pragma once
// Supports turned into prescribed DOF values, and the rigid-body check that catches models the
// supports do not hold in place before anything is factorised.
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

struct Constraints {
  std::vector<int> dofs;       // sorted, unique
  std::vector<double> values;  // prescribed value of each
};

/// Applies every Support of the problem:
/// - constant values go to every control point of the side (exact: the basis sums to one);
/// - value_function is L2-projected onto the side's control values (int_side R_a R_b c_b =
///   int_side R_a g), so a prescribed field in the spline space is imposed exactly and others
///   optimally (interpolating at control points would be off by O(h^2) for curved fields);
/// - symmetry fixes the displacement component along the side's normal, which must be a
///   coordinate axis (InputError otherwise);
/// - control_point restricts the support to that control point of side.patch (g evaluated there).
/// Two supports prescribing different constant values on one DOF are an InputError.
Constraints build_constraints(const Problem& problem, const DofMap& dofs);

/// Throws nurbs::InputError "the supports leave free: translation x, rotation about z ..." when,
/// for some connected part of the model, the constrained DOFs do not block all 3 (2D) or 6 (3D)
/// rigid-body motions.
void check_rigid_body_modes(const Problem& problem, const DofMap& dofs,
                            const Constraints& constraints);

/// What every static solver starts with: validate_problem, the DofMap, the constraints and
/// check_rigid_body_modes, in that order.
struct SupportedProblem {
  DofMap dofs;
  Constraints constraints;
};
SupportedProblem number_and_support(const Problem& problem);

}  // namespace isospring::analysis
