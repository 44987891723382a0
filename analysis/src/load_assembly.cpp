// Load vectors, lumped mass and volume: the integrals of single basis functions.
#include <string>

#include "assembly_structure.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

// Calls f(patch, control_points, point, weight * |J| * thickness) at every volume quadrature
// point of every patch.
template <class F>
void for_each_volume_point(const Problem& problem, F&& f) {
  const int dim = spatial_dimension(problem.formulation);
  const double thickness = thickness_factor(problem);
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const auto quadrature =
        detail::PatchQuadrature::volume(problem.patches[p], problem.quadrature_points);
    std::vector<int> cps(static_cast<size_t>(quadrature.basis_count()));
    detail::QuadraturePoint point;
    Eigen::MatrixXd g(quadrature.basis_count(), dim);
    for (int e = 0; e < quadrature.num_elements(); ++e) {
      quadrature.element_control_points(e, cps.data());
      for (int q = 0; q < quadrature.points_per_element(); ++q) {
        quadrature.evaluate(e, q, point);
        const double det = detail::physical_gradients(point, dim, static_cast<int>(p), e, g);
        f(static_cast<int>(p), cps, point, point.weight * det * thickness);
      }
    }
  }
}

// Calls f(control_points, point, frame, weight * measure * thickness) over a side.
template <class F>
void for_each_side_point(const Problem& problem, const Side& side, F&& f) {
  const auto& patch = problem.patches[static_cast<size_t>(side.patch)];
  const double thickness = thickness_factor(problem);
  const auto quadrature =
      detail::PatchQuadrature::side(patch, side.dir, side.end, problem.quadrature_points);
  std::vector<int> cps(static_cast<size_t>(quadrature.basis_count()));
  detail::QuadraturePoint point;
  for (int e = 0; e < quadrature.num_elements(); ++e) {
    quadrature.element_control_points(e, cps.data());
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      quadrature.evaluate(e, q, point);
      const SideFrame frame = side_frame(point.jacobian, patch.param_dim(), side.dir, side.end);
      f(cps, point, frame, point.weight * frame.measure * thickness);
    }
  }
}

}  // namespace

std::vector<std::vector<double>> lumped_mass(const Problem& problem) {
  std::vector<std::vector<double>> mass(problem.patches.size());
  for (size_t p = 0; p < problem.patches.size(); ++p)
    mass[p].assign(static_cast<size_t>(problem.patches[p].num_points()), 0.0);
  const double rho = problem.material.density;
  for_each_volume_point(problem, [&](int patch, const std::vector<int>& cps,
                                     const detail::QuadraturePoint& point, double dv) {
    for (size_t a = 0; a < cps.size(); ++a)
      mass[static_cast<size_t>(patch)][static_cast<size_t>(cps[a])] +=
          rho * point.values[static_cast<Eigen::Index>(a)] * dv;
  });
  return mass;
}

Eigen::VectorXd lumped_node_mass(const Problem& problem, const DofMap& dofs) {
  const auto mass = lumped_mass(problem);
  Eigen::VectorXd node_mass = Eigen::VectorXd::Zero(dofs.num_nodes());
  for (size_t p = 0; p < mass.size(); ++p)
    for (size_t i = 0; i < mass[p].size(); ++i)
      node_mass[dofs.node(static_cast<int>(p), static_cast<int>(i))] += mass[p][i];
  return node_mass;
}

double model_volume(const Problem& problem) {
  double volume = 0.0;
  for_each_volume_point(problem, [&](int, const std::vector<int>&, const detail::QuadraturePoint&,
                                     double dv) { volume += dv; });
  return volume;
}

Eigen::VectorXd assemble_load(const Problem& problem, const DofMap& dofs, const LoadCase& load) {
  const int dim = dofs.dofs_per_node();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs.num_dofs());
  auto add = [&](int patch, int cp, const Eigen::Vector3d& force) {
    for (int c = 0; c < dim; ++c) f[dofs.dof(patch, cp, c)] += force[c];
  };
  const Eigen::Vector3d body = load.body_force + problem.material.density * load.gravity;
  if (body.squaredNorm() > 0.0)
    for_each_volume_point(problem, [&](int patch, const std::vector<int>& cps,
                                       const detail::QuadraturePoint& point, double dv) {
      for (size_t a = 0; a < cps.size(); ++a)
        add(patch, cps[a], point.values[static_cast<Eigen::Index>(a)] * dv * body);
    });
  for (const auto& traction : load.tractions)
    for_each_side_point(
        problem, traction.side,
        [&](const std::vector<int>& cps, const detail::QuadraturePoint& point,
            const SideFrame& frame, double ds) {
          if (ds == 0.0) return;  // degenerate (collapsed) part of the side
          const Eigen::Vector3d t =
              traction.function ? traction.function(point.point, frame.normal) : traction.value;
          for (size_t a = 0; a < cps.size(); ++a)
            add(traction.side.patch, cps[a], point.values[static_cast<Eigen::Index>(a)] * ds * t);
        });
  for (const auto& pressure : load.pressures)
    for_each_side_point(problem, pressure.side,
                        [&](const std::vector<int>& cps, const detail::QuadraturePoint& point,
                            const SideFrame& frame, double ds) {
                          // Positive pressure pushes into the body: t = -p n (n outward).
                          const Eigen::Vector3d t = -pressure.value * frame.normal;
                          for (size_t a = 0; a < cps.size(); ++a)
                            add(pressure.side.patch, cps[a],
                                point.values[static_cast<Eigen::Index>(a)] * ds * t);
                        });
  for (const auto& point_load : load.point_loads)
    add(point_load.patch, point_load.control_point, point_load.force);
  return f;
}

}  // namespace isospring::analysis
