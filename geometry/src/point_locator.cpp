#include "isospring/geometry/point_locator.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>

#include <boost/tuple/tuple.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "isospring/nurbs/point_inversion.hpp"

namespace isospring::geometry {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
// Interior samples of a volume patch with their index, in a kd-tree.
using IndexedPoint = boost::tuple<Kernel::Point_3, int>;
using SampleTraits =
    CGAL::Search_traits_adapter<IndexedPoint, CGAL::Nth_of_tuple_property_map<0, IndexedPoint>,
                                CGAL::Search_traits_3<Kernel>>;
using NearestSample = CGAL::Orthogonal_k_neighbor_search<SampleTraits>;

Kernel::Point_3 to_cgal(const Eigen::Vector3d& x) {
  return {x.x(), x.y(), x.z()};
}
Eigen::Vector3d to_eigen(const Kernel::Point_3& p) {
  return {p.x(), p.y(), p.z()};
}

// Tessellation of one patch (its surface, or the six sides of a volume) with the parameters of
// every triangle corner, and an estimate of how far the triangles stray from the patch.
struct PatchMesh {
  std::vector<Triangle> triangles;
  std::vector<std::array<nurbs::Param, 3>> params;
  Tree tree;
  double chord_error = 0.0;
  // Volumes: a grid of interior samples (kInteriorSamples per element and direction). The
  // nearest one starts the inversion of a point inside; without it every such point sampled the
  // whole patch (nurbs::invert_point's own start), 8^3 samples per element.
  std::vector<nurbs::Param> sample_params;
  NearestSample::Tree samples;
  double sample_reach = 0.0;  // largest distance between neighbouring samples
};

std::vector<double> samples_along(const nurbs::Patch& patch, int dir, int per_element) {
  std::vector<double> values;
  const std::vector<double> breaks = patch.knots(dir).unique();
  for (size_t e = 0; e + 1 < breaks.size(); ++e)
    for (int s = 0; s < per_element; ++s)
      values.push_back(breaks[e] + (breaks[e + 1] - breaks[e]) * s / per_element);
  values.push_back(breaks.back());
  return values;
}

constexpr int kInteriorSamples = 2;

// The interior sample grid of a volume patch and the largest distance between grid neighbours
// (a point inside the patch is never farther than that from its nearest sample).
void add_interior_samples(PatchMesh& mesh, const nurbs::Patch& patch) {
  const std::vector<double> us = samples_along(patch, 0, kInteriorSamples);
  const std::vector<double> vs = samples_along(patch, 1, kInteriorSamples);
  const std::vector<double> ws = samples_along(patch, 2, kInteriorSamples);
  std::vector<IndexedPoint> points;
  std::vector<Eigen::Vector3d> xs;
  for (double w : ws)
    for (double v : vs)
      for (double u : us) {
        const nurbs::Param p{u, v, w};
        xs.push_back(patch.point(p));
        points.emplace_back(to_cgal(xs.back()), static_cast<int>(mesh.sample_params.size()));
        mesh.sample_params.push_back(p);
      }
  const size_t nu = us.size(), nv = vs.size();
  for (size_t i = 0; i < xs.size(); ++i) {
    const size_t a = i % nu, b = (i / nu) % nv;
    if (a + 1 < nu) mesh.sample_reach = std::max(mesh.sample_reach, (xs[i + 1] - xs[i]).norm());
    if (b + 1 < nv) mesh.sample_reach = std::max(mesh.sample_reach, (xs[i + nu] - xs[i]).norm());
    if (i + nu * nv < xs.size())
      mesh.sample_reach = std::max(mesh.sample_reach, (xs[i + nu * nv] - xs[i]).norm());
  }
  mesh.samples.insert(points.begin(), points.end());
}

// Triangulates the parameter grid of directions a, b with direction `fixed` held at `value`.
void add_grid(PatchMesh& mesh, const nurbs::Patch& patch, int a, int b, int fixed, double value,
              int per_element) {
  const std::vector<double> us = samples_along(patch, a, per_element);
  const std::vector<double> vs = samples_along(patch, b, per_element);
  std::vector<nurbs::Param> grid_params;
  std::vector<Eigen::Vector3d> grid_points;
  for (double v : vs)
    for (double u : us) {
      nurbs::Param p{0, 0, 0};
      p[static_cast<size_t>(a)] = u;
      p[static_cast<size_t>(b)] = v;
      if (fixed >= 0) p[static_cast<size_t>(fixed)] = value;
      grid_params.push_back(p);
      grid_points.push_back(patch.point(p));
    }
  const auto [lo, hi] = patch.control_bounds();
  const double degenerate_area = 1e-24 * (hi - lo).squaredNorm();
  const size_t nu = us.size();
  auto add = [&](size_t i, size_t j, size_t k) {
    const Eigen::Vector3d &x = grid_points[i], &y = grid_points[j], &z = grid_points[k];
    // Collapsed edges (poles, axes, singular corners) give zero-area triangles: the neighbours
    // cover the same points.
    if ((y - x).cross(z - x).squaredNorm() <= degenerate_area) return;
    mesh.triangles.emplace_back(to_cgal(x), to_cgal(y), to_cgal(z));
    mesh.params.push_back({grid_params[i], grid_params[j], grid_params[k]});
    nurbs::Param centre{0, 0, 0};
    for (int c = 0; c < 3; ++c)
      centre[static_cast<size_t>(c)] =
          (grid_params[i][c] + grid_params[j][c] + grid_params[k][c]) / 3.0;
    mesh.chord_error = std::max(mesh.chord_error, (patch.point(centre) - (x + y + z) / 3.0).norm());
  };
  for (size_t j = 0; j + 1 < vs.size(); ++j)
    for (size_t i = 0; i + 1 < nu; ++i) {
      const size_t p00 = j * nu + i, p10 = p00 + 1, p01 = p00 + nu, p11 = p01 + 1;
      add(p00, p10, p11);
      add(p00, p11, p01);
    }
}

// Parameter of the point p on triangle t of the mesh (linear interpolation of the corners).
nurbs::Param interpolate(const PatchMesh& mesh, size_t t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = to_eigen(mesh.triangles[t][0]), b = to_eigen(mesh.triangles[t][1]),
                        c = to_eigen(mesh.triangles[t][2]);
  Eigen::Matrix<double, 3, 2> E;
  E << b - a, c - a;
  Eigen::Vector2d st = E.colPivHouseholderQr().solve(p - a);
  st = st.cwiseMax(0.0);
  if (st.sum() > 1.0) st /= st.sum();
  nurbs::Param u{0, 0, 0};
  const auto& q = mesh.params[t];
  for (size_t d = 0; d < 3; ++d)
    u[d] = (1.0 - st(0) - st(1)) * q[0][d] + st(0) * q[1][d] + st(1) * q[2][d];
  return u;
}

// Interpolation leaves parameters a rounding error inside the box (1 - 1e-16); invert_point's
// projected Newton then treats that direction as free and can stall at the start, so parameters
// that close to a bound are put exactly on it.
nurbs::Param snapped_to_bounds(const nurbs::Patch& patch, nurbs::Param u) {
  for (int d = 0; d < patch.param_dim(); ++d) {
    const double lo = patch.param_min(d), hi = patch.param_max(d), eps = 1e-12 * (hi - lo);
    auto& x = u[static_cast<size_t>(d)];
    if (x - lo < eps) x = lo;
    if (hi - x < eps) x = hi;
  }
  return u;
}

constexpr double kInversionTolerance = 1e-14;

// invert_point decides by comparing squared distances, which resolves the closest point only to
// ~sqrt(machine epsilon) * distance along the surface (1e-9 for unit distances). A few Newton
// steps on the stationarity condition J^T (X - x) = 0 of the parameters not on a bound, accepted
// while the gradient shrinks, bring it to round-off.
nurbs::Inversion polished(const nurbs::Patch& patch, const Eigen::Vector3d& x,
                          nurbs::Inversion inv) {
  const int dim = patch.param_dim();
  auto gradient = [&](const nurbs::PatchDerivatives& der, const std::array<bool, 3>& active) {
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int a = 0; a < dim; ++a)
      if (active[static_cast<size_t>(a)]) g(a) = der.first.col(a).dot(der.point - x);
    return g;
  };
  std::array<bool, 3> active{false, false, false};
  for (int a = 0; a < dim; ++a) {
    const double u = inv.param[static_cast<size_t>(a)];
    active[static_cast<size_t>(a)] = u > patch.param_min(a) && u < patch.param_max(a);
  }
  nurbs::PatchDerivatives der = patch.derivatives(inv.param, 2);
  Eigen::Vector3d g = gradient(der, active);
  for (int iteration = 0; iteration < 4 && g.norm() > 0.0; ++iteration) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Identity();
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b)
        if (active[static_cast<size_t>(a)] && active[static_cast<size_t>(b)])
          H(a, b) = der.first.col(a).dot(der.first.col(b)) +
                    der.second[static_cast<size_t>(a)].col(b).dot(der.point - x);
    const Eigen::Vector3d step = H.ldlt().solve(-g);
    nurbs::Param trial = inv.param;
    for (int a = 0; a < dim; ++a)
      trial[static_cast<size_t>(a)] = std::clamp(trial[static_cast<size_t>(a)] + step(a),
                                                 patch.param_min(a), patch.param_max(a));
    const nurbs::PatchDerivatives next = patch.derivatives(trial, 2);
    const Eigen::Vector3d g_next = gradient(next, active);
    if (!(g_next.norm() < g.norm())) break;
    inv.param = trial;
    der = next;
    g = g_next;
  }
  inv.point = der.point;
  inv.distance = (der.point - x).norm();
  return inv;
}
}  // namespace

struct PointLocator::Impl {
  std::vector<nurbs::Patch> patches;
  std::vector<std::unique_ptr<PatchMesh>> meshes;
  double size = 0.0;
};

PointLocator::PointLocator(const std::vector<nurbs::Patch>& patches, int samples_per_element)
    : impl_(std::make_unique<Impl>()) {
  if (patches.empty()) throw std::invalid_argument("PointLocator: no patches");
  if (samples_per_element < 1)
    throw std::invalid_argument("PointLocator: samples_per_element must be >= 1");
  impl_->patches = patches;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& patch : patches) {
    if (patch.param_dim() < 2)
      throw std::invalid_argument("PointLocator: curves cannot be located on");
    auto mesh = std::make_unique<PatchMesh>();
    if (patch.param_dim() == 2) {
      add_grid(*mesh, patch, 0, 1, -1, 0.0, samples_per_element);
    } else {
      for (int fixed = 0; fixed < 3; ++fixed) {
        const int a = fixed == 0 ? 1 : 0, b = fixed == 2 ? 1 : 2;
        for (double end : {patch.param_min(fixed), patch.param_max(fixed)})
          add_grid(*mesh, patch, a, b, fixed, end, samples_per_element);
      }
      add_interior_samples(*mesh, patch);
    }
    mesh->tree.insert(mesh->triangles.begin(), mesh->triangles.end());
    mesh->tree.accelerate_distance_queries();
    impl_->meshes.push_back(std::move(mesh));
    const auto [plo, phi] = patch.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  impl_->size = (hi - lo).norm();
}

PointLocator::~PointLocator() = default;
PointLocator::PointLocator(PointLocator&&) noexcept = default;
PointLocator& PointLocator::operator=(PointLocator&&) noexcept = default;

double PointLocator::model_size() const {
  return impl_->size;
}

Location PointLocator::locate(const Eigen::Vector3d& x) const {
  const size_t n = impl_->patches.size();
  // Closest tessellation point of every patch: a distance estimate and a starting parameter.
  std::vector<double> mesh_distance(n, std::numeric_limits<double>::infinity());
  std::vector<nurbs::Param> start(n);
  double best_mesh = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < n; ++p) {
    const PatchMesh& mesh = *impl_->meshes[p];
    if (mesh.triangles.empty()) continue;
    const auto [closest, id] = mesh.tree.closest_point_and_primitive(to_cgal(x));
    const Eigen::Vector3d c = to_eigen(closest);
    mesh_distance[p] = (c - x).norm();
    start[p] = snapped_to_bounds(
        impl_->patches[p], interpolate(mesh, static_cast<size_t>(id - mesh.triangles.begin()), c));
    best_mesh = std::min(best_mesh, mesh_distance[p]);
  }
  Location best;
  best.distance = std::numeric_limits<double>::infinity();
  const double slack = 1e-12 * impl_->size;
  for (size_t p = 0; p < n; ++p) {
    const nurbs::Patch& patch = impl_->patches[p];
    const PatchMesh& mesh = *impl_->meshes[p];
    const auto [lo, hi] = patch.control_bounds();
    const bool may_contain = patch.param_dim() == 3 && (x.array() >= lo.array() - slack).all() &&
                             (x.array() <= hi.array() + slack).all();
    // The exact patch is within chord_error of its tessellation, so only patches whose mesh is
    // that close to the best can hold the closest point.
    const bool near = mesh_distance[p] <= best_mesh + 2.0 * mesh.chord_error + slack;
    if (!near && !may_contain) continue;
    std::vector<nurbs::Inversion> tries;
    if (near) tries.push_back(nurbs::invert_point(patch, x, start[p], kInversionTolerance));
    const double inside = 1e-10 * impl_->size;
    if (may_contain && !mesh.sample_params.empty()) {
      // Starts at the nearest interior samples; the whole patch is sampled only when none of
      // them reaches the point and it is close enough to the samples to be inside.
      const NearestSample search(mesh.samples, to_cgal(x), 3);
      double nearest = std::numeric_limits<double>::infinity();
      bool found = false;
      for (auto it = search.begin(); it != search.end() && !found; ++it) {
        nearest = std::min(nearest, std::sqrt(it->second));
        const auto& sample = mesh.sample_params[static_cast<size_t>(boost::get<1>(it->first))];
        tries.push_back(nurbs::invert_point(patch, x, sample, kInversionTolerance));
        found = tries.back().distance <= inside;
      }
      if (!found && nearest <= mesh.sample_reach)
        tries.push_back(nurbs::invert_point(patch, x, std::nullopt, kInversionTolerance));
    }
    for (auto& inv : tries) inv = polished(patch, x, inv);
    for (const auto& inv : tries)
      if (inv.distance < best.distance) {
        best.patch = static_cast<int>(p);
        best.param = inv.param;
        best.point = inv.point;
        best.distance = inv.distance;
        best.inside = patch.param_dim() == 3 && inv.distance <= 1e-10 * impl_->size;
      }
  }
  return best;
}

PointLocator::Batch PointLocator::locate_all(const std::vector<Eigen::Vector3d>& points,
                                             double tolerance) const {
  Batch batch;
  batch.locations.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    batch.locations.push_back(locate(points[i]));
    if (batch.locations.back().distance > tolerance) batch.far.push_back(static_cast<int>(i));
  }
  return batch;
}

}  // namespace isospring::geometry
