// Hexahedral solids (six 4-sided faces) -> one NURBS volume by transfinite interpolation.
#include "cad_solid_recognisers.hpp"

#include <BRepGProp.hxx>
#include <BRep_Tool.hxx>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "cad_coons.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/coons.hpp"
#include "isospring/geometry/measure.hpp"

namespace isospring::geometry::detail {

namespace {

// Corner c = i + 2 j + 4 k of the block (i, j, k in {0, 1}) as a vertex index of the solid: of
// the 48 right-handed ways to number the corners (origin corner, order of its 3 edges), the one
// whose u, v, w edges point most along +x, +y, +z. The vertex order in the file is arbitrary, and
// users expect an axis-aligned block to have u along x (u0 at the smallest x), as `box` does.
bool number_corners(const std::array<std::set<int>, 8>& adjacent,
                    const std::array<Eigen::Vector3d, 8>& x, std::array<int, 8>& order) {
  auto common = [&](int a, int b, int not_this) {
    for (int c : adjacent[static_cast<size_t>(a)])
      if (c != not_this && adjacent[static_cast<size_t>(b)].count(c)) return c;
    return -1;
  };
  double best_score = -INFINITY;
  for (int origin = 0; origin < 8; ++origin) {
    std::vector<int> n(adjacent[static_cast<size_t>(origin)].begin(),
                       adjacent[static_cast<size_t>(origin)].end());
    std::sort(n.begin(), n.end());
    do {
      const Eigen::Vector3d eu = x[n[0]] - x[origin], ev = x[n[1]] - x[origin],
                            ew = x[n[2]] - x[origin];
      if (eu.cross(ev).dot(ew) <= 0.0) continue;
      const int c110 = common(n[0], n[1], origin), c101 = common(n[0], n[2], origin),
                c011 = common(n[1], n[2], origin);
      if (c110 < 0 || c101 < 0 || c011 < 0) continue;
      const int c111 = common(c110, c101, n[0]);
      if (c111 < 0) continue;
      const double score = eu.normalized().x() + ev.normalized().y() + ew.normalized().z();
      if (score > best_score + 1e-12) {
        best_score = score;
        order = {origin, n[0], n[1], c110, n[2], c101, c011, c111};
      }
    } while (std::next_permutation(n.begin(), n.end()));
  }
  return best_score > -INFINITY && std::set<int>(order.begin(), order.end()).size() == 8;
}

}  // namespace

namespace {

// The CAD face (of `faces`) whose vertices are the four corners of a surface patch, or -1.
int face_with_corners(const TopTools_IndexedMapOfShape& faces, const nurbs::Patch& p,
                      double tolerance) {
  for (int g = 1; g <= faces.Extent(); ++g) {
    TopTools_IndexedMapOfShape face_vertices;
    TopExp::MapShapes(faces(g), TopAbs_VERTEX, face_vertices);
    int matched = 0;
    for (int k = 1; k <= face_vertices.Extent(); ++k) {
      const gp_Pnt q = BRep_Tool::Pnt(TopoDS::Vertex(face_vertices(k)));
      for (const nurbs::Param& u : {nurbs::Param{p.param_min(0), p.param_min(1), 0},
                                    nurbs::Param{p.param_max(0), p.param_min(1), 0},
                                    nurbs::Param{p.param_min(0), p.param_max(1), 0},
                                    nurbs::Param{p.param_max(0), p.param_max(1), 0}})
        matched += (p.point(u) - Eigen::Vector3d(q.X(), q.Y(), q.Z())).norm() <= tolerance;
    }
    if (matched == 4) return g;
  }
  return -1;
}

// `top` as a translate of `base` (same knots and weights, every control point moved by the same
// vector), trying the 8 ways to parametrise it (reversals and a swap of directions).
bool translate_of(const nurbs::Patch& base, const nurbs::Patch& top, double tolerance,
                  Eigen::Vector3d& offset) {
  for (int swap = 0; swap < 2; ++swap)
    for (int flips = 0; flips < 4; ++flips) {
      nurbs::Patch t = swap ? swap_directions(top, 0, 1) : top;
      if (flips & 1) t = reverse_direction(t, 0);
      if (flips & 2) t = reverse_direction(t, 1);
      if (t.num_points() != base.num_points() || t.weights() != base.weights() ||
          t.knots(0).values() != base.knots(0).values() ||
          t.knots(1).values() != base.knots(1).values())
        continue;
      offset = t.control_point(0) - base.control_point(0);
      bool same = true;
      for (int a = 0; a < base.num_points() && same; ++a)
        same = (t.control_point(a) - base.control_point(a) - offset).norm() <= tolerance;
      if (same) return true;
    }
  return false;
}

// A hexahedral solid as the extrusion of one natural face to an opposite, translated one.
bool prism_patch(const TopoDS_Shape& solid, const TopTools_IndexedMapOfShape& faces,
                 const std::function<const nurbs::Patch*(const TopoDS_Shape&)>& natural_patch,
                 double size, nurbs::Patch& patch) {
  const double tolerance = std::max(1e-9 * size, BRep_Tool::MaxTolerance(solid, TopAbs_EDGE));
  for (int f = 1; f <= 6; ++f)
    for (int g = f + 1; g <= 6; ++g) {
      const nurbs::Patch *base = natural_patch(faces(f)), *top = natural_patch(faces(g));
      Eigen::Vector3d offset;
      if (base == nullptr || top == nullptr || !translate_of(*base, *top, tolerance, offset))
        continue;
      nurbs::Patch volume = extrude(*base, offset);
      if (jacobian_range(volume).min < 0.0) volume = reverse_direction(volume, 0);
      // The four sides (the extrusions of the base's boundary curves) must be CAD faces.
      bool sides = true;
      for (int dir = 0; dir < 2 && sides; ++dir)
        for (int end = 0; end < 2 && sides; ++end) {
          const nurbs::Patch side = boundary_side(volume, dir, end);
          const int h = face_with_corners(faces, side, 2.0 * tolerance + 1e-12);
          sides = h > 0 && surface_deviation(side, TopoDS::Face(faces(h))) <= tolerance;
        }
      if (sides) {
        patch = volume;
        return true;
      }
    }
  return false;
}

// The solid's topology as a block: its vertices, edges and faces, which vertices each vertex is
// joined to and by which edge, the vertices' positions and the block's corner numbering.
struct HexTopology {
  TopTools_IndexedMapOfShape vertices, edges, faces;
  std::array<std::set<int>, 8> adjacent;            // 0-based vertex -> its 3 neighbours
  std::map<std::pair<int, int>, int> edge_between;  // (vertex, vertex), smaller first -> edge
  std::array<Eigen::Vector3d, 8> x;                 // vertex positions
  std::array<int, 8> order{};                       // corner i + 2 j + 4 k -> vertex
};

// 8 vertices, 12 edges, 6 faces of one wire of 4 edges each, every vertex joining 3 edges; false
// (with why) otherwise.
bool hexahedral_topology(const TopoDS_Shape& solid, HexTopology& t, std::string& why) {
  TopExp::MapShapes(solid, TopAbs_VERTEX, t.vertices);
  TopExp::MapShapes(solid, TopAbs_EDGE, t.edges);
  TopExp::MapShapes(solid, TopAbs_FACE, t.faces);
  std::ostringstream counts;
  counts << t.vertices.Extent() << " vertices, " << t.edges.Extent() << " edges, "
         << t.faces.Extent() << " faces";
  if (t.vertices.Extent() != 8 || t.edges.Extent() != 12 || t.faces.Extent() != 6) {
    why = "not hexahedral (" + counts.str() + "; a block needs 8, 12 and 6)";
    return false;
  }
  for (int f = 1; f <= 6; ++f) {
    TopTools_IndexedMapOfShape wires;
    TopExp::MapShapes(t.faces(f), TopAbs_WIRE, wires);
    if (wires.Extent() != 1 || outer_wire_edges(TopoDS::Face(t.faces(f))) != 4) {
      why = "not hexahedral (a face is not bounded by one loop of 4 edges)";
      return false;
    }
  }
  for (int e = 1; e <= 12; ++e) {
    TopoDS_Vertex a, b;
    TopExp::Vertices(TopoDS::Edge(t.edges(e)), a, b);
    const int i = t.vertices.FindIndex(a) - 1, j = t.vertices.FindIndex(b) - 1;
    if (i < 0 || j < 0 || i == j || t.edge_between.count({std::min(i, j), std::max(i, j)})) {
      why = "not hexahedral (a closed or doubled edge)";
      return false;
    }
    t.edge_between[{std::min(i, j), std::max(i, j)}] = e;
    t.adjacent[static_cast<size_t>(i)].insert(j);
    t.adjacent[static_cast<size_t>(j)].insert(i);
  }
  for (const auto& a : t.adjacent)
    if (a.size() != 3) {
      why = "not hexahedral (a vertex does not join exactly 3 edges)";
      return false;
    }
  return true;
}

// The vertices' positions and the corner numbering (number_corners); false (with why) when the
// corners cannot be numbered consistently.
bool corners_of(HexTopology& t, std::string& why) {
  for (int v = 0; v < 8; ++v) {
    const gp_Pnt p = BRep_Tool::Pnt(TopoDS::Vertex(t.vertices(v + 1)));
    t.x[static_cast<size_t>(v)] = {p.X(), p.Y(), p.Z()};
  }
  if (!number_corners(t.adjacent, t.x, t.order)) {
    why = "not hexahedral (no consistent numbering of the corners)";
    return false;
  }
  return true;
}

// edge[d][a + 2 b]: the edge along direction d at the other two directions' ends a, b (in
// increasing direction order).
using BlockEdges = std::array<std::array<nurbs::Patch, 4>, 3>;

// The 12 edges as curves from corner to corner, ends snapped onto the shared vertices (they may be
// off by the vertex tolerance), compatible per direction. Throws std::runtime_error when an edge
// ends farther than twice the vertex tolerance from its vertex.
BlockEdges block_edges(const HexTopology& t, double vertex_tolerance) {
  BlockEdges edge;
  for (int d = 0; d < 3; ++d) {
    std::vector<nurbs::Patch> curves;
    for (int ab = 0; ab < 4; ++ab) {
      const int a = ab & 1, b = ab >> 1;
      // Corner indices of the edge's start (direction d at 0) and end (at 1).
      std::array<int, 3> ijk{};
      const int other0 = d == 0 ? 1 : 0, other1 = d == 2 ? 1 : 2;
      ijk[static_cast<size_t>(other0)] = a;
      ijk[static_cast<size_t>(other1)] = b;
      ijk[static_cast<size_t>(d)] = 0;
      const int s = t.order[static_cast<size_t>(ijk[0] + 2 * ijk[1] + 4 * ijk[2])];
      ijk[static_cast<size_t>(d)] = 1;
      const int e_end = t.order[static_cast<size_t>(ijk[0] + 2 * ijk[1] + 4 * ijk[2])];
      const TopoDS_Edge e =
          TopoDS::Edge(t.edges(t.edge_between.at({std::min(s, e_end), std::max(s, e_end)}))
                           .Oriented(TopAbs_FORWARD));
      nurbs::Patch c = edge_curve(e);
      TopoDS_Vertex first, second;
      TopExp::Vertices(e, first, second);
      if (t.vertices.FindIndex(first) - 1 != s) c = reverse_direction(c, 0);
      for (auto [index, corner] : {std::pair{0, s}, std::pair{c.num_points() - 1, e_end}}) {
        const double gap = (c.control_point(index) - t.x[static_cast<size_t>(corner)]).norm();
        if (gap > 2.0 * vertex_tolerance + 1e-12)
          throw std::runtime_error("an edge ends " + std::to_string(gap) + " m from its vertex");
        c.set_control_point(index, t.x[static_cast<size_t>(corner)]);
      }
      curves.push_back(c);
    }
    const std::vector<nurbs::Patch> compatible = make_compatible(curves);
    for (int ab = 0; ab < 4; ++ab)
      edge[static_cast<size_t>(d)][static_cast<size_t>(ab)] = compatible[static_cast<size_t>(ab)];
  }
  return edge;
}

// Faces u=a over (v, w), v=b over (u, w), w=c over (u, v) as Coons patches of their edges
// (coons_patch(bottom, right, top, left) with bottom/top along the first face direction).
std::array<nurbs::Patch, 6> block_faces(const BlockEdges& edge) {
  auto E = [&](int d, int a, int b) -> const nurbs::Patch& {
    return edge[static_cast<size_t>(d)][static_cast<size_t>(a + 2 * b)];
  };
  std::array<nurbs::Patch, 6> face_patch;
  for (int e = 0; e < 2; ++e) {
    face_patch[static_cast<size_t>(e)] =
        coons_patch(E(1, e, 0), E(2, e, 1), E(1, e, 1), E(2, e, 0));
    face_patch[static_cast<size_t>(2 + e)] =
        coons_patch(E(0, e, 0), E(2, 1, e), E(0, e, 1), E(2, 0, e));
    face_patch[static_cast<size_t>(4 + e)] =
        coons_patch(E(0, 0, e), E(1, 1, e), E(0, 1, e), E(1, 0, e));
  }
  return face_patch;
}

// Each Coons face must be the CAD face with the same corners; false (with why naming the first
// that is not) otherwise.
bool faces_are_blends(const TopoDS_Shape& solid, const HexTopology& t,
                      const std::array<nurbs::Patch, 6>& face_patch, double vertex_tolerance,
                      double size, std::string& why) {
  for (int f = 0; f < 6; ++f) {
    const nurbs::Patch& p = face_patch[static_cast<size_t>(f)];
    const Eigen::Vector3d mid = p.point({0.5, 0.5, 0});
    const int g = face_with_corners(t.faces, p, 2.0 * vertex_tolerance + 1e-12);
    const double best = g > 0 ? surface_deviation(p, TopoDS::Face(t.faces(g))) : INFINITY;
    const double tolerance = std::max(1e-9 * size, BRep_Tool::MaxTolerance(solid, TopAbs_EDGE));
    if (!(best <= tolerance)) {
      std::ostringstream msg;
      msg.precision(3);
      msg << "hexahedral, but the face near (" << mid.transpose() << ") is not the blend of "
          << "its edges (" << (std::isfinite(best) ? std::to_string(best) + " m off" : "no match")
          << ")";
      why = msg.str();
      return false;
    }
  }
  return true;
}

// The trivariate Coons volume of the faces' Coons patches or, when a face is not the blend of its
// edges, the extrusion of a natural face (`prismatic`); false (with why) when it is neither or
// OpenCascade or a construction fails.
bool block_volume(const TopoDS_Shape& solid, const HexTopology& t,
                  const std::function<const nurbs::Patch*(const TopoDS_Shape&)>& natural_patch,
                  nurbs::Patch& patch, bool& prismatic, std::string& why) {
  try {
    const double vertex_tolerance = BRep_Tool::MaxTolerance(solid, TopAbs_VERTEX);
    const std::array<nurbs::Patch, 6> face_patch = block_faces(block_edges(t, vertex_tolerance));
    const double size =
        (t.x[static_cast<size_t>(t.order[7])] - t.x[static_cast<size_t>(t.order[0])]).norm();
    if (faces_are_blends(solid, t, face_patch, vertex_tolerance, size, why)) {
      patch = coons_volume(face_patch, 2.0 * vertex_tolerance + 1e-12);
    } else {
      if (!prism_patch(solid, t.faces, natural_patch, size, patch)) return false;
      why.clear();  // a prism after all: the extrusion of a natural face
      prismatic = true;
    }
  } catch (const Standard_Failure& e) {
    why = std::string("hexahedral, but OpenCascade failed: ") + e.GetMessageString();
    return false;
  } catch (const std::exception& e) {
    why = std::string("hexahedral, but ") + e.what();
    return false;
  }
  return true;
}

// Right-handed, positive Jacobian inside and OpenCascade's volume to 1e-6; false (with why)
// otherwise.
bool volume_accepted(const TopoDS_Shape& solid, bool prismatic, nurbs::Patch& patch,
                     std::string& why) {
  // The corner numbering judged handedness by straight corner-to-corner vectors; a strongly
  // curved block may still come out left-handed everywhere: mirror the first direction then.
  if (jacobian_range(patch).max < 0.0) patch = reverse_direction(patch, 0);
  if (!(jacobian_range(patch).min > 0.0)) {
    why = "hexahedral, but the transfinite volume folds (Jacobian not positive)";
    return false;
  }
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props, 1e-9);
  const double volume = measure(patch);
  if (std::abs(volume - props.Mass()) > 1e-6 * std::abs(props.Mass())) {
    std::ostringstream msg;
    msg << "hexahedral, but the " << (prismatic ? "extruded" : "transfinite") << " volume "
        << volume << " m^3 differs from the solid's " << props.Mass() << " m^3";
    why = msg.str();
    return false;
  }
  return true;
}

// The stages in order: the topology, the corner numbering, the volume (Coons or prism), and its
// checks.
bool hexahedron_patch(const TopoDS_Shape& solid,
                      const std::function<const nurbs::Patch*(const TopoDS_Shape&)>& natural_patch,
                      nurbs::Patch& patch, std::string& why) {
  HexTopology t;
  if (!hexahedral_topology(solid, t, why) || !corners_of(t, why)) return false;
  bool prismatic = false;
  if (!block_volume(solid, t, natural_patch, patch, prismatic, why)) return false;
  return volume_accepted(solid, prismatic, patch, why);
}

}  // namespace

// A solid with 8 vertices, 12 edges and 6 faces of one wire and 4 edges each as the trivariate
// Coons volume of its faces, each face the Coons patch of its (exactly converted, compatible)
// edges. Planar faces with straight edges give the exact trilinear block. Accepted when every
// face's Coons patch lies on the CAD face's surface, the Jacobian is positive and the volume
// matches OCCT's to 1e-6. Corners are numbered right-handed with u, v, w most along x, y, z.
// When a face is not the blend of its edges, the solid may still be a prism: two opposite faces
// whose natural patches (from `natural_patch`, nullptr if none) are translates of each other give
// the exact ruled (extruded) volume, accepted when the four side faces lie on the CAD faces and
// the volume matches. Otherwise not recognised, with why.
SolidRecognition recognise_hexahedron(const SolidContext& context) {
  SolidRecognition r;
  nurbs::Patch patch;
  r.recognised = hexahedron_patch(context.solid, context.natural_patch, patch, r.why);
  if (r.recognised) r.patches = {patch};
  return r;
}

}  // namespace isospring::geometry::detail
