// The serendipity mesh of a CalculiX deck (calculix_mesh.hpp): nodes per patch, merged across
// conforming interfaces.
#include "calculix_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::io::calculix_detail {
using Eigen::Vector3d;

namespace {

/// Merges coincident nodes of different patches (conforming interfaces) by position.
class NodeRegistry {
 public:
  explicit NodeRegistry(double tolerance) : tolerance_(tolerance) {}
  int add(const Vector3d& x) {
    const std::array<long long, 3> cell = key(x);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
          if (it == cells_.end()) continue;
          for (int n : it->second)
            if ((nodes_[static_cast<size_t>(n)] - x).norm() <= tolerance_) return n;
        }
    nodes_.push_back(x);
    const int id = static_cast<int>(nodes_.size()) - 1;
    cells_[cell].push_back(id);
    return id;
  }
  const std::vector<Vector3d>& nodes() const { return nodes_; }

 private:
  std::array<long long, 3> key(const Vector3d& x) const {
    return {std::llround(x.x() / tolerance_), std::llround(x.y() / tolerance_),
            std::llround(x.z() / tolerance_)};
  }
  double tolerance_;
  std::vector<Vector3d> nodes_;
  std::map<std::array<long long, 3>, std::vector<int>> cells_;
};

PatchNodes patch_nodes(const nurbs::Patch& patch, NodeRegistry& registry) {
  PatchNodes pn;
  for (int d = 0; d < 3; ++d) {
    if (d >= patch.param_dim()) {  // a 2D patch: one layer of nodes in its plane
      pn.params[d] = {0.0};
      pn.size[d] = 1;
      continue;
    }
    const std::vector<double> knots = patch.knots(d).unique();
    for (size_t i = 0; i + 1 < knots.size(); ++i) {
      pn.params[d].push_back(knots[i]);
      pn.params[d].push_back(0.5 * (knots[i] + knots[i + 1]));
    }
    pn.params[d].push_back(knots.back());
    pn.size[d] = static_cast<int>(pn.params[d].size());
  }
  pn.node.assign(static_cast<size_t>(pn.size[0] * pn.size[1] * pn.size[2]), -1);
  for (int c = 0; c < pn.size[2]; ++c)
    for (int b = 0; b < pn.size[1]; ++b)
      for (int a = 0; a < pn.size[0]; ++a) {
        if ((a % 2) + (b % 2) + (c % 2) > 1) continue;
        const Vector3d x = patch.point({pn.params[0][a], pn.params[1][b], pn.params[2][c]});
        pn.node[static_cast<size_t>(a + pn.size[0] * (b + pn.size[1] * c))] = registry.add(x);
      }
  nurbs::Param centre{};
  for (int d = 0; d < patch.param_dim(); ++d)
    centre[d] = 0.5 * (patch.param_min(d) + patch.param_max(d));
  const Eigen::Matrix3d J = patch.derivatives(centre).first;
  pn.flip = (patch.param_dim() == 3 ? J.determinant() : J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0)) < 0;
  return pn;
}

}  // namespace

DeckMesh mesh_patches(const analysis::Problem& problem, int dim) {
  // Tolerance for merging interface nodes: relative to the model size.
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const auto& patch : problem.patches) {
    const auto [plo, phi] = patch.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  NodeRegistry registry(1e-9 * std::max((hi - lo).norm(), 1e-300));
  DeckMesh mesh;
  for (const auto& patch : problem.patches) {
    if (patch.param_dim() != dim)
      throw nurbs::InputError(std::string("CalculiX export of a ") + (dim == 3 ? "3D" : "2D") +
                              " case needs patches of parametric dimension " + std::to_string(dim));
    mesh.patches.push_back(patch_nodes(patch, registry));
  }
  mesh.nodes = registry.nodes();
  return mesh;
}

std::array<int, 3> side_index(const PatchNodes& pn, int dir, int end, int s, int t) {
  std::array<int, 3> idx{};
  const int a = (dir + 1) % 3, b = (dir + 2) % 3;
  const int first = std::min(a, b), second = std::max(a, b);
  idx[dir] = end ? pn.size[dir] - 1 : 0;
  idx[first] = s;
  idx[second] = t;
  return idx;
}

}  // namespace isospring::io::calculix_detail
