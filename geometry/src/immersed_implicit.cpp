// Immersed domains of analytic shapes: background grid, cell quadrature, boundary points.
#include "isospring/geometry/immersed_implicit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "immersed_lines.hpp"
#include "immersed_spheres.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry {

namespace {

using detail::LineCircle;
using detail::PlaneRule;
using detail::Rectangle;

struct Grid {
  int dim = 2;
  Eigen::Vector3d lo, hi;
  Eigen::Vector3i elements;
  std::array<std::vector<double>, 3> lines;  // grid line coordinates per direction
  std::array<std::vector<int>, 3> spans;     // knot-span index of each element
};

void check_input(const ImplicitShape& shape, const ImplicitGrid& options, const Grid& grid) {
  const auto fail = [](const std::string& message) { throw nurbs::InputError(message); };
  if (shape.dimension != 2 && shape.dimension != 3)
    fail("implicit shape: dimension is " + std::to_string(shape.dimension) + "; use 2 or 3");
  if (options.degree < 1) fail("implicit grid: degree must be at least 1");
  if (options.points < 0 || options.cut_points < 0)
    fail("implicit grid: points and cut_points must be 0 (automatic) or positive");
  for (int d = 0; d < shape.dimension; ++d) {
    const std::string axis(1, "xyz"[d]);
    if (!(shape.box_max[d] > shape.box_min[d]))
      fail("implicit shape: box_max." + axis + " must exceed box_min." + axis);
    if (options.elements[d] < 1) fail("implicit grid: elements." + axis + " must be at least 1");
    const double slack = 1e-12 * (grid.hi[d] - grid.lo[d]);
    if (!(grid.lo[d] <= shape.box_min[d] + slack && grid.hi[d] >= shape.box_max[d] - slack))
      fail("implicit grid: the grid does not contain the shape's box along " + axis +
           "; widen grid_min/grid_max or leave them unset (the box)");
  }
  for (size_t k = 0; k < shape.circles.size(); ++k)
    if (!(shape.circles[k].radius > 0) || !std::isfinite(shape.circles[k].radius))
      fail("implicit shape: circles[" + std::to_string(k) + "].radius must be positive");
  if (shape.spheres.empty()) return;
  if (shape.dimension != 3) fail("implicit shape: spheres need dimension 3");
  if (!shape.circles.empty())
    fail("implicit shape: a shape has circles (cylinders) or spheres, not both");
  for (size_t k = 0; k < shape.spheres.size(); ++k) {
    const auto& s = shape.spheres[k];
    if (!(s.radius > 0) || !std::isfinite(s.radius))
      fail("implicit shape: spheres[" + std::to_string(k) + "].radius must be positive");
    for (size_t m = 0; m < k; ++m) {
      const double l = (s.centre - shape.spheres[m].centre).norm();
      if (l < s.radius + shape.spheres[m].radius &&
          l > std::abs(s.radius - shape.spheres[m].radius))
        fail("implicit shape: spheres[" + std::to_string(m) + "] and spheres[" + std::to_string(k) +
             "] intersect; spheres must be apart or nested");
    }
  }
}

// Affine B-spline box: uniform open knots on [0, 1], control points at the Greville abscissae,
// so that the map from parameters to space is x = lo + (hi - lo) u exactly.
nurbs::Patch background_patch(const Grid& grid, int degree) {
  std::vector<nurbs::KnotVector> knots;
  for (int d = 0; d < grid.dim; ++d)
    knots.push_back(nurbs::KnotVector::uniform(degree, grid.elements[d]));
  std::array<std::vector<double>, 3> greville;
  for (int d = 0; d < 3; ++d) {
    if (d >= grid.dim) {
      greville[static_cast<size_t>(d)] = {0.0};
      continue;
    }
    const auto& kv = knots[static_cast<size_t>(d)];
    for (int a = 0; a < kv.num_basis(); ++a) {
      double g = 0;
      for (int k = 1; k <= degree; ++k) g += kv[a + k];
      greville[static_cast<size_t>(d)].push_back(g / degree);
    }
  }
  std::vector<Eigen::Vector3d> points;
  for (double w : greville[2])
    for (double v : greville[1])
      for (double u : greville[0]) {
        Eigen::Vector3d x(u, v, w);
        x = grid.lo + (grid.hi - grid.lo).cwiseProduct(x);
        if (grid.dim == 2) x.z() = 0.0;
        points.push_back(x);
      }
  return nurbs::Patch(std::move(knots), std::move(points));
}

Grid make_grid(const ImplicitShape& shape, const ImplicitGrid& options) {
  Grid grid;
  grid.dim = shape.dimension;
  grid.lo = options.grid_min.allFinite() ? options.grid_min : shape.box_min;
  grid.hi = options.grid_max.allFinite() ? options.grid_max : shape.box_max;
  grid.elements = options.elements;
  if (grid.dim == 2) {
    grid.lo.z() = grid.hi.z() = 0.0;
    grid.elements.z() = 1;
  }
  for (int d = 0; d < grid.dim; ++d) {
    const int n = std::max(1, grid.elements[d]);
    for (int i = 0; i <= n; ++i)
      grid.lines[static_cast<size_t>(d)].push_back(grid.lo[d] + (grid.hi[d] - grid.lo[d]) * i / n);
    for (int i = 0; i < n; ++i) grid.spans[static_cast<size_t>(d)].push_back(options.degree + i);
  }
  return grid;
}

std::vector<LineCircle> line_circles(const ImplicitShape& shape) {
  std::vector<LineCircle> out;
  for (const auto& c : shape.circles) out.push_back({c.centre, c.radius, c.part_inside});
  return out;
}

// The cross-section's rule in one grid cell (x-y), clipped to the box; `inside` when the cell is
// uncut.
struct CellRule {
  PlaneRule rule;
  bool inside = false;
};

CellRule cross_section_cell(const Grid& grid, const ImplicitShape& shape,
                            const std::vector<LineCircle>& circles, int i, int j, int points,
                            int cut_points, std::string& warning) {
  CellRule out;
  const Rectangle cell{
      {grid.lines[0][static_cast<size_t>(i)], grid.lines[1][static_cast<size_t>(j)]},
      {grid.lines[0][static_cast<size_t>(i + 1)], grid.lines[1][static_cast<size_t>(j + 1)]}};
  Rectangle rect{cell.lo.cwiseMax(shape.box_min.head<2>()),
                 cell.hi.cwiseMin(shape.box_max.head<2>())};
  if ((rect.hi.array() <= rect.lo.array()).any()) return out;
  std::vector<LineCircle> crossing;
  for (const auto& c : circles) {
    const detail::Overlap o = detail::circle_overlap(rect, c);
    if (o == detail::Overlap::kNone) return out;
    if (o == detail::Overlap::kPartial) crossing.push_back(c);
  }
  if (crossing.empty()) {
    const nurbs::GaussRule g = nurbs::gauss_legendre(points);
    for (size_t b = 0; b < g.points.size(); ++b)
      for (size_t a = 0; a < g.points.size(); ++a) {
        const Eigen::Vector2d t(g.points[a], g.points[b]);
        out.rule.points.push_back(0.5 * (rect.lo + rect.hi) +
                                  0.5 * (rect.hi - rect.lo).cwiseProduct(t));
        out.rule.weights.push_back(0.25 * (rect.hi - rect.lo).prod() * g.weights[a] * g.weights[b]);
      }
    out.inside = (rect.lo - cell.lo).cwiseAbs().maxCoeff() == 0 &&
                 (rect.hi - cell.hi).cwiseAbs().maxCoeff() == 0;
    return out;
  }
  out.rule = detail::cut_rectangle_rule(rect, crossing, cut_points, warning);
  return out;
}

// z-elements clipped to the box: (element index, z0, z1).
struct ZPiece {
  int element;
  double z0, z1;
};
std::vector<ZPiece> z_pieces(const Grid& grid, const ImplicitShape& shape) {
  std::vector<ZPiece> out;
  if (grid.dim == 2) return {{0, 0.0, 0.0}};
  for (int k = 0; k < grid.elements.z(); ++k) {
    const double z0 = std::max(grid.lines[2][static_cast<size_t>(k)], shape.box_min.z());
    const double z1 = std::min(grid.lines[2][static_cast<size_t>(k + 1)], shape.box_max.z());
    if (z1 > z0) out.push_back({k, z0, z1});
  }
  return out;
}

// Adds the inside and cut cells; returns the cross-section's rule of every x-y cell (the z faces'
// quadrature in 3D).
std::vector<PlaneRule> add_cells(const Grid& grid, const ImplicitShape& shape,
                                 const ImplicitGrid& options, ImmersedDomain& domain) {
  const int p1 = options.degree + 1;
  const int points = options.points > 0 ? options.points : p1;
  const int cut_points = options.cut_points > 0 ? options.cut_points : 2 * p1;
  const auto circles = line_circles(shape);
  const auto zs = z_pieces(grid, shape);
  std::string warning;
  std::vector<PlaneRule> cross_section;
  for (int j = 0; j < grid.elements.y(); ++j)
    for (int i = 0; i < grid.elements.x(); ++i) {
      const CellRule plane =
          cross_section_cell(grid, shape, circles, i, j, points, cut_points, warning);
      cross_section.push_back(plane.rule);
      if (plane.rule.points.empty()) continue;
      for (const ZPiece& piece : zs) {
        ImmersedCell cell;
        cell.span = {grid.spans[0][static_cast<size_t>(i)], grid.spans[1][static_cast<size_t>(j)],
                     grid.dim == 3 ? grid.spans[2][static_cast<size_t>(piece.element)] : 0};
        const bool z_full =
            grid.dim == 2 || (piece.z0 == grid.lines[2][static_cast<size_t>(piece.element)] &&
                              piece.z1 == grid.lines[2][static_cast<size_t>(piece.element + 1)]);
        cell.kind = plane.inside && z_full ? CellKind::kInside : CellKind::kCut;
        const nurbs::GaussRule g = nurbs::gauss_legendre(grid.dim == 3 ? points : 1);
        for (size_t q = 0; q < g.points.size(); ++q) {
          const double half = 0.5 * (piece.z1 - piece.z0);
          const double z = 0.5 * (piece.z0 + piece.z1) + half * g.points[q];
          const double wz = grid.dim == 3 ? half * g.weights[q] : 1.0;
          for (size_t a = 0; a < plane.rule.points.size(); ++a) {
            cell.points.emplace_back(plane.rule.points[a].x(), plane.rule.points[a].y(), z);
            cell.weights.push_back(plane.rule.weights[a] * wz);
          }
        }
        domain.cells.push_back(std::move(cell));
      }
    }
  if (!warning.empty()) domain.warnings.push_back(warning);
  return cross_section;
}

// Cells, sphere points and box faces of a box intersected with spheres.
void add_sphere_shape(const Grid& grid, const ImplicitShape& shape, const ImplicitGrid& options,
                      ImmersedDomain& domain) {
  const int points = options.points > 0 ? options.points : options.degree + 1;
  const int cut_points = options.cut_points > 0 ? options.cut_points : 2 * (options.degree + 1);
  std::string warning;
  for (int k = 0; k < grid.elements.z(); ++k)
    for (int j = 0; j < grid.elements.y(); ++j)
      for (int i = 0; i < grid.elements.x(); ++i) {
        const std::array<int, 3> e{i, j, k};
        Eigen::Vector3d lo, hi;
        bool clipped = false;
        for (int d = 0; d < 3; ++d) {
          const auto& lines = grid.lines[static_cast<size_t>(d)];
          const size_t at = static_cast<size_t>(e[static_cast<size_t>(d)]);
          lo[d] = std::max(lines[at], shape.box_min[d]);
          hi[d] = std::min(lines[at + 1], shape.box_max[d]);
          clipped = clipped || lo[d] != lines[at] || hi[d] != lines[at + 1];
        }
        if ((hi.array() <= lo.array()).any()) continue;
        detail::SphereRule rule;
        const bool cut = detail::sphere_cell_rule(lo, hi, shape.spheres, 6, points, cut_points, 8,
                                                  warning, rule);
        for (auto& b : rule.surface) domain.boundary.push_back(b);
        if (rule.points.empty()) continue;
        ImmersedCell cell;
        cell.span = {grid.spans[0][static_cast<size_t>(i)], grid.spans[1][static_cast<size_t>(j)],
                     grid.spans[2][static_cast<size_t>(k)]};
        cell.kind = cut || clipped ? CellKind::kCut : CellKind::kInside;
        cell.points = std::move(rule.points);
        cell.weights = std::move(rule.weights);
        domain.cells.push_back(std::move(cell));
      }
  // Box faces, one rule per grid cell of the face.
  for (int d = 0; d < 3; ++d)
    for (int end = 0; end < 2; ++end) {
      const int a = (d + 1) % 3, b = (d + 2) % 3;
      const double t = end ? shape.box_max[d] : shape.box_min[d];
      const auto& la = grid.lines[static_cast<size_t>(a)];
      const auto& lb = grid.lines[static_cast<size_t>(b)];
      for (size_t j = 0; j + 1 < lb.size(); ++j)
        for (size_t i = 0; i + 1 < la.size(); ++i) {
          const Eigen::Vector2d lo(std::max(la[i], shape.box_min[a]),
                                   std::max(lb[j], shape.box_min[b]));
          const Eigen::Vector2d hi(std::min(la[i + 1], shape.box_max[a]),
                                   std::min(lb[j + 1], shape.box_max[b]));
          if ((hi.array() <= lo.array()).any()) continue;
          std::vector<Eigen::Vector3d> xs;
          std::vector<double> ws;
          detail::sphere_box_face(lo, hi, d, t, shape.spheres, cut_points, warning, xs, ws);
          Eigen::Vector3d normal = Eigen::Vector3d::Zero();
          normal[d] = end ? 1.0 : -1.0;
          for (size_t q = 0; q < xs.size(); ++q)
            domain.boundary.push_back({xs[q], normal, ws[q], 2 * d + end});
        }
    }
  if (!warning.empty()) domain.warnings.push_back(warning);
}

}  // namespace

ImmersedDomain immerse_implicit(const ImplicitShape& shape, const ImplicitGrid& options) {
  const Grid grid = make_grid(shape, options);
  check_input(shape, options, grid);
  ImmersedDomain domain;
  domain.dimension = shape.dimension;
  domain.background = background_patch(grid, options.degree);
  domain.origin = grid.lo;
  domain.extent = grid.hi - grid.lo;
  if (grid.dim == 2) domain.extent.z() = 1.0;
  domain.face_count = (shape.dimension == 2 ? 4 : 6) +
                      static_cast<int>(shape.circles.size() + shape.spheres.size());
  if (!shape.spheres.empty()) {
    add_sphere_shape(grid, shape, options, domain);
    if (domain.cells.empty())
      throw nurbs::InputError(
          "implicit shape: the part covers no cell of the grid; check the spheres' centres, radii "
          "and part_inside");
    return domain;
  }
  const std::vector<PlaneRule> cross_section = add_cells(grid, shape, options, domain);
  if (domain.cells.empty())
    throw nurbs::InputError(
        "implicit shape: the part covers no cell of the grid (the circles remove the whole box); "
        "check the circles' centres, radii and part_inside");
  const int cut_points = options.cut_points > 0 ? options.cut_points : 2 * (options.degree + 1);
  detail::add_implicit_boundary(shape, grid.lines, cut_points, cross_section, domain);
  return domain;
}

}  // namespace isospring::geometry
