// Load cases from the supports (header: which cases and why).
#include "isospring/fitting/load_suite.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

bool supported(const analysis::Problem& problem, const analysis::Side& side) {
  for (const auto& s : problem.supports)
    if (!s.control_point && s.side.patch == side.patch && s.side.dir == side.dir &&
        s.side.end == side.end)
      return true;
  return false;
}

analysis::LoadCase traction_case(std::string id, const analysis::Side& side,
                                 const Eigen::Vector3d& value) {
  analysis::LoadCase lc;
  lc.id = std::move(id);
  analysis::Traction t;
  t.side = side;
  t.value = value;
  lc.tractions.push_back(t);
  return lc;
}

// Torsion about the side's own normal through the centre of its control points: t = tau n x
// (x - c) on a face of a solid (a swirl on curved faces), t = tau e_z x (x - c) on an edge of a
// membrane (an in-plane moment).
Eigen::Vector3d side_centre(const analysis::Problem& problem, const analysis::Side& side,
                            double* radius = nullptr) {
  const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  const std::vector<int> points = analysis::side_control_points(patch, side.dir, side.end);
  for (int cp : points) centre += patch.control_point(cp);
  centre /= static_cast<double>(points.size());
  if (radius) {
    *radius = 0.0;
    for (int cp : points) *radius = std::max(*radius, (patch.control_point(cp) - centre).norm());
  }
  return centre;
}

analysis::LoadCase twist_case(std::string id, const analysis::Problem& problem,
                              const analysis::Side& side, double tau) {
  const Eigen::Vector3d centre = side_centre(problem, side);
  const bool membrane = problem.formulation != analysis::Formulation::kSolid;
  analysis::LoadCase lc;
  lc.id = std::move(id);
  analysis::Traction t;
  t.side = side;
  t.function = [centre, tau, membrane](const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
    const Eigen::Vector3d axis = membrane ? Eigen::Vector3d::UnitZ() : n;
    return Eigen::Vector3d(tau * axis.cross(x - centre));
  };
  lc.tractions.push_back(t);
  return lc;
}

// t = tau (|x - c| / R) d along the oblique direction d (R: the largest distance of a control
// point of the side from their centre c): a smooth load that no sum of uniform tractions,
// twists and self-weights produces.
analysis::LoadCase ramp_case(std::string id, const analysis::Problem& problem,
                             const analysis::Side& side, double tau) {
  double radius = 0.0;
  const Eigen::Vector3d centre = side_centre(problem, side, &radius);
  const bool membrane = problem.formulation != analysis::Formulation::kSolid;
  const Eigen::Vector3d d =
      (membrane ? Eigen::Vector3d(1, 1, 0) : Eigen::Vector3d(1, 1, 1)).normalized();
  analysis::LoadCase lc;
  lc.id = std::move(id);
  analysis::Traction t;
  t.side = side;
  t.function = [centre, radius, tau, d](const Eigen::Vector3d& x, const Eigen::Vector3d&) {
    return Eigen::Vector3d(tau * (x - centre).norm() / radius * d);
  };
  lc.tractions.push_back(t);
  return lc;
}

// analysis::inner_sides is made for the faces of volumes: a surface's side is a single row of
// points, which its "collapsed along the second direction" test always takes for collapsed. For
// a surface: a side is inner when its points coincide (a pole) or its node set is another
// side's (an interface).
std::vector<std::array<bool, 6>> sides_not_to_load(const analysis::Problem& problem,
                                                   const analysis::DofMap& dofs) {
  if (problem.formulation == analysis::Formulation::kSolid)
    return analysis::inner_sides(problem.patches, dofs);
  std::vector<std::array<bool, 6>> inner(problem.patches.size(), std::array<bool, 6>{});
  std::vector<std::vector<int>> node_sets;
  std::vector<std::pair<size_t, size_t>> owner;
  for (size_t p = 0; p < problem.patches.size(); ++p)
    for (int dir = 0; dir < problem.patches[p].param_dim(); ++dir)
      for (int end = 0; end < 2; ++end) {
        const auto points = analysis::side_control_points(problem.patches[p], dir, end);
        const auto [lo, hi] = problem.patches[p].control_bounds();
        bool point = true;
        std::vector<int> nodes;
        for (int cp : points) {
          point = point && (problem.patches[p].control_point(cp) -
                            problem.patches[p].control_point(points.front()))
                                   .norm() <= 1e-9 * (hi - lo).norm();
          nodes.push_back(dofs.node(static_cast<int>(p), cp));
        }
        std::sort(nodes.begin(), nodes.end());
        const size_t side = static_cast<size_t>(2 * dir + end);
        inner[p][side] = point;
        for (size_t other = 0; other < node_sets.size(); ++other)
          if (node_sets[other] == nodes) {
            inner[p][side] = true;
            inner[owner[other].first][owner[other].second] = true;
          }
        node_sets.push_back(nodes);
        owner.emplace_back(p, side);
      }
  return inner;
}

}  // namespace

LoadSuite generate_load_suite(const analysis::Problem& problem, const LoadSuiteOptions& options) {
  if (!(options.traction > 0.0) || !(options.gravity > 0.0))
    throw nurbs::InputError("load suite: traction and gravity must be positive");
  const bool solid = problem.formulation == analysis::Formulation::kSolid;
  const int dim = solid ? 3 : 2;
  static const std::array<const char*, 3> kAxis = {"x", "y", "z"};

  LoadSuite suite;
  auto add = [&suite](analysis::LoadCase lc, bool validation) {
    (validation ? suite.validation : suite.training).push_back(lc.id);
    suite.cases.push_back(std::move(lc));
  };
  const analysis::DofMap dofs(problem);
  const std::vector<std::array<bool, 6>> inner = sides_not_to_load(problem, dofs);
  for (int p = 0; p < static_cast<int>(problem.patches.size()); ++p)
    for (int dir = 0; dir < problem.patches[static_cast<size_t>(p)].param_dim(); ++dir)
      for (int end = 0; end < 2; ++end) {
        const analysis::Side side{p, dir, end};
        if (inner[static_cast<size_t>(p)][static_cast<size_t>(2 * dir + end)] ||
            supported(problem, side))
          continue;
        const std::string prefix = "p" + std::to_string(p) + "_" + analysis::side_name(side);
        if (options.axis_tractions)
          for (int a = 0; a < dim; ++a)
            add(traction_case(prefix + "_" + kAxis[static_cast<size_t>(a)], side,
                              options.traction * Eigen::Vector3d::Unit(a)),
                false);
        if (options.twists)
          add(twist_case(prefix + "_twist", problem, side, options.traction), false);
        if (options.validation)
          add(ramp_case(prefix + "_ramp", problem, side, options.traction), true);
      }
  if (options.self_weight)
    for (int a = 0; a < dim; ++a) {
      analysis::LoadCase lc;
      lc.id = std::string("gravity_") + kAxis[static_cast<size_t>(a)];
      lc.gravity = -options.gravity * Eigen::Vector3d::Unit(a);
      add(lc, false);
    }
  if (options.validation && options.self_weight) {
    analysis::LoadCase lc;
    lc.id = "gravity_oblique";
    lc.gravity = -options.gravity *
                 (solid ? Eigen::Vector3d(1, 1, 1) : Eigen::Vector3d(1, 1, 0)).normalized();
    add(lc, true);
  }
  if (suite.cases.empty())
    throw nurbs::InputError(
        "load suite: the model has no free side to load and self-weight is off; give the load "
        "cases explicitly");
  return suite;
}

}  // namespace isospring::fitting
