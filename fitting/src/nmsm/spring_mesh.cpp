// Springs on the control nets: all corner pairs of every net cell, collected once per particle
// pair.
#include "isospring/fitting/spring_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <utility>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_strain_point.hpp"
#include "isospring/analysis/spring_volume.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm/net_springs.hpp"

namespace isospring::fitting {

namespace {

// Union of coincident points: sort along x and compare within the tolerance window, so the cost is
// O(n log n) for nets without large clusters of equal x.
std::vector<int> merge_coincident(const std::vector<Eigen::Vector3d>& points, double tolerance) {
  const int n = static_cast<int>(points.size());
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return points[a].x() < points[b].x(); });
  std::vector<int> root(static_cast<size_t>(n));
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int a) {
    while (root[a] != a) a = root[a] = root[root[a]];
    return a;
  };
  for (int s = 0; s < n; ++s) {
    for (int t = s + 1; t < n; ++t) {
      const int a = order[s], b = order[t];
      if (points[b].x() - points[a].x() > tolerance) break;
      if ((points[a] - points[b]).norm() <= tolerance) root[find(b)] = find(a);
    }
  }
  // Renumber the classes by first appearance so particle order follows node order.
  std::vector<int> label(static_cast<size_t>(n), -1), result(static_cast<size_t>(n));
  int next = 0;
  for (int a = 0; a < n; ++a) {
    const int r = find(a);
    if (label[r] < 0) label[r] = next++;
    result[a] = label[r];
  }
  return result;
}

// A patch's control net through the mesh's particles (every point carries one).
detail::NetView patch_net(const nurbs::Patch& patch, const std::vector<int>& particle) {
  detail::NetView net;
  for (int d = 0; d < patch.param_dim(); ++d) net.n[static_cast<size_t>(d)] = patch.num_points(d);
  net.particle = [&patch, &particle](int i, int j, int k) {
    return particle[static_cast<size_t>(patch.index(i, j, k))];
  };
  return net;
}

// One volume term per net cell of every patch, corners in tensor order; cells whose |volume| is
// below 1e-12 diagonal^dim (collapsed corners: round-off of a zero volume) are skipped.
void add_cell_volume_terms(const analysis::Problem& problem, double diagonal,
                           analysis::CellEnergy kind, SpringMesh& mesh) {
  auto& net = mesh.network;
  const int dim = net.dimension;
  int degenerate = 0;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const nurbs::Patch& patch = problem.patches[p];
    if (patch.param_dim() != dim)
      throw nurbs::InputError("spring mesh: volume terms need patches of the model's dimension (" +
                              std::to_string(dim) + "); patch " + std::to_string(p) + " has " +
                              std::to_string(patch.param_dim()));
    degenerate += detail::add_net_cell_terms(patch_net(patch, mesh.particle[p]), kind,
                                             1e-12 * std::pow(diagonal, dim), net);
  }
  if (degenerate > 0) mesh.warnings.push_back(detail::skipped_cells_warning(degenerate, kind));
}

// A volume and a shear strain-point term at every site of every patch (spring_strain_point.hpp),
// the control points mapped to their particles (merged control points add their gradients).
void add_strain_point_terms(const analysis::Problem& problem, int points_per_direction,
                            SpringMesh& mesh) {
  auto& net = mesh.network;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    if (problem.patches[p].param_dim() != net.dimension)
      throw nurbs::InputError("spring mesh: strain points need patches of the model's dimension");
    for (const auto& site :
         analysis::strain_point_sites(problem.patches[p], points_per_direction)) {
      analysis::VolumeTerm term;
      term.rest_volume = site.volume;
      for (size_t a = 0; a < site.control_points.size(); ++a) {
        const int particle = mesh.particle[p][static_cast<size_t>(site.control_points[a])];
        const auto at = std::find(term.points.begin(), term.points.end(), particle);
        if (at == term.points.end()) {
          term.points.push_back(particle);
          term.gradients.push_back(site.gradients[a]);
        } else {
          term.gradients[static_cast<size_t>(at - term.points.begin())] += site.gradients[a];
        }
      }
      for (auto kind : {analysis::CellEnergy::kVolume, analysis::CellEnergy::kShear}) {
        term.kind = kind;
        net.volumes.push_back(term);
      }
    }
  }
}

}  // namespace

int SpringMesh::num_control_points() const {
  int count = 0;
  for (const auto& p : particle) count += static_cast<int>(p.size());
  return count;
}

long expected_spring_count(int n0, int n1, int n2) {
  const long a = n0, b = n1, c = n2;
  if (c <= 1) return a * (b - 1) + b * (a - 1) + 2 * (a - 1) * (b - 1);
  const long edges = (a - 1) * b * c + a * (b - 1) * c + a * b * (c - 1);
  const long face_diagonals =
      2 * ((a - 1) * (b - 1) * c + (a - 1) * b * (c - 1) + a * (b - 1) * (c - 1));
  const long body_diagonals = 4 * (a - 1) * (b - 1) * (c - 1);
  return edges + face_diagonals + body_diagonals;
}

std::vector<int> particle_of_node(const analysis::Problem& problem, const SpringMesh& mesh) {
  const analysis::DofMap dofs(problem);
  std::vector<int> result(static_cast<size_t>(dofs.num_nodes()), -1);
  for (int p = 0; p < dofs.num_patches(); ++p) {
    const auto& nodes = dofs.patch_nodes(p);
    for (size_t cp = 0; cp < nodes.size(); ++cp)
      result[static_cast<size_t>(nodes[cp])] = mesh.particle[static_cast<size_t>(p)][cp];
  }
  return result;
}

SpringMesh build_spring_mesh(const analysis::Problem& problem, const SpringMeshOptions& options) {
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    if (problem.patches[p].param_dim() < 2)
      throw nurbs::InputError("spring mesh: patch " + std::to_string(p) +
                              " is a curve; the NMSM needs surface (2D) or volume (3D) patches");
  }
  const analysis::DofMap dofs(problem);
  const auto& node_positions = dofs.node_positions();
  const double tolerance =
      options.relative_tolerance * detail::bounding_box_diagonal(node_positions);

  std::vector<int> particle_of(static_cast<size_t>(dofs.num_nodes()));
  std::iota(particle_of.begin(), particle_of.end(), 0);
  if (options.merge_coincident) particle_of = merge_coincident(node_positions, tolerance);
  const int num_particles =
      particle_of.empty() ? 0 : *std::max_element(particle_of.begin(), particle_of.end()) + 1;

  SpringMesh mesh;
  auto& net = mesh.network;
  net.dimension = analysis::spatial_dimension(problem.formulation);
  net.positions.assign(static_cast<size_t>(num_particles), Eigen::Vector3d::Zero());
  std::vector<bool> placed(static_cast<size_t>(num_particles), false);
  for (int node = 0; node < dofs.num_nodes(); ++node) {
    const int q = particle_of[node];
    if (!placed[q]) net.positions[q] = node_positions[node];
    placed[q] = true;
  }
  net.masses.assign(static_cast<size_t>(num_particles), 0.0);
  net.fixed.assign(static_cast<size_t>(num_particles), false);

  mesh.particle.resize(problem.patches.size());
  for (int p = 0; p < dofs.num_patches(); ++p)
    for (int node : dofs.patch_nodes(p)) mesh.particle[p].push_back(particle_of[node]);

  // Every pair of corners of a net cell is a spring (2D: 4 edges + 2 diagonals; 3D: 12 edges +
  // 12 face diagonals + 4 body diagonals); with reach r, every pair of points of every block of
  // (r + 1) points per direction (smaller where the net is). The ordered set gives a
  // deterministic spring order.
  if (options.reach < 1 || options.reach > 2)
    throw nurbs::InputError("spring mesh: reach must be 1 (net cells) or 2");
  std::set<std::pair<int, int>> pairs;
  int collapsed = 0;
  for (size_t p = 0; p < problem.patches.size(); ++p)
    detail::collect_block_pairs(patch_net(problem.patches[p], mesh.particle[p]), options.reach,
                                net.positions, tolerance, pairs, collapsed);
  detail::add_springs(pairs, net);
  if (collapsed > 0)
    mesh.warnings.push_back("skipped " + std::to_string(collapsed) +
                            " zero-length corner pairs of degenerate (collapsed) net cells; they "
                            "have no direction and cannot carry a spring");
  if (options.volume_terms)
    add_cell_volume_terms(problem, detail::bounding_box_diagonal(node_positions),
                          analysis::CellEnergy::kVolume, mesh);
  if (options.shear_terms)
    add_cell_volume_terms(problem, detail::bounding_box_diagonal(node_positions),
                          analysis::CellEnergy::kShear, mesh);
  if (options.strain_points > 0) add_strain_point_terms(problem, options.strain_points, mesh);
  return mesh;
}

}  // namespace isospring::fitting
