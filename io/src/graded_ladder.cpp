// Graded nets for the discretisation ladder of a clamped solid (graded_ladder.hpp).
#include "isospring/io/graded_ladder.hpp"

#include <string>

#include "isospring/analysis/problem.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::io {

namespace {

// Whether the two end faces of direction `dir` are one face (a closed ring's seam): their
// control points coincide pairwise.
bool closed_direction(const nurbs::Patch& patch, int dir) {
  const auto [lo, hi] = patch.control_bounds();
  const double tolerance = 1e-12 * (1.0 + (hi - lo).norm());
  const int last = patch.num_points(dir) - 1;
  for (int i = 0; i < patch.num_points(); ++i) {
    std::array<int, 3> ijk = patch.net_position(i);
    if (ijk[static_cast<size_t>(dir)] != 0) continue;
    ijk[static_cast<size_t>(dir)] = last;
    const int j = patch.index(ijk[0], ijk[1], ijk[2]);
    if ((patch.control_point(i) - patch.control_point(j)).norm() > tolerance) return false;
  }
  return true;
}

bool is_clamp(const analysis::Support& support) {
  return !support.control_point && !support.symmetry && support.fixed[0] && support.fixed[1] &&
         support.fixed[2];
}

}  // namespace

std::optional<ClampGrading> clamp_grading(const Case& c) {
  if (c.dimension != 3 || c.geometry.size() != 1 || c.geometry[0].param_dim() != 3)
    return std::nullopt;
  ClampGrading grading;
  std::string sides;
  for (const analysis::Support& support : c.problem.supports) {
    if (!is_clamp(support) || support.side.patch != 0) continue;
    nurbs::Grading& g = grading.directions[static_cast<size_t>(support.side.dir)];
    g.exponent = kClampGradingExponent;
    (support.side.end == 0 ? g.towards_start : g.towards_end) = true;
    const std::string name = analysis::side_name(support.side);
    if (sides.find(name) == std::string::npos) sides += (sides.empty() ? "" : ", ") + name;
  }
  if (sides.empty()) return std::nullopt;
  for (int d = 0; d < 3; ++d) {
    nurbs::Grading& g = grading.directions[static_cast<size_t>(d)];
    if (g.graded() || closed_direction(c.geometry[0], d)) continue;
    g = {kClampGradingExponent, true, true};  // across the clamp: towards its edges
  }
  grading.label = "graded towards the clamp (" + sides + ")";
  return grading;
}

analysis::Problem graded_problem_at(const Case& c, const CaseDiscretization& disc,
                                    const ClampGrading& grading) {
  const nurbs::Patch& exact = c.geometry.at(0);
  CaseDiscretization elevated = disc;
  for (int d = 0; d < 3; ++d)
    elevated.elements[static_cast<size_t>(d)] = exact.knots(d).num_elements();
  // The case's conditions on the elevated net, then the net refined under them.
  analysis::Problem problem = problem_at(c, elevated);
  const nurbs::Patch coarse = problem.patches.at(0);
  nurbs::Patch patch = coarse;
  for (int d = 0; d < 3; ++d) {
    const auto i = static_cast<size_t>(d);
    if (grading.directions[i].graded()) {
      patch = nurbs::refine_graded(patch, d, disc.elements[i], grading.directions[i]);
    } else {
      const int spans = exact.knots(d).num_elements();
      if (disc.elements[i] % spans != 0)
        throw nurbs::InputError(
            c.file.string() + ": graded ladder: " + std::to_string(disc.elements[i]) +
            " elements is not a multiple of the exact geometry's " + std::to_string(spans) +
            " spans along direction " + std::to_string(d));
      patch = nurbs::refine_uniform(patch, d, disc.elements[i] / spans);
    }
  }
  problem.patches[0] = patch;
  // Conditions on single control points: a net corner stays the same corner (knot insertion
  // keeps the corners where they are); any other control point has no counterpart.
  auto follow = [&](int& index, const std::string& what) {
    std::array<int, 3> ijk = coarse.net_position(index);
    for (int d = 0; d < 3; ++d) {
      auto& at = ijk[static_cast<size_t>(d)];
      if (at != 0 && at != coarse.num_points(d) - 1)
        throw nurbs::InputError(
            c.file.string() + ": " + what + " is on control point " + std::to_string(index) +
            ", not a corner of the net: it has no counterpart on a refined net. Support or load "
            "whole sides, or turn the discretisation check off (\"discretization_check\": false)");
      if (at != 0) at = patch.num_points(d) - 1;
    }
    index = patch.index(ijk[0], ijk[1], ijk[2]);
  };
  for (size_t s = 0; s < problem.supports.size(); ++s)
    if (problem.supports[s].control_point)
      follow(*problem.supports[s].control_point, "support " + std::to_string(s + 1));
  for (auto& load : problem.load_cases)
    for (size_t k = 0; k < load.point_loads.size(); ++k)
      follow(load.point_loads[k].control_point,
             "point load " + std::to_string(k + 1) + " of load case " + load.id);
  return problem;
}

}  // namespace isospring::io
