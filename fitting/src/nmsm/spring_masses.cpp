// Masses (lumped IGA or net cells) and the [S15] stiffness bounds, both from control-net cells.
#include "isospring/fitting/spring_masses.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

double quad_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 const Eigen::Vector3d& d) {
  // Corners in net order a=(0,0) b=(1,0) c=(0,1) d=(1,1): the diagonals are d-a and c-b.
  return 0.5 * (d - a).cross(c - b).norm();
}

double tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

// Corners in net order (bit 0: i, bit 1: j, bit 2: k). Six tetrahedra sharing the diagonal 0-7.
double hex_volume(const std::vector<Eigen::Vector3d>& x) {
  const int paths[6][2] = {{1, 3}, {3, 2}, {2, 6}, {6, 4}, {4, 5}, {5, 1}};
  double volume = 0.0;
  for (const auto& p : paths) volume += tet_volume(x[0], x[p[0]], x[p[1]], x[7]);
  return std::abs(volume);
}

}  // namespace

std::vector<NetCell> net_cells(const analysis::Problem& problem, const SpringMesh& mesh) {
  const bool plane = analysis::spatial_dimension(problem.formulation) == 2;
  const double thickness = plane ? problem.material.thickness : 1.0;
  std::vector<NetCell> cells;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const nurbs::Patch& patch = problem.patches[p];
    const bool solid = patch.param_dim() == 3;
    const int n0 = patch.num_points(0), n1 = patch.num_points(1);
    const int c2 = solid ? patch.num_points(2) - 1 : 1;
    for (int k = 0; k < c2; ++k)
      for (int j = 0; j + 1 < n1; ++j)
        for (int i = 0; i + 1 < n0; ++i) {
          NetCell cell;
          std::vector<Eigen::Vector3d> x;
          for (int dk = 0; dk < (solid ? 2 : 1); ++dk)
            for (int dj = 0; dj < 2; ++dj)
              for (int di = 0; di < 2; ++di) {
                const int cp = patch.index(i + di, j + dj, k + dk);
                cell.corners.push_back(mesh.particle[p][static_cast<size_t>(cp)]);
                x.push_back(patch.control_point(cp));
              }
          cell.measure = solid ? hex_volume(x) : thickness * quad_area(x[0], x[1], x[2], x[3]);
          cells.push_back(std::move(cell));
        }
  }
  return cells;
}

void assign_masses(const analysis::Problem& problem, SpringMesh& mesh, MassModel model) {
  const double rho = problem.material.density;
  if (!(rho > 0.0) || !std::isfinite(rho))
    throw nurbs::InputError("material density = " + std::to_string(rho) +
                            ": the spring model needs a positive density for its masses");
  auto& masses = mesh.network.masses;
  masses.assign(mesh.network.positions.size(), 0.0);
  if (model == MassModel::kLumpedIga) {
    const auto lumped = analysis::lumped_mass(problem);
    for (size_t p = 0; p < lumped.size(); ++p)
      for (size_t cp = 0; cp < lumped[p].size(); ++cp)
        masses[mesh.particle[p][cp]] += lumped[p][cp];
    // Glued control points appear once per patch in `lumped`, each with its own patch's share,
    // so the sum above is already the node's mass.
    return;
  }
  for (const NetCell& cell : net_cells(problem, mesh)) {
    const double share = rho * cell.measure / static_cast<double>(cell.corners.size());
    for (int q : cell.corners) masses[q] += share;
  }
}

std::vector<double> stiffness_upper_bounds(const analysis::Problem& problem,
                                           const SpringMesh& mesh) {
  const auto& net = mesh.network;
  const double e = problem.material.youngs_modulus, nu = problem.material.poisson_ratio;
  // Per particle: the number of cells containing it and the largest of their measures.
  std::vector<int> cell_count(net.positions.size(), 0);
  std::vector<double> largest(net.positions.size(), 0.0);
  for (const NetCell& cell : net_cells(problem, mesh)) {
    std::vector<int> unique = cell.corners;
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    for (int q : unique) {
      ++cell_count[q];
      largest[q] = std::max(largest[q], cell.measure);
    }
  }
  const double root_d = std::sqrt(static_cast<double>(net.dimension));
  std::vector<double> bounds;
  bounds.reserve(net.springs.size());
  for (const auto& s : net.springs)
    bounds.push_back(cell_count[s.i] * root_d * e * (1.0 + nu) * largest[s.i] /
                     (2.0 * s.rest_length * s.rest_length));
  return bounds;
}

}  // namespace isospring::fitting
