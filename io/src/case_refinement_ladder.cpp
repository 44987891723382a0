// k-refinement ladder of a case file (case_refinement_ladder.hpp).
#include "isospring/io/case_refinement_ladder.hpp"

#include <algorithm>
#include <numeric>

#include "isospring/io/graded_ladder.hpp"

namespace isospring::io {

namespace {

// Degree elevation stops here: a degree-p basis couples (2p + 1)^d functions, so a degree-4
// solid has 729 couplings per function against 343 at degree 3 and its factorisation costs
// several times more for the same DOFs (measured: 49 s for 19,008 degree-4 DOFs).
int max_ladder_degree(int parametric_dimension) {
  return parametric_dimension >= 3 ? 3 : 4;
}

int parametric_dimension(const Case& c) {
  int dim = 1;
  for (const auto& patch : c.geometry) dim = std::max(dim, patch.param_dim());
  return dim;
}

}  // namespace

CaseDiscretization ladder_discretization(const Case& c, int level) {
  const int dim = parametric_dimension(c);
  CaseDiscretization disc = c.discretization;
  const int cap = max_ladder_degree(dim);
  int elevations = 0;  // levels spent raising degrees
  for (int d = 0; d < dim; ++d) elevations = std::max(elevations, cap - c.discretization.degree[d]);
  const int raise = std::min(level, elevations);
  for (int d = 0; d < dim; ++d)
    disc.degree[d] =
        std::max(c.discretization.degree[d], std::min(c.discretization.degree[d] + raise, cap));
  const int doublings = level - raise;
  for (int d = 0; d < dim; ++d) disc.elements[d] = c.discretization.elements[d] << doublings;
  return disc;
}

int case_ladder_ratio_from_level(const Case& c) {
  if (!clamp_grading(c)) return 0;
  int level = 1;
  while (level < 12 &&
         ladder_discretization(c, level).degree != ladder_discretization(c, level + 1).degree)
    ++level;
  return level;
}

std::optional<CaseDiscretization> intermediate_discretization(const Case& c, int level) {
  if (level < 2) return std::nullopt;
  const CaseDiscretization below = ladder_discretization(c, level - 1);
  if (below.degree != ladder_discretization(c, level).degree) return std::nullopt;
  CaseDiscretization disc = below;
  const int dim = parametric_dimension(c);
  bool coarser = false;
  for (int d = 0; d < dim; ++d) {
    // Every span of the exact geometry is split equally: a multiple of each patch's spans.
    int spans = 1;
    for (const auto& patch : c.geometry)
      if (d < patch.param_dim()) spans = std::lcm(spans, patch.knots(d).num_elements());
    const int wanted = (3 * below.elements[d] + 1) / 2;
    disc.elements[d] = (wanted + spans - 1) / spans * spans;
    coarser = coarser || disc.elements[d] < 2 * below.elements[d];
  }
  if (!coarser) return std::nullopt;  // rounding made it level `level` itself
  return disc;
}

namespace {

// "degree 3,3,3, 20 x 4 x 4 elements"
std::string describe(const Case& c, const CaseDiscretization& disc) {
  const int dim = parametric_dimension(c);
  std::string degrees, elements;
  for (int d = 0; d < dim; ++d) {
    degrees += (d ? "," : "") + std::to_string(disc.degree[d]);
    elements += (d ? " x " : "") + std::to_string(disc.elements[d]);
  }
  return "degree " + degrees + ", " + elements + " elements";
}

}  // namespace

namespace {

// The problem at `disc`, on graded nets when the case is a clamped solid (graded_ladder.hpp).
analysis::Problem level_problem(const Case& c, const CaseDiscretization& disc,
                                const std::optional<ClampGrading>& grading,
                                std::string* description) {
  if (description) *description = describe(c, disc) + (grading ? ", " + grading->label : "");
  return grading ? graded_problem_at(c, disc, *grading) : problem_at(c, disc);
}

}  // namespace

fitting::DiscretizationLadder case_refinement_ladder(const Case& c) {
  return [c, grading = clamp_grading(c)](
             int level, std::string* description) -> std::optional<analysis::Problem> {
    if (level < 1 || level > 12) return std::nullopt;
    return level_problem(c, ladder_discretization(c, level), grading, description);
  };
}

fitting::DiscretizationLadder case_refinement_intermediate(const Case& c) {
  return [c, grading = clamp_grading(c)](
             int level, std::string* description) -> std::optional<analysis::Problem> {
    if (level > 12) return std::nullopt;
    const std::optional<CaseDiscretization> disc = intermediate_discretization(c, level);
    if (!disc) return std::nullopt;
    return level_problem(c, *disc, grading, description);
  };
}

}  // namespace isospring::io
