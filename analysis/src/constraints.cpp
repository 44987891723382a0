// Supports -> prescribed DOF values.
#include "isospring/analysis/constraints.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <map>

#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/validation.hpp"
#include "isospring/nurbs/error.hpp"
#include "patch_quadrature.hpp"

namespace isospring::analysis {

namespace {

std::string where(const Support& support, size_t index) {
  return "supports[" + std::to_string(index) + "] (patch " + std::to_string(support.side.patch) +
         ", side " + side_name(support.side) + ")";
}

// L2 projection of g onto the control values of a side: returns one vector per side point.
std::vector<Eigen::Vector3d> project_on_side(
    const Problem& problem, const Side& side,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& g) {
  const auto& patch = problem.patches[static_cast<size_t>(side.patch)];
  const std::vector<int> side_points = side_control_points(patch, side.dir, side.end);
  std::map<int, int> local;
  for (size_t i = 0; i < side_points.size(); ++i) local[side_points[i]] = static_cast<int>(i);
  const int n = static_cast<int>(side_points.size());
  // One more point than the default rule: the mass integrand is degree 2p times a rational.
  int max_degree = 0;
  for (int d = 0; d < patch.param_dim(); ++d) max_degree = std::max(max_degree, patch.degree(d));
  const auto quadrature = detail::PatchQuadrature::side(
      patch, side.dir, side.end, std::max(problem.quadrature_points, max_degree + 2));
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  std::vector<int> cps(static_cast<size_t>(quadrature.basis_count()));
  detail::QuadraturePoint point;
  double measure = 0.0;
  for (int e = 0; e < quadrature.num_elements(); ++e) {
    quadrature.element_control_points(e, cps.data());
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      quadrature.evaluate(e, q, point);
      const double ds =
          point.weight * side_frame(point.jacobian, patch.param_dim(), side.dir, side.end).measure;
      if (ds == 0.0) continue;
      measure += ds;
      const Eigen::Vector3d value = g(point.point);
      for (size_t a = 0; a < cps.size(); ++a) {
        const auto ia = local.find(cps[a]);
        const double ra = point.values[static_cast<Eigen::Index>(a)];
        if (ia == local.end() || ra == 0.0) continue;  // not on the side: vanishes there
        rhs.row(ia->second) += ds * ra * value.transpose();
        for (size_t b = 0; b < cps.size(); ++b) {
          const auto ib = local.find(cps[b]);
          if (ib != local.end())
            triplets.emplace_back(ia->second, ib->second,
                                  ds * ra * point.values[static_cast<Eigen::Index>(b)]);
        }
      }
    }
  }
  std::vector<Eigen::Vector3d> values(static_cast<size_t>(n));
  if (measure == 0.0) {  // a side collapsed to a point: interpolate
    for (int i = 0; i < n; ++i)
      values[static_cast<size_t>(i)] = g(patch.control_point(side_points[static_cast<size_t>(i)]));
    return values;
  }
  Eigen::SparseMatrix<double> mass(n, n);
  mass.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(mass);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("L2 projection of a prescribed displacement on patch " +
                             std::to_string(side.patch) + ", side " + side_name(side) +
                             " failed: the side's mass matrix is singular");
  const Eigen::MatrixXd solution = solver.solve(rhs);
  for (int i = 0; i < n; ++i) values[static_cast<size_t>(i)] = solution.row(i).transpose();
  return values;
}

// The coordinate axis a symmetry side is normal to; InputError when it is not a plane x/y/z =
// const.
int symmetry_axis(const Problem& problem, const Support& support, size_t index) {
  const auto& patch = problem.patches[static_cast<size_t>(support.side.patch)];
  const auto quadrature =
      detail::PatchQuadrature::side(patch, support.side.dir, support.side.end, 0);
  detail::QuadraturePoint point;
  int axis = -1;
  for (int e = 0; e < quadrature.num_elements(); ++e)
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      quadrature.evaluate(e, q, point);
      const SideFrame frame =
          side_frame(point.jacobian, patch.param_dim(), support.side.dir, support.side.end);
      if (frame.measure == 0.0) continue;
      Eigen::Index best;
      const double alignment = frame.normal.cwiseAbs().maxCoeff(&best);
      if (alignment < 1.0 - 1e-8 || (axis >= 0 && axis != static_cast<int>(best)))
        throw nurbs::InputError(
            where(support, index) +
            ": a symmetry support needs a plane side normal to a coordinate axis, but the "
            "side's normal is (" +
            std::to_string(frame.normal.x()) + ", " + std::to_string(frame.normal.y()) + ", " +
            std::to_string(frame.normal.z()) + ") at parameter (" + std::to_string(point.param[0]) +
            ", " + std::to_string(point.param[1]) +
            "); fix the normal displacement component with `fixed` instead");
      axis = static_cast<int>(best);
    }
  if (axis < 0)
    throw nurbs::InputError(where(support, index) +
                            ": the side is degenerate (zero area), a symmetry condition has no "
                            "normal there; use `fixed` components instead");
  return axis;
}

}  // namespace

Constraints build_constraints(const Problem& problem, const DofMap& dofs) {
  const int dim = dofs.dofs_per_node();
  struct Prescribed {
    double value;
    bool constant;
    size_t support;
  };
  std::map<int, Prescribed> prescribed;
  auto prescribe = [&](int dof, double value, bool constant, size_t index) {
    const auto it = prescribed.find(dof);
    if (it != prescribed.end() && constant && it->second.constant &&
        std::abs(it->second.value - value) > 1e-12 * (1.0 + std::abs(value)))
      throw nurbs::InputError(where(problem.supports[index], index) + " prescribes " +
                              std::to_string(value) + " on a displacement component that " +
                              where(problem.supports[it->second.support], it->second.support) +
                              " sets to " + std::to_string(it->second.value) +
                              "; make the two supports agree where they meet");
    prescribed[dof] = {value, constant, index};
  };
  for (size_t s = 0; s < problem.supports.size(); ++s) {
    const Support& support = problem.supports[s];
    const auto& patch = problem.patches[static_cast<size_t>(support.side.patch)];
    std::array<bool, 3> fixed = support.fixed;
    if (support.symmetry) fixed[static_cast<size_t>(symmetry_axis(problem, support, s))] = true;
    std::vector<int> points;
    std::vector<Eigen::Vector3d> values;
    if (support.control_point) {
      points = {*support.control_point};
      const Eigen::Vector3d x = patch.control_point(*support.control_point);
      values = {support.value_function ? support.value_function(x) : support.value};
    } else {
      points = side_control_points(patch, support.side.dir, support.side.end);
      values = support.value_function
                   ? project_on_side(problem, support.side, support.value_function)
                   : std::vector<Eigen::Vector3d>(points.size(), support.value);
    }
    const bool constant = !support.value_function;
    for (size_t i = 0; i < points.size(); ++i)
      for (int c = 0; c < dim; ++c) {
        if (!fixed[static_cast<size_t>(c)]) continue;
        // A symmetry component is zero whatever `value` says.
        const bool symmetric_component = support.symmetry && !support.fixed[static_cast<size_t>(c)];
        prescribe(dofs.dof(support.side.patch, points[i], c),
                  symmetric_component ? 0.0 : values[i][c], constant || symmetric_component, s);
      }
  }
  Constraints constraints;
  for (const auto& [dof, p] : prescribed) {
    constraints.dofs.push_back(dof);
    constraints.values.push_back(p.value);
  }
  return constraints;
}

SupportedProblem number_and_support(const Problem& problem) {
  validate_problem(problem);
  SupportedProblem supported{DofMap(problem), {}};
  supported.constraints = build_constraints(problem, supported.dofs);
  check_rigid_body_modes(problem, supported.dofs, supported.constraints);
  return supported;
}

}  // namespace isospring::analysis
