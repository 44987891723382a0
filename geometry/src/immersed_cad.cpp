// Immersed domain of a CAD solid: grid, classification, cell and boundary quadrature
// (immersed_cad.hpp).
#include <omp.h>
#include <Precision.hxx>
#include <Standard_Failure.hxx>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <sstream>

#include "cad_placement.hpp"
#include "cad_solid_shape.hpp"
#include "immersed_cad_budget.hpp"
#include "immersed_cad_cells.hpp"
#include "immersed_cad_faces.hpp"
#include "immersed_cad_lines.hpp"
#include "immersed_grading.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry {

using nurbs::InputError;

namespace {

// The background cells: per axis the cell boundaries (uniform, or graded towards planes).
struct Grid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), extent = Eigen::Vector3d::Ones();
  Eigen::Vector3i cells = Eigen::Vector3i::Ones();
  Eigen::Vector3d base = Eigen::Vector3d::Ones();  // cell lengths before grading
  std::array<std::vector<double>, 3> ticks;        // cells[k] + 1 coordinates per axis
  std::array<bool, 3> graded = {false, false, false};
  Eigen::Vector3d corner(const Eigen::Vector3i& index) const {
    Eigen::Vector3d x;
    for (int k = 0; k < 3; ++k) x[k] = ticks[static_cast<size_t>(k)][static_cast<size_t>(index[k])];
    return x;
  }
  // The edge lengths of cell `index`.
  Eigen::Vector3d size(const Eigen::Vector3i& index) const {
    return corner(index + Eigen::Vector3i::Ones()) - corner(index);
  }
  double smallest() const {
    double h = 1e300;
    for (const auto& t : ticks)
      for (size_t i = 1; i < t.size(); ++i) h = std::min(h, t[i] - t[i - 1]);
    return h;
  }
  // The cell holding x (clamped to the grid).
  Eigen::Vector3i cell_of(const Eigen::Vector3d& x) const {
    Eigen::Vector3i i;
    for (int k = 0; k < 3; ++k) {
      const auto& t = ticks[static_cast<size_t>(k)];
      const long j = std::upper_bound(t.begin(), t.end(), x[k]) - t.begin() - 1;
      i[k] = static_cast<int>(std::clamp<long>(j, 0, cells[k] - 1));
    }
    return i;
  }
  long index(const Eigen::Vector3i& i) const {
    return (static_cast<long>(i.z()) * cells.y() + i.y()) * cells.x() + i.x();
  }
};

std::string vec(const Eigen::Vector3d& x) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")";
  return out.str();
}

void check_options(const ImmersionOptions& o, const std::string& name) {
  const std::string where = name + ": immersion option ";
  if (o.degree < 1 || o.degree > 8)
    throw InputError(where + "degree = " + std::to_string(o.degree) + ": give 1..8");
  if ((o.cells.array() < 0).any() || ((o.cells.array() > 0).any() && (o.cells.array() == 0).any()))
    throw InputError(where + "cells: give three positive counts, or none and a cell_size");
  if (!(std::isfinite(o.cell_size) && o.cell_size >= 0.0))
    throw InputError(where + "cell_size must be a positive length in m (or 0 with cells)");
  for (const GradingPlane& p : o.grading)
    if (p.axis < 0 || p.axis > 2 || !std::isfinite(p.at) || !(p.smallest > 0.0) ||
        !(p.ratio >= 1.0 && p.ratio <= 10.0))
      throw InputError(where +
                       "grading: give each plane an axis 0..2, a coordinate, a smallest cell "
                       "length > 0 (m) and a ratio in [1, 10]");
  for (const std::vector<double>& axis : o.breaks)
    if (!std::all_of(axis.begin(), axis.end(), [](double x) { return std::isfinite(x); }))
      throw InputError(where + "breaks: give finite coordinates in m");
  if (!(std::isfinite(o.margin) && o.margin >= 0.0))
    throw InputError(where + "margin must be a length >= 0 in m");
  if (o.gauss != 0 && o.gauss < o.degree + 1)
    throw InputError(where + "gauss = " + std::to_string(o.gauss) +
                     ": give at least degree + 1 = " + std::to_string(o.degree + 1) +
                     " (or 0 for degree + 2)");
  if (o.max_depth < 0 || o.max_depth > 8)
    throw InputError(where + "max_depth = " + std::to_string(o.max_depth) + ": give 0..8");
  if (!(o.tolerance > 0.0 && o.tolerance < 1.0))
    throw InputError(where + "tolerance must be in (0, 1)");
  if (!(o.max_quadrature_gb > 0.0))
    throw InputError(where + "max_quadrature_gb must be a size > 0 in GB");
  if (o.threads < 0 || o.threads > 256)
    throw InputError(where + "threads = " + std::to_string(o.threads) +
                     ": give 1..256, or 0 for one per core");
}

// A grading plane asking for cells thinner than kSmallestCellFraction of the base cell would
// make the slivers that breaks are kept from making (immersed_grading.hpp): refused, not clipped.
void check_grading(const ImmersionOptions& o, const Eigen::Vector3d& base,
                   const std::string& name) {
  for (const GradingPlane& p : o.grading)
    if (p.smallest < detail::kSmallestCellFraction * base[p.axis])
      throw InputError(
          name + ": immersion option grading: smallest = " + std::to_string(p.smallest) +
          " m along axis " + std::to_string(p.axis) + " is below " +
          std::to_string(detail::kSmallestCellFraction) + " of the base cell (" +
          std::to_string(base[p.axis]) + " m); give a larger smallest or a smaller cell_size");
}

Grid make_grid(const detail::SolidProbe& probe, const ImmersionOptions& o,
               const std::string& name) {
  const Eigen::Vector3d part_min = probe.box_min(), part_max = probe.box_max();
  const Eigen::Vector3d part = part_max - part_min;
  Grid grid;
  if ((o.box_max.array() > o.box_min.array()).all()) {
    const double slack = 1e-9 * part.norm();
    if ((o.box_min.array() > part_min.array() + slack).any() ||
        (o.box_max.array() < part_max.array() - slack).any())
      throw InputError(name + ": immersion option box " + vec(o.box_min) + ".." + vec(o.box_max) +
                       " does not contain the part " + vec(part_min) + ".." + vec(part_max) +
                       "; enlarge it or leave it out (the part's bounding box is used)");
    grid.origin = o.box_min;
    grid.extent = o.box_max - o.box_min;
  } else {
    grid.origin = part_min - Eigen::Vector3d::Constant(o.margin);
    grid.extent = part + Eigen::Vector3d::Constant(2.0 * o.margin);
  }
  // A box end within the part's tolerance of a kept plane moves onto it before the cells are
  // counted (a box 1e-9 m longer than 0.04 m must not get a fifth 0.01 m cell): the part's
  // extreme planar face then lies on the grid's boundary instead of a tolerance off it. The
  // tolerance is tighten_box's (10 confusions), so the part stays inside the box to it.
  const double snap = 10.0 * Precision::Confusion();
  for (int k = 0; k < 3; ++k) {
    double a = grid.origin[k], b = grid.origin[k] + grid.extent[k];
    detail::snap_ends(a, b, o.breaks[static_cast<size_t>(k)], snap);
    grid.origin[k] = a;
    grid.extent[k] = b - a;
  }
  if ((o.cells.array() > 0).all()) {
    grid.cells = o.cells;
  } else {
    const double size = o.cell_size > 0.0 ? o.cell_size : grid.extent.maxCoeff() / 10.0;
    for (int k = 0; k < 3; ++k)
      grid.cells[k] = std::max(1, static_cast<int>(std::ceil(grid.extent[k] / size - 1e-9)));
  }
  grid.base = grid.extent.cwiseQuotient(grid.cells.cast<double>());
  check_grading(o, grid.base, name);
  for (int k = 0; k < 3; ++k) {
    grid.ticks[static_cast<size_t>(k)] =
        detail::graded_ticks(grid.origin[k], grid.origin[k] + grid.extent[k], grid.cells[k],
                             o.grading, k, o.breaks[static_cast<size_t>(k)], snap);
    const std::vector<double>& t = grid.ticks[static_cast<size_t>(k)];
    grid.origin[k] = t.front();
    grid.extent[k] = t.back() - t.front();
    const int cells = static_cast<int>(grid.ticks[static_cast<size_t>(k)].size()) - 1;
    grid.graded[static_cast<size_t>(k)] =
        !o.breaks[static_cast<size_t>(k)].empty() ||
        std::any_of(o.grading.begin(), o.grading.end(), [&](const GradingPlane& p) {
          return p.axis == k && p.smallest < grid.base[k];
        });
    grid.cells[k] = cells;
  }
  const double count = grid.cells.cast<double>().prod();
  if (count > 2e7)
    throw InputError(name + ": " + std::to_string(static_cast<long>(count)) +
                     " background cells are too many; give a larger cell_size or fewer cells");
  if ((part.array() < grid.base.array()).all() || o.cell_size >= part.maxCoeff() ||
      (grid.cells.array() == 1).all())
    throw InputError(name + ": the part " + vec(part) + " m is smaller than one cell " +
                     vec(grid.base) + " m in every direction; give a cell_size below " +
                     std::to_string(part.maxCoeff()) + " m or more cells");
  return grid;
}

// Affine B-spline box: open knots at the grid's cell boundaries (scaled to [0, 1]), control
// points at the Greville abscissae. Greville points reproduce linear functions for any knots, so
// the box maps [0, 1]^3 linearly onto the grid also when it is graded.
nurbs::Patch background_patch(const Grid& grid, int degree) {
  std::vector<nurbs::KnotVector> knots;
  for (int k = 0; k < 3; ++k) {
    const auto& t = grid.ticks[static_cast<size_t>(k)];
    if (!grid.graded[static_cast<size_t>(k)]) {
      knots.push_back(nurbs::KnotVector::uniform(degree, grid.cells[k]));
      continue;
    }
    std::vector<double> u(static_cast<size_t>(degree), 0.0);
    for (double x : t) u.push_back((x - t.front()) / (t.back() - t.front()));
    u.front() = 0.0;
    u[static_cast<size_t>(degree)] = 0.0;
    u.back() = 1.0;
    u.insert(u.end(), static_cast<size_t>(degree), 1.0);
    knots.emplace_back(degree, std::move(u), "immersed background grid");
  }
  std::vector<Eigen::Vector3d> points;
  const auto greville = [&](int dir, int i) {
    double s = 0.0;
    for (int j = 1; j <= degree; ++j) s += knots[static_cast<size_t>(dir)][i + j];
    return s / degree;
  };
  for (int k = 0; k < knots[2].num_basis(); ++k)
    for (int j = 0; j < knots[1].num_basis(); ++j)
      for (int i = 0; i < knots[0].num_basis(); ++i)
        points.push_back(grid.origin + grid.extent.cwiseProduct(Eigen::Vector3d(
                                           greville(0, i), greville(1, j), greville(2, k))));
  return nurbs::Patch(std::move(knots), std::move(points));
}

enum class State : unsigned char { kOutside, kInside, kCut };

// Halves blocks of cells until no face comes near a block (then its centre decides for all of
// it) or the block is one cell (then it is cut).
void classify(detail::SolidProbe& probe, const Grid& grid, const Eigen::Vector3i& lo,
              const Eigen::Vector3i& hi, std::vector<State>& states) {
  const Eigen::Vector3d a = grid.corner(lo), b = grid.corner(hi);
  State state = State::kCut;
  if (!probe.near_boundary(a, b)) {
    state = probe.contains(0.5 * (a + b)) ? State::kInside : State::kOutside;
  } else if ((hi - lo).maxCoeff() > 1) {
    int k = 0;
    (hi - lo).maxCoeff(&k);
    Eigen::Vector3i mid_hi = hi, mid_lo = lo;
    mid_hi[k] = mid_lo[k] = lo[k] + (hi[k] - lo[k]) / 2;
    classify(probe, grid, lo, mid_hi, states);
    classify(probe, grid, mid_lo, hi, states);
    return;
  }
  for (int z = lo.z(); z < hi.z(); ++z)
    for (int y = lo.y(); y < hi.y(); ++y)
      for (int x = lo.x(); x < hi.x(); ++x)
        states[static_cast<size_t>(grid.index({x, y, z}))] = state;
}

ImmersedCell tensor_cell(const Grid& grid, const Eigen::Vector3i& index, int n) {
  const nurbs::GaussRule rule = nurbs::gauss_legendre(n);
  const Eigen::Vector3d lo = grid.corner(index), h = grid.size(index);
  ImmersedCell cell;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d r(rule.points[i], rule.points[j], rule.points[k]);
        cell.points.push_back(lo + 0.5 * h.cwiseProduct(r + Eigen::Vector3d::Ones()));
        cell.weights.push_back(h.prod() / 8.0 * rule.weights[i] * rule.weights[j] *
                               rule.weights[k]);
      }
  return cell;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The boundary points of each cell (their normals choose a cut cell's line direction).
std::vector<std::vector<const BoundaryPoint*>> points_by_cell(const Grid& grid,
                                                              const ImmersedDomain& domain) {
  std::vector<std::vector<const BoundaryPoint*>> near(
      static_cast<size_t>(grid.cells.cast<long>().prod()));
  for (const BoundaryPoint& b : domain.boundary)
    near[static_cast<size_t>(grid.index(grid.cell_of(b.point)))].push_back(&b);
  return near;
}

// The rules of the cut candidates, on `threads` threads (OpenMP), each with its own probe (its
// own OpenCascade intersectors and classifier: they are not shared between threads). Cells are
// handed out one by one, as their cost varies by orders of magnitude; each rule depends on its
// cell only, so the result does not depend on the threads.
std::vector<detail::CutCellRule> cut_cell_rules(
    detail::SolidProbe& probe, const Grid& grid, const std::vector<Eigen::Vector3i>& cut,
    const std::vector<std::vector<const BoundaryPoint*>>& near,
    const detail::CutCellSettings& settings, int threads, ImmersionStats& stats,
    detail::CutCellStats& totals) {
  threads = std::max(1, std::min<int>(threads, static_cast<int>(cut.size())));
  std::vector<std::unique_ptr<detail::SolidProbe>> copies;
  for (int t = 1; t < threads; ++t) copies.push_back(std::make_unique<detail::SolidProbe>(probe));
  std::vector<detail::CutCellStats> per_thread(static_cast<size_t>(threads));
  std::vector<detail::CutCellRule> rules(cut.size());
  std::vector<std::exception_ptr> errors(static_cast<size_t>(threads));
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (long c = 0; c < static_cast<long>(cut.size()); ++c) {
    const int t = omp_get_thread_num();
    if (errors[static_cast<size_t>(t)]) continue;
    detail::SolidProbe& mine = t == 0 ? probe : *copies[static_cast<size_t>(t - 1)];
    const Eigen::Vector3i& index = cut[static_cast<size_t>(c)];
    try {
      const Eigen::Vector3d lo = grid.corner(index),
                            hi = grid.corner(index + Eigen::Vector3i::Ones());
      rules[static_cast<size_t>(c)] =
          detail::cut_cell_rule(mine, lo, hi, near[static_cast<size_t>(grid.index(index))],
                                settings, (hi - lo).prod(), per_thread[static_cast<size_t>(t)]);
    } catch (...) {
      errors[static_cast<size_t>(t)] = std::current_exception();
    }
  }
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
  for (const detail::CutCellStats& s : per_thread) {
    totals.boxes += s.boxes;
    totals.unresolved += s.unresolved;
    totals.unresolved_error += s.unresolved_error;
  }
  for (const auto& copy : copies) {
    stats.lines += copy->lines();
    stats.classified_lines += copy->classified_lines();
    stats.binned_face_lines += copy->fast_face_lines();
    stats.face_classifications += copy->face_classifications();
    stats.face_lines += copy->fast_face_lines() + copy->full_face_lines();
  }
  return rules;
}

// A cut cell holding less than 1e-9 of its volume of the part is taken as outside. Such slivers
// come from faces lying on a grid plane whose CAD vertices are off it by round-off (5e-14 m on
// the CAx-IF L-bracket): a slab of 1e-9 of a cell (1e-11 m at 1 cm cells) is far thinner than
// what the B-rep resolves (OpenCascade's Precision::Confusion, 1e-7 m here, and the shapes'
// vertex tolerances), the analysis already puts boundary points within 1e-9 of a cell of a grid
// plane into the cell on the part's side, and dropping it changes the volume by less than the
// quadrature's own tolerance. Kept, its basis functions are tied to the part's by the ghost
// penalty across the face and stiffen the model (by 1.5 % on the L-bracket at 5 mm cells).
bool sliver(const detail::CutCellRule& rule, double cell_volume) {
  double volume = 0.0;
  for (double w : rule.weights) volume += w;
  return volume < 1e-9 * cell_volume;
}

// The cells: inside cells get the tensor Gauss rule, cut cells the line rule
// (immersed_cad_cells.hpp); a cut candidate whose lines meet no boundary is inside or outside.
void add_cells(detail::SolidProbe& probe, const Grid& grid, const std::vector<State>& states,
               const ImmersionOptions& o, ImmersedDomain& domain, ImmersionStats& stats) {
  const std::vector<std::vector<const BoundaryPoint*>> near = points_by_cell(grid, domain);
  detail::CutCellSettings settings;
  settings.order = o.gauss > 0 ? o.gauss : o.degree + 2;
  settings.tolerance = o.tolerance;
  settings.max_depth = o.max_depth;
  std::vector<Eigen::Vector3i> cut;
  for (int z = 0; z < grid.cells.z(); ++z)
    for (int y = 0; y < grid.cells.y(); ++y)
      for (int x = 0; x < grid.cells.x(); ++x)
        if (states[static_cast<size_t>(grid.index({x, y, z}))] == State::kCut)
          cut.emplace_back(x, y, z);
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  stats.threads = threads;
  detail::CutCellStats totals;
  const std::vector<detail::CutCellRule> rules =
      cut_cell_rules(probe, grid, cut, near, settings, threads, stats, totals);
  size_t next_cut = 0;
  for (int z = 0; z < grid.cells.z(); ++z)
    for (int y = 0; y < grid.cells.y(); ++y)
      for (int x = 0; x < grid.cells.x(); ++x) {
        const Eigen::Vector3i index(x, y, z);
        const State state = states[static_cast<size_t>(grid.index(index))];
        if (state == State::kOutside) continue;
        ImmersedCell cell;
        if (state == State::kCut) {
          const detail::CutCellRule& rule = rules[next_cut++];
          if (rule.points.empty()) continue;
          if (rule.crossed && sliver(rule, grid.size(index).prod())) {
            ++stats.sliver_cells;
            continue;
          }
          cell.kind = CellKind::kCut;
          cell.points = rule.points;
          cell.weights = rule.weights;
          // Not crossed: wholly inside or (its lines beside its faces aside) wholly outside.
          if (!rule.crossed && !rule.inside) continue;
          if (!rule.crossed) cell = tensor_cell(grid, index, o.degree + 1);
        } else {
          cell = tensor_cell(grid, index, o.degree + 1);
        }
        cell.span = index + Eigen::Vector3i::Constant(o.degree);
        (cell.kind == CellKind::kCut ? stats.cut_cells : stats.inside_cells) += 1;
        domain.cells.push_back(std::move(cell));
      }
  stats.cut_boxes = totals.boxes;
  // Pieces left at max_depth are worth a warning only when together they could move the
  // part's volume by more than 1e-6.
  double volume = 0.0;
  for (const ImmersedCell& cell : domain.cells)
    for (double w : cell.weights) volume += w;
  if (totals.unresolved_error > 1e-6 * volume) {
    std::ostringstream out;
    out.precision(3);
    out << totals.unresolved << " pieces of cut cells did not reach the quadrature tolerance after "
        << o.max_depth << " bisections; their volumes may be off by "
        << totals.unresolved_error / volume
        << " of the part's in all: a finer grid or a larger max_depth resolves them";
    domain.warnings.push_back(out.str());
  }
}

ImmersedDomain immerse(const CadSolid& solid, const ImmersionOptions& o, ImmersionStats& stats) {
  check_options(o, solid.name());
  detail::SolidProbe probe(solid.shape());
  const Grid grid = make_grid(probe, o, solid.name());
  ImmersedDomain domain;
  domain.dimension = 3;
  domain.origin = grid.origin;
  domain.extent = grid.extent;
  domain.background = background_patch(grid, o.degree);
  domain.face_count = solid.face_count();

  auto start = std::chrono::steady_clock::now();
  const int order = o.gauss > 0 ? o.gauss : o.degree + 2;
  detail::check_face_quadrature_size(solid.shape(), order, grid.smallest(),
                                     o.max_quadrature_gb * 1e9, solid.name());
  domain.boundary = detail::face_quadrature(solid.shape(), order, grid.smallest(), domain.warnings);
  stats.boundary_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  std::vector<State> states(static_cast<size_t>(grid.cells.cast<long>().prod()), State::kOutside);
  classify(probe, grid, Eigen::Vector3i::Zero(), grid.cells, states);
  stats.classification_seconds = seconds_since(start);
  stats.distance_queries = probe.distance_queries();

  start = std::chrono::steady_clock::now();
  add_cells(probe, grid, states, o, domain, stats);
  stats.cut_cell_seconds = seconds_since(start);
  stats.lines += probe.lines();
  stats.classified_lines += probe.classified_lines();
  stats.binned_face_lines += probe.fast_face_lines();
  stats.face_classifications += probe.face_classifications();
  stats.face_lines += probe.fast_face_lines() + probe.full_face_lines();
  return domain;
}

// A frame other than the identity: the part turned into the frame (grid coordinates y =
// frame^T x), immersed there on an axis-aligned grid, and its quadrature, normals and background
// control points turned back to the world. Rotating a point costs a round-off (1e-16 of its
// distance from the origin), so the result equals the world-aligned immersion of the turned part,
// turned back, to that.
ImmersedDomain immerse_in_frame(const CadSolid& solid, const ImmersionOptions& o,
                                ImmersionStats& stats) {
  detail::check_rotation(o.frame, solid.name() + ": immersion option frame");
  if (detail::is_identity(o.frame)) return immerse(solid, o, stats);
  const Eigen::Matrix3d& frame = o.frame;
  ImmersionOptions in_frame = o;
  in_frame.frame = Eigen::Matrix3d::Identity();
  ImmersedDomain domain = immerse(transform_solid(solid, frame.transpose()), in_frame, stats);
  domain.frame = frame;
  for (ImmersedCell& cell : domain.cells)
    for (Eigen::Vector3d& x : cell.points) x = frame * x;
  for (BoundaryPoint& b : domain.boundary) {
    b.point = frame * b.point;
    b.normal = frame * b.normal;
  }
  for (int a = 0; a < domain.background.num_points(); ++a)
    domain.background.set_control_point(a, frame * domain.background.control_point(a));
  return domain;
}

}  // namespace

ImmersedDomain immerse_solid(const CadSolid& solid, const ImmersionOptions& options,
                             ImmersionStats* stats) {
  ImmersionStats local;
  try {
    return immerse_in_frame(solid, options, stats ? *stats : local);
  } catch (const Standard_Failure& e) {
    throw InputError(solid.name() + ": OpenCascade failed immersing the solid (" +
                     e.GetMessageString() + "); check the part in the CAD program");
  }
}

}  // namespace isospring::geometry
