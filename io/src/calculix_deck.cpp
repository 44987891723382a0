// make_calculix_deck: the deck's sections in the order ccx reads them (nodes, elements,
// materials, one step per load case); the mesh and the consistent side loads are in
// calculix_mesh.cpp and calculix_side_loads.cpp.
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <map>

#include "calculix_mesh.hpp"
#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::io {
using Eigen::Vector3d;

namespace {
using calculix_detail::DeckMesh;
using calculix_detail::kQuad8;
using calculix_detail::mesh_patches;
using calculix_detail::PatchNodes;
using calculix_detail::side_index;
using calculix_detail::side_load_forces;

/// Fine-grid offsets of the 20 nodes of a C3D20 element in CalculiX/Abaqus order: corners of the
/// bottom (w = 0) and top faces counter-clockwise, bottom and top mid-edges, then vertical ones.
constexpr int kHex20[20][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2},
                               {2, 0, 2}, {2, 2, 2}, {0, 2, 2}, {1, 0, 0}, {2, 1, 0},
                               {1, 2, 0}, {0, 1, 0}, {1, 0, 2}, {2, 1, 2}, {1, 2, 2},
                               {0, 1, 2}, {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};

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

/// Stage: the comment header, *HEADING and every node.
void write_nodes(const std::string& title, CalculixDeck& deck) {
  std::string& out = deck.text;
  out += "** CalculiX deck written by isospring export-calculix: " + title + "\n";
  out += "** Same geometry (exact NURBS points at corner and mid-edge nodes), material, supports\n";
  out += "** and loads as the isospring case; one *STEP per load case.\n";
  out += "*HEADING\n" + title + "\n";
  out += "*NODE, NSET=Nall\n";
  for (size_t n = 0; n < deck.nodes.size(); ++n)
    append_line(out, "%zu, %s, %s, %s", n + 1, num(deck.nodes[n].x()).c_str(),
                num(deck.nodes[n].y()).c_str(), num(deck.nodes[n].z()).c_str());
}

/// Stage: the elements, one per knot span, and the centroid of each one's corner nodes. A
/// left-handed patch's elements are mirrored (w flipped in 3D, v in 2D) so that every element's
/// Jacobian is positive, as ccx requires.
std::vector<Vector3d> write_elements(const std::vector<PatchNodes>& patches, bool solid,
                                     CalculixDeck& deck) {
  std::string& out = deck.text;
  std::vector<Vector3d> centroids;
  out += "*ELEMENT, TYPE=" + deck.element_type + ", ELSET=Eall\n";
  for (const PatchNodes& pn : patches) {
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
  return centroids;
}

/// The elastic law of one material: Hooke's (*ELASTIC E, nu) or the neo-Hookean one with the
/// same small-strain moduli (C10 = mu / 2, D1 = 2 / K).
void write_elastic_law(double E, double nu, bool neo_hookean, std::string& out) {
  if (!neo_hookean) {
    out += "*ELASTIC\n";
    append_line(out, "%s, %s", num(E).c_str(), num(nu).c_str());
    return;
  }
  // The analysis' moduli (and its checks of E and nu), so that both solve the same law.
  analysis::Material material;
  material.youngs_modulus = E;
  material.poisson_ratio = nu;
  const analysis::NeoHookeanParameters m =
      analysis::neo_hookean_parameters(material, analysis::Formulation::kSolid);
  const double mu = m.shear, bulk = m.bulk;
  out += "*HYPERELASTIC, NEO HOOKE\n";
  append_line(out, "%s, %s", num(mu / 2.0).c_str(), num(2.0 / bulk).c_str());
}

/// Stage: the materials and sections, one, or one per distinct Young's modulus when it varies
/// with position (options.youngs_modulus_at at the element centroids).
void write_materials(const analysis::Problem& problem, const CalculixOptions& options,
                     const std::vector<Vector3d>& centroids, bool solid, CalculixDeck& deck) {
  std::string& out = deck.text;
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
    out += "*MATERIAL, NAME=" + name + "\n";
    write_elastic_law(E, problem.material.poisson_ratio, options.neo_hookean, out);
    if (problem.material.density > 0) {
      out += "*DENSITY\n";
      append_line(out, "%s", num(problem.material.density).c_str());
    }
    out += "*SOLID SECTION, ELSET=" + set + ", MATERIAL=" + name + "\n";
    if (!solid) append_line(out, "%s", num(problem.material.thickness).c_str());  // plane elements
  }
}

/// Stage: the supports as a *BOUNDARY block, one line per node and component (values may vary
/// from node to node); every step repeats it.
std::string boundary_block(const analysis::Problem& problem, const DeckMesh& mesh, int dim) {
  std::string boundary = "*BOUNDARY, OP=NEW\n";
  for (size_t s = 0; s < problem.supports.size(); ++s) {
    const analysis::Support& support = problem.supports[s];
    if (support.control_point)
      throw nurbs::InputError(where_support(s) +
                              ": a support on a single control point has no CalculiX node; "
                              "support a side instead");
    const nurbs::Patch& patch = problem.patches[static_cast<size_t>(support.side.patch)];
    const PatchNodes& pn = mesh.patches[static_cast<size_t>(support.side.patch)];
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
        const Vector3d x = mesh.nodes[static_cast<size_t>(node)];
        const Vector3d value = support.symmetry         ? Vector3d::Zero()
                               : support.value_function ? support.value_function(x)
                                                        : support.value;
        for (int c = 0; c < dim; ++c)
          if (fixed[static_cast<size_t>(c)])
            append_line(boundary, "%d, %d, %d, %s", node + 1, c + 1, c + 1, num(value[c]).c_str());
      }
  }
  return boundary;
}

/// Stage, per load case: its *STEP (NLGEOM and Newton criteria as `options` say) with the supports,
/// the consistent nodal forces (*CLOAD), the body force and gravity (*DLOAD) and the displacement
/// output.
void write_step(const analysis::LoadCase& lc, const std::map<int, Vector3d>& forces,
                const std::string& boundary, const CalculixOptions& options, int dim,
                std::string& out) {
  out += "**\n** load case " + lc.id + (options.nonlinear ? "\n*STEP, NLGEOM" : "\n*STEP") +
         "\n*STATIC\n";
  if (options.newton_tolerance > 0)
    append_line(out, "*CONTROLS, PARAMETERS=FIELD\n%s, %s", num(options.newton_tolerance).c_str(),
                num(100 * options.newton_tolerance).c_str());
  out += boundary;
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
    append_line(out, "Eall, GRAV, %s, %s, %s, %s", num(g).c_str(), num(lc.gravity.x() / g).c_str(),
                num(lc.gravity.y() / g).c_str(), num(lc.gravity.z() / g).c_str());
  out += "*NODE PRINT, NSET=Nall\nU\n";
  if (options.print_reactions) out += "*NODE PRINT, NSET=Nall\nRF\n";
  out += "*NODE FILE\nU\n*END STEP\n";
}

}  // namespace

CalculixDeck make_calculix_deck(const analysis::Problem& problem, const CalculixOptions& options) {
  const bool solid = problem.formulation == analysis::Formulation::kSolid;
  const int dim = solid ? 3 : 2;
  if (options.neo_hookean && problem.formulation == analysis::Formulation::kPlaneStress)
    throw nurbs::InputError(
        "CalculiX export: a neo-Hookean material in plane stress is not supported (as in the "
        "analysis); use plane strain or a 3D solid");
  CalculixDeck deck;
  deck.element_type = element_type_for(problem.formulation, options.element_type);
  const DeckMesh mesh = mesh_patches(problem, dim);
  deck.nodes = mesh.nodes;

  write_nodes(options.title, deck);
  const std::vector<Vector3d> centroids = write_elements(mesh.patches, solid, deck);
  write_materials(problem, options, centroids, solid, deck);
  const std::string boundary = boundary_block(problem, mesh, dim);
  const nurbs::GaussRule rule = nurbs::gauss_legendre(options.face_quadrature);
  for (const analysis::LoadCase& lc : problem.load_cases) {
    deck.load_case_ids.push_back(lc.id);
    if (!lc.point_loads.empty())
      throw nurbs::InputError("load case '" + lc.id +
                              "': point loads act on control points, which have no CalculiX "
                              "node; use a traction instead");
    write_step(lc, side_load_forces(problem, mesh, rule, lc), boundary, options, dim, deck.text);
  }
  return deck;
}

}  // namespace isospring::io
