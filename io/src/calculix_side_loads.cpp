// Consistent nodal forces of tractions and pressures for a CalculiX deck (calculix_mesh.hpp):
// f_a = integral of N_a t dA over each element face, on the deck's own serendipity faces so that
// CalculiX sees the load its elements would integrate.
#include <Eigen/Geometry>
#include <functional>

#include "calculix_mesh.hpp"

namespace isospring::io::calculix_detail {
using Eigen::Vector3d;

namespace {

using TractionFunction = std::function<Vector3d(const Vector3d&, const Vector3d&)>;

/// One side's load: a pressure (traction -p n), a traction function of (x, n), or a constant.
struct SideLoad {
  const analysis::Side& side;
  const Vector3d& constant;
  const TractionFunction& f;
  double pressure;
  bool is_pressure;
  Vector3d traction(const Vector3d& x, const Vector3d& n) const {
    return is_pressure ? Vector3d(-pressure * n) : f ? f(x, n) : constant;
  }
};

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

/// 2D: 3-node edges along the other parametric direction; forces per unit length times the
/// thickness, as the plane elements carry it.
void add_edge_loads(const analysis::Problem& problem, const DeckMesh& mesh,
                    const nurbs::GaussRule& rule, const SideLoad& load,
                    std::map<int, Vector3d>& forces) {
  const analysis::Side& side = load.side;
  const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
  const PatchNodes& pn = mesh.patches[static_cast<size_t>(side.patch)];
  const int along = 1 - side.dir;
  for (int s0 = 0; s0 + 2 < pn.size[along]; s0 += 2) {
    int nodes[3];
    Vector3d x[3];
    for (int q = 0; q < 3; ++q) {
      std::array<int, 3> idx{0, 0, 0};
      idx[side.dir] = side.end ? pn.size[side.dir] - 1 : 0;
      idx[along] = s0 + q;
      nodes[q] = pn.at(idx[0], idx[1], idx[2]);
      x[q] = mesh.nodes[static_cast<size_t>(nodes[q])];
    }
    nurbs::Param mid{};
    mid[side.dir] = pn.params[side.dir][static_cast<size_t>(side.end ? pn.size[side.dir] - 1 : 0)];
    mid[along] = pn.params[along][static_cast<size_t>(s0 + 1)];
    const Vector3d outward_ref = patch.derivatives(mid).first.col(side.dir) * (side.end ? 1 : -1);
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
      const Vector3d traction = load.traction(xq, n);
      const double w = rule.weights[i] * length * problem.material.thickness;
      for (int q = 0; q < 3; ++q) {
        auto [it, inserted] = forces.try_emplace(nodes[q], Vector3d::Zero());
        it->second += w * N[q] * traction;
      }
    }
  }
}

/// 3D: 8-node serendipity faces.
void add_face_loads(const analysis::Problem& problem, const DeckMesh& mesh,
                    const nurbs::GaussRule& rule, const SideLoad& load,
                    std::map<int, Vector3d>& forces) {
  const analysis::Side& side = load.side;
  const nurbs::Patch& patch = problem.patches[static_cast<size_t>(side.patch)];
  const PatchNodes& pn = mesh.patches[static_cast<size_t>(side.patch)];
  const int a = std::min((side.dir + 1) % 3, (side.dir + 2) % 3);
  const int b = std::max((side.dir + 1) % 3, (side.dir + 2) % 3);
  for (int t0 = 0; t0 + 2 < pn.size[b]; t0 += 2)
    for (int s0 = 0; s0 + 2 < pn.size[a]; s0 += 2) {
      int nodes[8];
      Vector3d x[8];
      for (int q = 0; q < 8; ++q) {
        const auto idx = side_index(pn, side.dir, side.end, s0 + kQuad8[q][0], t0 + kQuad8[q][1]);
        nodes[q] = pn.at(idx[0], idx[1], idx[2]);
        x[q] = mesh.nodes[static_cast<size_t>(nodes[q])];
      }
      // Outward: along +dX/du_dir at the last knot, against it at the first.
      nurbs::Param mid{};
      mid[side.dir] = pn.params[side.dir][side.end ? pn.size[side.dir] - 1 : 0];
      mid[a] = pn.params[a][s0 + 1];
      mid[b] = pn.params[b][t0 + 1];
      const Vector3d outward_ref = patch.derivatives(mid).first.col(side.dir) * (side.end ? 1 : -1);
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
          const Vector3d traction = load.traction(xq, n);
          const double w = rule.weights[i] * rule.weights[j] * area;
          for (int q = 0; q < 8; ++q) {
            auto [it, inserted] = forces.try_emplace(nodes[q], Vector3d::Zero());
            it->second += w * N[q] * traction;
          }
        }
    }
}

}  // namespace

std::map<int, Vector3d> side_load_forces(const analysis::Problem& problem, const DeckMesh& mesh,
                                         const nurbs::GaussRule& rule,
                                         const analysis::LoadCase& lc) {
  const bool solid = problem.formulation == analysis::Formulation::kSolid;
  std::map<int, Vector3d> forces;
  auto add = [&](const SideLoad& load) {
    (solid ? add_face_loads : add_edge_loads)(problem, mesh, rule, load, forces);
  };
  const TractionFunction none;
  for (const auto& tr : lc.tractions) add({tr.side, tr.value, tr.function, 0.0, false});
  const Vector3d zero = Vector3d::Zero();
  for (const auto& pr : lc.pressures) add({pr.side, zero, none, pr.value, true});
  return forces;
}

}  // namespace isospring::io::calculix_detail
