// Uniform refinement of long display triangles (see surface_refinement.hpp).
#include "surface_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace isospring::workflows::detail {
namespace {

class Refiner {
 public:
  Refiner(const geometry::CadTriangulation& mesh, geometry::CadTriangulation& out)
      : mesh_(mesh), out_(out) {}

  // The point of barycentric grid position (i, j) of k on triangle t (weights of corners 1, 2).
  int point(const std::array<int, 3>& t, int k, int i, int j) {
    const int l = k - i - j;
    const std::array<int, 3> w{l, i, j};
    if (w[0] == k) return t[0];
    if (w[1] == k) return t[1];
    if (w[2] == k) return t[2];
    // On an edge: one weight is zero; the key is the edge's corners in ascending order and the
    // position counted from the lower one, so both triangles sharing it find the same point.
    for (int zero = 0; zero < 3; ++zero) {
      if (w[zero] != 0) continue;
      const int a = (zero + 1) % 3, b = (zero + 2) % 3;
      const bool ascending = t[a] < t[b];
      const int lo = ascending ? t[a] : t[b], hi = ascending ? t[b] : t[a];
      const int steps = ascending ? w[b] : w[a];  // from lo towards hi
      const auto key = std::make_tuple(lo, hi, k, steps);
      if (auto it = edge_points_.find(key); it != edge_points_.end()) return it->second;
      const int index = add(t, w, k);
      edge_points_.emplace(key, index);
      return index;
    }
    return add(t, w, k);
  }

 private:
  int add(const std::array<int, 3>& t, const std::array<int, 3>& w, int k) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) x += w[c] * mesh_.points[static_cast<size_t>(t[c])];
    out_.points.push_back(x / k);
    return static_cast<int>(out_.points.size()) - 1;
  }

  const geometry::CadTriangulation& mesh_;
  geometry::CadTriangulation& out_;
  std::map<std::tuple<int, int, int, int>, int> edge_points_;
};

}  // namespace

geometry::CadTriangulation refine_triangulation(const geometry::CadTriangulation& mesh,
                                                double max_edge) {
  geometry::CadTriangulation out;
  out.points = mesh.points;
  Refiner refiner(mesh, out);
  for (size_t n = 0; n < mesh.triangles.size(); ++n) {
    const std::array<int, 3>& t = mesh.triangles[n];
    double longest = 0;
    for (int c = 0; c < 3; ++c)
      longest = std::max(longest, (mesh.points[static_cast<size_t>(t[c])] -
                                   mesh.points[static_cast<size_t>(t[(c + 1) % 3])])
                                      .norm());
    const int k = max_edge > 0 ? std::max(1, static_cast<int>(std::ceil(longest / max_edge))) : 1;
    // Row i, column j of the barycentric grid: the upright triangle (i, j) (i + 1, j) (i, j + 1)
    // and, where it fits, the inverted one (i + 1, j) (i + 1, j + 1) (i, j + 1).
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j) {
        const int p = refiner.point(t, k, i, j), q = refiner.point(t, k, i + 1, j),
                  r = refiner.point(t, k, i, j + 1);
        out.triangles.push_back({p, q, r});
        out.triangle_face.push_back(mesh.triangle_face[n]);
        if (i + j + 2 <= k) {
          const int s = refiner.point(t, k, i + 1, j + 1);
          out.triangles.push_back({q, s, r});
          out.triangle_face.push_back(mesh.triangle_face[n]);
        }
      }
  }
  return out;
}

}  // namespace isospring::workflows::detail
