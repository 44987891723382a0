#pragma once
// Graded nets for the discretisation ladder of a clamped solid (case_refinement_ladder.hpp).
//
// The edges of a clamped face carry singular stresses (displacement ~ r^a, a ~ 0.5-0.7, lower as
// nu -> 0.5), which slow uniform refinement of every degree to an error ratio of ~0.4 per halving
// of h at markers far from the clamp. The graded nets keep the ladder's degrees and element
// counts but place the spans as nurbs::refine_graded does with exponent 2: along the clamped
// side's normal direction towards the clamp, across it towards both faces (where the clamp's
// edges are), except around a closed direction (a full ring, whose two ends are one seam).
// Measured on the identify suite's cantilever (tests/analysis/test_bbar_dofs.cpp): 3.7-3.9 x
// smaller tip errors than the uniform net of the same DOFs at nu = 0.45 / 0.49, degree 3,
// 20 x 4 x 4. The levels stay nested ((i / n)^2 = (2i / 2n)^2) and of one family at a fixed
// exponent, so successive differences still shrink by a steady ratio, which the check's
// Richardson estimate needs.
#include <array>
#include <optional>
#include <string>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/graded_refine.hpp"

namespace isospring::io {

/// The grading exponent of every graded direction.
inline constexpr double kClampGradingExponent = 2.0;

struct ClampGrading {
  std::array<nurbs::Grading, 3> directions;  // per parametric direction (exponent 1: uniform)
  std::string label;                         // "graded towards the clamp (u0)"
};

/// The grading of case `c`: a single-patch solid (3 parametric directions) with at least one
/// side whose every displacement component is fixed (a clamp, not a symmetry plane or a single
/// control point); nullopt for any other case, which keeps uniform nets.
std::optional<ClampGrading> clamp_grading(const Case& c);

/// The case's problem with the degrees and elements of `disc`, spans placed by `grading`:
/// the exact geometry is elevated, then graded directions get disc.elements[d] graded spans
/// (the exact geometry's own knots kept), the others every exact span split equally.
analysis::Problem graded_problem_at(const Case& c, const CaseDiscretization& disc,
                                    const ClampGrading& grading);

}  // namespace isospring::io
