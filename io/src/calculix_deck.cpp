#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
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

/// A normal (not unit, sign arbitrary) of the side at parameters (s, t) in [0, 1] of its
/// tangential directions: the cross product of the two tangents (3D) or the in-plane
/// perpendicular of the one tangent (2D).
Vector3d side_normal(const nurbs::Patch& patch, const analysis::Side& side, double s, double t) {
  nurbs::Param u{};
  u[side.dir] = side.end ? patch.param_max(side.dir) : patch.param_min(side.dir);
  auto along = [&](int d, double f) {
    if (d < patch.param_dim())
      u[d] = patch.param_min(d) + f * (patch.param_max(d) - patch.param_min(d));
  };
  const int a = (side.dir + 1) % 3, b = (side.dir + 2) % 3;
  along(a, s);
  along(b, t);
  const Eigen::Matrix3d J = patch.derivatives(u).first;
  if (patch.param_dim() == 3) return J.col(a).cross(J.col(b));
  const Vector3d tangent = J.col(1 - side.dir);
  return Vector3d(tangent.y(), -tangent.x(), 0.0);
}

/// Axis (0, 1, 2) the side's normal is parallel to, for symmetry supports.
int symmetry_axis(const nurbs::Patch& patch, const analysis::Side& side, size_t index) {
  int axis = -1;
  for (double s : {0.0, 0.5, 1.0})
    for (double t : {0.0, 0.5, 1.0}) {
      const Vector3d n = side_normal(patch, side, s, t);
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

/// The element type for the case's formulation: the user's choice when it fits, else a clear
/// error; empty means CalculiX's recommended reduced-integration type.
std::string element_type_for(analysis::Formulation formulation, const std::string& requested) {
  const char* stress_types[] = {"CPS8R", "CPS8"};
  const char* strain_types[] = {"CPE8R", "CPE8"};
  const char* solid_types[] = {"C3D20R", "C3D20"};
  const char** allowed = formulation == analysis::Formulation::kSolid         ? solid_types
                         : formulation == analysis::Formulation::kPlaneStress ? stress_types
                                                                              : strain_types;
  if (requested.empty()) return allowed[0];
  if (requested == allowed[0] || requested == allowed[1]) return requested;
  const char* what = formulation == analysis::Formulation::kSolid         ? "a 3D (solid)"
                     : formulation == analysis::Formulation::kPlaneStress ? "a plane stress"
                                                                          : "a plane strain";
  throw nurbs::InputError("CalculiX element type '" + requested + "' does not fit " + what +
                          " case; use " + allowed[0] + " or " + allowed[1]);
}

/// Writes element numbers as *ELSET data lines (at most 16 entries per line).
void append_numbers(std::string& out, const std::vector<int>& numbers) {
  for (size_t i = 0; i < numbers.size(); ++i)
    out +=
        std::to_string(numbers[i]) + ((i + 1) % 16 == 0 || i + 1 == numbers.size() ? "\n" : ", ");
}

/// A number as ccx reads it: ccx takes at most 20 characters of a field (a longer
/// "2.0833333333333329e-05" is cut to an invalid "2.0833333333333329e-" and the deck rejected),
/// so the most significant digits that fit, at most 17 (a double round-trips).
std::string num(double x) {
  char buffer[40];
  for (int digits = 17; digits > 1; --digits) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, x);
    if (std::strlen(buffer) <= 20) break;
  }
  return buffer;
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
  const bool solid = problem.formulation == analysis::Formulation::kSolid;
  const int dim = solid ? 3 : 2;
  CalculixDeck deck;
  deck.element_type = element_type_for(problem.formulation, options.element_type);
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
    if (patch.param_dim() != dim)
      throw nurbs::InputError(std::string("CalculiX export of a ") + (solid ? "3D" : "2D") +
                              " case needs patches of parametric dimension " + std::to_string(dim));
    patch_nodes_list.push_back(patch_nodes(patch, registry));
  }

  deck.nodes = registry.nodes();
  std::string& out = deck.text;
  out += "** CalculiX deck written by isospring export-calculix: " + options.title + "\n";
  out += "** Same geometry (exact NURBS points at corner and mid-edge nodes), material, supports\n";
  out += "** and loads as the isospring case; one *STEP per load case.\n";
  out += "*HEADING\n" + options.title + "\n";
  out += "*NODE, NSET=Nall\n";
  for (size_t n = 0; n < deck.nodes.size(); ++n)
    append_line(out, "%zu, %s, %s, %s", n + 1, num(deck.nodes[n].x()).c_str(),
                num(deck.nodes[n].y()).c_str(), num(deck.nodes[n].z()).c_str());

  // Elements: one per knot span. A left-handed patch's elements are mirrored (w flipped in 3D,
  // v in 2D) so that every element's Jacobian is positive, as ccx requires.
  std::vector<Vector3d> centroids;  // of each element's corner nodes
  out += "*ELEMENT, TYPE=" + deck.element_type + ", ELSET=Eall\n";
  for (const PatchNodes& pn : patch_nodes_list) {
    const int corners = solid ? 8 : 4, count = solid ? 20 : 8;
    for (int k = 0; k + 2 < pn.size[2] || (!solid && k == 0); k += 2)
      for (int j = 0; j + 2 < pn.size[1]; j += 2)
        for (int i = 0; i + 2 < pn.size[0]; i += 2) {
          std::string line = std::to_string(++deck.elements);
          Vector3d centroid = Vector3d::Zero();
          for (int a = 0; a < count; ++a) {
            const int node =
                solid ? pn.at(i + kHex20[a][0], j + kHex20[a][1],
                              k + (pn.flip ? 2 - kHex20[a][2] : kHex20[a][2]))
                      : pn.at(i + kQuad8[a][0], j + (pn.flip ? 2 - kQuad8[a][1] : kQuad8[a][1]), 0);
            if (a < corners) centroid += deck.nodes[static_cast<size_t>(node)] / corners;
            // ccx data lines hold at most 16 entries: 15 nodes, then a continuation line.
            line += a == 15 ? ",\n" : ", ";
            line += std::to_string(node + 1);
          }
          out += line + "\n";
          centroids.push_back(centroid);
        }
  }

  // Materials: one, or one per distinct Young's modulus when it varies with position.
  std::map<double, std::vector<int>> elements_by_modulus;
  for (int e = 0; e < deck.elements; ++e) {
    const double E = options.youngs_modulus_at
                         ? options.youngs_modulus_at(centroids[static_cast<size_t>(e)])
                         : problem.material.youngs_modulus;
    if (!(E > 0) || !std::isfinite(E))
      throw nurbs::InputError("CalculiX export: Young's modulus " + std::to_string(E) +
                              " at element " + std::to_string(e + 1) + " is not positive");
    elements_by_modulus[E].push_back(e + 1);
  }
  int material = 0;
  for (const auto& [E, elements] : elements_by_modulus) {
    const std::string name =
        elements_by_modulus.size() == 1 ? "MATERIAL" : "M" + std::to_string(++material);
    const std::string set = elements_by_modulus.size() == 1 ? "Eall" : name;
    if (set != "Eall") {
      out += "*ELSET, ELSET=" + set + "\n";
      append_numbers(out, elements);
    }
    out += "*MATERIAL, NAME=" + name + "\n*ELASTIC\n";
    append_line(out, "%s, %s", num(E).c_str(), num(problem.material.poisson_ratio).c_str());
    if (problem.material.density > 0) {
      out += "*DENSITY\n";
      append_line(out, "%s", num(problem.material.density).c_str());
    }
    out += "*SOLID SECTION, ELSET=" + set + ", MATERIAL=" + name + "\n";
    if (!solid) append_line(out, "%s", num(problem.material.thickness).c_str());  // plane elements
  }

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
        for (int c = 0; c < dim; ++c)
          if (fixed[static_cast<size_t>(c)])
            append_line(boundary, "%d, %d, %d, %s", node + 1, c + 1, c + 1, num(value[c]).c_str());
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
      if (!solid) {
        // 3-node edges along the other parametric direction; forces per unit length times the
        // thickness, as the plane elements carry it.
        const int along = 1 - side.dir;
        for (int s0 = 0; s0 + 2 < pn.size[along]; s0 += 2) {
          int nodes[3];
          Vector3d x[3];
          for (int q = 0; q < 3; ++q) {
            std::array<int, 3> idx{0, 0, 0};
            idx[side.dir] = side.end ? pn.size[side.dir] - 1 : 0;
            idx[along] = s0 + q;
            nodes[q] = pn.at(idx[0], idx[1], idx[2]);
            x[q] = deck.nodes[static_cast<size_t>(nodes[q])];
          }
          nurbs::Param mid{};
          mid[side.dir] =
              pn.params[side.dir][static_cast<size_t>(side.end ? pn.size[side.dir] - 1 : 0)];
          mid[along] = pn.params[along][static_cast<size_t>(s0 + 1)];
          const Vector3d outward_ref =
              patch.derivatives(mid).first.col(side.dir) * (side.end ? 1 : -1);
          for (size_t i = 0; i < rule.points.size(); ++i) {
            const double r = rule.points[i];
            const double N[3] = {-0.5 * r * (1 - r), 1 - r * r, 0.5 * r * (1 + r)};
            const double dN[3] = {r - 0.5, -2 * r, r + 0.5};
            Vector3d xq = Vector3d::Zero(), xs = Vector3d::Zero();
            for (int q = 0; q < 3; ++q) {
              xq += N[q] * x[q];
              xs += dN[q] * x[q];
            }
            const double length = xs.norm();
            if (length == 0) continue;
            Vector3d n(xs.y() / length, -xs.x() / length, 0.0);
            if (n.dot(outward_ref) < 0) n = -n;
            const Vector3d traction = is_pressure ? Vector3d(-pressure * n)
                                      : f         ? f(xq, n)
                                                  : constant;
            const double w = rule.weights[i] * length * problem.material.thickness;
            for (int q = 0; q < 3; ++q) {
              auto [it, inserted] = forces.try_emplace(nodes[q], Vector3d::Zero());
              it->second += w * N[q] * traction;
            }
          }
        }
        return;
      }
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

    out += "**\n** load case " + lc.id + (options.nonlinear ? "\n*STEP, NLGEOM" : "\n*STEP") +
           "\n*STATIC\n" + boundary;
    out += "*CLOAD, OP=NEW\n";
    for (const auto& [node, f] : forces)
      for (int c = 0; c < dim; ++c)
        if (f[c] != 0) append_line(out, "%d, %d, %s", node + 1, c + 1, num(f[c]).c_str());
    out += "*DLOAD, OP=NEW\n";
    const char* body[3] = {"BX", "BY", "BZ"};
    for (int c = 0; c < dim; ++c)
      if (lc.body_force[c] != 0)
        append_line(out, "Eall, %s, %s", body[c], num(lc.body_force[c]).c_str());
    const double g = lc.gravity.norm();
    if (g > 0)
      append_line(out, "Eall, GRAV, %s, %s, %s, %s", num(g).c_str(),
                  num(lc.gravity.x() / g).c_str(), num(lc.gravity.y() / g).c_str(),
                  num(lc.gravity.z() / g).c_str());
    out += "*NODE PRINT, NSET=Nall\nU\n*NODE FILE\nU\n*END STEP\n";
  }
  return deck;
}

}  // namespace isospring::io
