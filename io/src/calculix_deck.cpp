#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <functional>
#include <map>

#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::io {
using Eigen::Vector3d;

namespace {

/// Corner and mid-edge nodes of one patch on its "fine" parametric grid: knot values and span
/// midpoints, (2 n_d + 1) per direction. A fine-grid point is a node when at most one of its
/// indices is odd (face and body centres are not nodes of a serendipity element).
struct PatchNodes {
  std::array<int, 3> size{};  // fine-grid points per direction
  std::array<std::vector<double>, 3> params;
  std::vector<int> node;  // fine-grid index -> global node (0-based), -1 when none
  bool flip = false;      // left-handed parametrisation: reverse w in the elements
  int at(int a, int b, int c) const {
    return node[static_cast<size_t>(a + size[0] * (b + size[1] * c))];
  }
};

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
  const nurbs::Param centre{0.5 * (patch.param_min(0) + patch.param_max(0)),
                            0.5 * (patch.param_min(1) + patch.param_max(1)),
                            0.5 * (patch.param_min(2) + patch.param_max(2))};
  pn.flip = patch.derivatives(centre).first.determinant() < 0;
  return pn;
}

/// Fine-grid offsets of the 20 nodes of a C3D20 element in CalculiX/Abaqus order: corners of the
/// bottom (w = 0) and top faces counter-clockwise, bottom and top mid-edges, then vertical ones.
constexpr int kHex20[20][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2},
                               {2, 0, 2}, {2, 2, 2}, {0, 2, 2}, {1, 0, 0}, {2, 1, 0},
                               {1, 2, 0}, {0, 1, 0}, {1, 0, 2}, {2, 1, 2}, {1, 2, 2},
                               {0, 1, 2}, {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};

/// Face nodes in (s, t) fine offsets: corners, then mid-edges (8-node serendipity quad).
constexpr int kQuad8[8][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 0}, {2, 1}, {1, 2}, {0, 1}};

/// Serendipity shape functions of the 8-node quad and their derivatives at (s, t) in [-1, 1]^2.
void quad8(double s, double t, double N[8], double dNs[8], double dNt[8]) {
  for (int a = 0; a < 8; ++a) {
    const double si = kQuad8[a][0] - 1.0, ti = kQuad8[a][1] - 1.0;
    if (a < 4) {
      N[a] = 0.25 * (1 + s * si) * (1 + t * ti) * (s * si + t * ti - 1);
      dNs[a] = 0.25 * si * (1 + t * ti) * (2 * s * si + t * ti);
      dNt[a] = 0.25 * ti * (1 + s * si) * (s * si + 2 * t * ti);
    } else if (si == 0) {
      N[a] = 0.5 * (1 - s * s) * (1 + t * ti);
      dNs[a] = -s * (1 + t * ti);
      dNt[a] = 0.5 * (1 - s * s) * ti;
    } else {
      N[a] = 0.5 * (1 + s * si) * (1 - t * t);
      dNs[a] = 0.5 * si * (1 - t * t);
      dNt[a] = -t * (1 + s * si);
    }
  }
}

/// Fine-grid index of a side point: `dir` fixed at the side, (s, t) along the other two.
std::array<int, 3> side_index(const PatchNodes& pn, int dir, int end, int s, int t) {
  std::array<int, 3> idx{};
  const int a = (dir + 1) % 3, b = (dir + 2) % 3;
  const int first = std::min(a, b), second = std::max(a, b);
  idx[dir] = end ? pn.size[dir] - 1 : 0;
  idx[first] = s;
  idx[second] = t;
  return idx;
}

std::string where_support(size_t i) {
  return "support " + std::to_string(i) + " (boundary[" + std::to_string(i) + "])";
}

/// Axis (0, 1, 2) the side's normal is parallel to, for symmetry supports.
int symmetry_axis(const nurbs::Patch& patch, const analysis::Side& side, size_t index) {
  const int a = (side.dir + 1) % 3, b = (side.dir + 2) % 3;
  int axis = -1;
  for (double s : {0.0, 0.5, 1.0})
    for (double t : {0.0, 0.5, 1.0}) {
      nurbs::Param u{};
      u[side.dir] = side.end ? patch.param_max(side.dir) : patch.param_min(side.dir);
      u[a] = patch.param_min(a) + s * (patch.param_max(a) - patch.param_min(a));
      u[b] = patch.param_min(b) + t * (patch.param_max(b) - patch.param_min(b));
      const Eigen::Matrix3d J = patch.derivatives(u).first;
      const Vector3d n = J.col(a).cross(J.col(b));
      if (n.norm() == 0) continue;  // degenerate point
      int this_axis = 0;
      n.cwiseAbs().maxCoeff(&this_axis);
      if (std::abs(n[this_axis]) < (1 - 1e-10) * n.norm() || (axis >= 0 && axis != this_axis))
        throw nurbs::InputError(where_support(index) +
                                ": a symmetry support on a side whose normal is not a coordinate "
                                "axis cannot be written as CalculiX *BOUNDARY; fix components "
                                "instead");
      axis = this_axis;
    }
  return axis;
}

void append_line(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void append_line(std::string& out, const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  out += buffer;
  out += '\n';
}

}  // namespace

CalculixDeck make_calculix_deck(const analysis::Problem& problem, const CalculixOptions& options) {
  if (problem.formulation != analysis::Formulation::kSolid)
    throw nurbs::InputError("CalculiX export needs a 3D (solid) case; this one is 2D");
  if (options.element_type != "C3D20" && options.element_type != "C3D20R")
    throw nurbs::InputError("CalculiX element type '" + options.element_type +
                            "' is not supported; use C3D20 or C3D20R");
  // Tolerance for merging interface nodes: relative to the model size.
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const auto& patch : problem.patches) {
    const auto [plo, phi] = patch.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  NodeRegistry registry(1e-9 * std::max((hi - lo).norm(), 1e-300));
  std::vector<PatchNodes> patch_nodes_list;
  for (const auto& patch : problem.patches) {
    if (patch.param_dim() != 3)
      throw nurbs::InputError("CalculiX export needs volume patches (parametric dimension 3)");
    patch_nodes_list.push_back(patch_nodes(patch, registry));
  }

  CalculixDeck deck;
  deck.nodes = registry.nodes();
  std::string& out = deck.text;
  out += "** CalculiX deck written by isospring export-calculix: " + options.title + "\n";
  out += "** Same geometry (exact NURBS points at corner and mid-edge nodes), material, supports\n";
  out += "** and loads as the isospring case; one *STEP per load case.\n";
  out += "*HEADING\n" + options.title + "\n";
  out += "*NODE, NSET=Nall\n";
  for (size_t n = 0; n < deck.nodes.size(); ++n)
    append_line(out, "%zu, %.17g, %.17g, %.17g", n + 1, deck.nodes[n].x(), deck.nodes[n].y(),
                deck.nodes[n].z());

  out += "*ELEMENT, TYPE=" + options.element_type + ", ELSET=Eall\n";
  for (const PatchNodes& pn : patch_nodes_list) {
    for (int k = 0; k + 2 < pn.size[2]; k += 2)
      for (int j = 0; j + 2 < pn.size[1]; j += 2)
        for (int i = 0; i + 2 < pn.size[0]; i += 2) {
          std::string line = std::to_string(++deck.elements);
          for (int a = 0; a < 20; ++a) {
            const int dc = pn.flip ? 2 - kHex20[a][2] : kHex20[a][2];
            // ccx data lines hold at most 16 entries: 15 nodes, then a continuation line.
            line += a == 15 ? ",\n" : ", ";
            line += std::to_string(pn.at(i + kHex20[a][0], j + kHex20[a][1], k + dc) + 1);
          }
          out += line + "\n";
        }
  }
  // A left-handed patch's elements are mirrored by flipping w; then the first four nodes are
  // the top face. That keeps every element's Jacobian positive, as ccx requires.

  out += "*MATERIAL, NAME=MATERIAL\n*ELASTIC\n";
  append_line(out, "%.17g, %.17g", problem.material.youngs_modulus, problem.material.poisson_ratio);
  if (problem.material.density > 0) {
    out += "*DENSITY\n";
    append_line(out, "%.17g", problem.material.density);
  }
  out += "*SOLID SECTION, ELSET=Eall, MATERIAL=MATERIAL\n";

  // Supports: one *BOUNDARY line per node and component (values may vary from node to node).
  std::string boundary = "*BOUNDARY, OP=NEW\n";
  for (size_t s = 0; s < problem.supports.size(); ++s) {
    const analysis::Support& support = problem.supports[s];
    if (support.control_point)
      throw nurbs::InputError(where_support(s) +
                              ": a support on a single control point has no CalculiX node; "
                              "support a side instead");
    const nurbs::Patch& patch = problem.patches[static_cast<size_t>(support.side.patch)];
    const PatchNodes& pn = patch_nodes_list[static_cast<size_t>(support.side.patch)];
    std::array<bool, 3> fixed = support.fixed;
    if (support.symmetry) {
      fixed = {false, false, false};
      fixed[static_cast<size_t>(symmetry_axis(patch, support.side, s))] = true;
    }
    const int a = (support.side.dir + 1) % 3, b = (support.side.dir + 2) % 3;
    for (int t = 0; t < pn.size[std::max(a, b)]; ++t)
      for (int sIdx = 0; sIdx < pn.size[std::min(a, b)]; ++sIdx) {
        const auto idx = side_index(pn, support.side.dir, support.side.end, sIdx, t);
        const int node = pn.at(idx[0], idx[1], idx[2]);
        if (node < 0) continue;
        const Vector3d x = deck.nodes[static_cast<size_t>(node)];
        const Vector3d value = support.symmetry         ? Vector3d::Zero()
                               : support.value_function ? support.value_function(x)
                                                        : support.value;
        for (int c = 0; c < 3; ++c)
          if (fixed[c])
            append_line(boundary, "%d, %d, %d, %.17g", node + 1, c + 1, c + 1, value[c]);
      }
  }

  const nurbs::GaussRule rule = nurbs::gauss_legendre(options.face_quadrature);
  for (const analysis::LoadCase& lc : problem.load_cases) {
    deck.load_case_ids.push_back(lc.id);
    if (!lc.point_loads.empty())
      throw nurbs::InputError("load case '" + lc.id +
                              "': point loads act on control points, which have no CalculiX "
                              "node; use a traction instead");
    // Consistent nodal forces of the side loads: f_a = integral of N_a t dA over each face.
    std::map<int, Vector3d> forces;
    auto add_side_load = [&](const analysis::Side& side, const Vector3d& constant,
                             const std::function<Vector3d(const Vector3d&, const Vector3d&)>& f,
                             double pressure, bool is_pressure) {
      const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
      const PatchNodes& pn = patch_nodes_list[static_cast<size_t>(side.patch)];
      const int a = std::min((side.dir + 1) % 3, (side.dir + 2) % 3);
      const int b = std::max((side.dir + 1) % 3, (side.dir + 2) % 3);
      for (int t0 = 0; t0 + 2 < pn.size[b]; t0 += 2)
        for (int s0 = 0; s0 + 2 < pn.size[a]; s0 += 2) {
          int nodes[8];
          Vector3d x[8];
          for (int q = 0; q < 8; ++q) {
            const auto idx =
                side_index(pn, side.dir, side.end, s0 + kQuad8[q][0], t0 + kQuad8[q][1]);
            nodes[q] = pn.at(idx[0], idx[1], idx[2]);
            x[q] = deck.nodes[static_cast<size_t>(nodes[q])];
          }
          // Outward: along +dX/du_dir at the last knot, against it at the first.
          nurbs::Param mid{};
          mid[side.dir] = pn.params[side.dir][side.end ? pn.size[side.dir] - 1 : 0];
          mid[a] = pn.params[a][s0 + 1];
          mid[b] = pn.params[b][t0 + 1];
          const Vector3d outward_ref =
              patch.derivatives(mid).first.col(side.dir) * (side.end ? 1 : -1);
          for (size_t i = 0; i < rule.points.size(); ++i)
            for (size_t j = 0; j < rule.points.size(); ++j) {
              double N[8], dNs[8], dNt[8];
              quad8(rule.points[i], rule.points[j], N, dNs, dNt);
              Vector3d xq = Vector3d::Zero(), xs = Vector3d::Zero(), xt = Vector3d::Zero();
              for (int q = 0; q < 8; ++q) {
                xq += N[q] * x[q];
                xs += dNs[q] * x[q];
                xt += dNt[q] * x[q];
              }
              Vector3d n = xs.cross(xt);
              const double area = n.norm();
              if (area == 0) continue;
              n /= area;
              if (n.dot(outward_ref) < 0) n = -n;
              const Vector3d traction = is_pressure ? Vector3d(-pressure * n)
                                        : f         ? f(xq, n)
                                                    : constant;
              const double w = rule.weights[i] * rule.weights[j] * area;
              for (int q = 0; q < 8; ++q) {
                auto [it, inserted] = forces.try_emplace(nodes[q], Vector3d::Zero());
                it->second += w * N[q] * traction;
              }
            }
        }
    };
    for (const auto& tr : lc.tractions) add_side_load(tr.side, tr.value, tr.function, 0.0, false);
    for (const auto& pr : lc.pressures)
      add_side_load(pr.side, Vector3d::Zero(), {}, pr.value, true);

    out += "**\n** load case " + lc.id + "\n*STEP\n*STATIC\n" + boundary;
    out += "*CLOAD, OP=NEW\n";
    for (const auto& [node, f] : forces)
      for (int c = 0; c < 3; ++c)
        if (f[c] != 0) append_line(out, "%d, %d, %.17g", node + 1, c + 1, f[c]);
    out += "*DLOAD, OP=NEW\n";
    const char* body[3] = {"BX", "BY", "BZ"};
    for (int c = 0; c < 3; ++c)
      if (lc.body_force[c] != 0) append_line(out, "Eall, %s, %.17g", body[c], lc.body_force[c]);
    const double g = lc.gravity.norm();
    if (g > 0)
      append_line(out, "Eall, GRAV, %.17g, %.17g, %.17g, %.17g", g, lc.gravity.x() / g,
                  lc.gravity.y() / g, lc.gravity.z() / g);
    out += "*NODE PRINT, NSET=Nall\nU\n*NODE FILE\nU\n*END STEP\n";
  }
  return deck;
}

}  // namespace isospring::io
