// Where a solid's edges cross a cut cell (immersed_cad_edges.hpp).
#include "immersed_cad_edges.hpp"

#include <BRepBndLib.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>

#include "occt_box.hpp"

namespace isospring::geometry::detail {

namespace {

// Samples per edge: a crossing or turning point between two samples is found by bisection on the
// exact curve; two of them between the same samples (an edge touching a plane twice within 1/64
// of its length) may be missed, and then the Gauss orders' comparison still bisects the cell.
constexpr int kSamples = 64;
constexpr int kBisections = 60;

Eigen::Vector3d to_eigen(const gp_Pnt& p) {
  return {p.X(), p.Y(), p.Z()};
}

// Seams (an edge twice in one face) and degenerate edges: the surface is smooth across them.
bool is_seam_or_degenerate(const TopoDS_Edge& edge, const TopoDS_Shape& solid) {
  if (BRep_Tool::Degenerated(edge)) return true;
  for (TopExp_Explorer f(solid, TopAbs_FACE); f.More(); f.Next()) {
    const TopoDS_Face& face = TopoDS::Face(f.Current());
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next())
      if (e.Current().IsSame(edge)) {
        if (BRep_Tool::IsClosed(edge, face)) return true;
        break;
      }
  }
  return false;
}

}  // namespace

EdgeCrossings::EdgeCrossings(const CadSolid::Shape& shape) {
  auto edges = std::make_shared<std::vector<Edge>>();
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape.solid, TopAbs_EDGE, map);
  for (int i = 1; i <= map.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(map(i));
    double first = 0.0, last = 0.0;
    if (is_seam_or_degenerate(e, shape.solid) || BRep_Tool::Curve(e, first, last).IsNull())
      continue;
    Edge edge;
    edge.edge = e;
    const BRepAdaptor_Curve curve(e);
    const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
    for (int k = 0; k <= kSamples; ++k) {
      edge.t.push_back(t0 + (t1 - t0) * k / kSamples);
      edge.x.push_back(to_eigen(curve.Value(edge.t.back())));
    }
    Bnd_Box box;
    BRepBndLib::Add(e, box, false);
    const Corners box_corners = corners(box);
    edge.box_min = box_corners.lo;
    edge.box_max = box_corners.hi;
    edges->push_back(std::move(edge));
  }
  edges_ = edges;
  make_curves();
}

EdgeCrossings::EdgeCrossings(const EdgeCrossings& other) : edges_(other.edges_) {
  make_curves();
}

void EdgeCrossings::make_curves() {
  curves_.clear();
  for (const Edge& edge : *edges_)
    curves_.push_back(std::make_unique<BRepAdaptor_Curve>(edge.edge));
}

Eigen::Vector3d EdgeCrossings::value(size_t e, double t) const {
  return to_eigen(curves_[e]->Value(t));
}

bool EdgeCrossings::meets(const Edge& edge, const Eigen::Vector3d& lo,
                          const Eigen::Vector3d& hi) const {
  return (edge.box_min.array() <= hi.array()).all() && (edge.box_max.array() >= lo.array()).all();
}

std::vector<double> EdgeCrossings::crossings(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                             int normal, double at, int along) {
  std::vector<double> found;
  const int other = 3 - normal - along;
  for (size_t e = 0; e < edges_->size(); ++e) {
    const Edge& edge = (*edges_)[e];
    if (!meets(edge, lo, hi) || edge.box_min[normal] > at || edge.box_max[normal] < at) continue;
    for (size_t k = 0; k + 1 < edge.x.size(); ++k) {
      double f0 = edge.x[k][normal] - at, f1 = edge.x[k + 1][normal] - at;
      if (f0 == 0.0 && f1 == 0.0) continue;  // along the plane: its ends are turning points
      if ((f0 < 0.0) == (f1 < 0.0) && f1 != 0.0) continue;
      double t0 = edge.t[k], t1 = edge.t[k + 1];
      for (int i = 0; i < kBisections && t1 - t0 > 0.0; ++i) {
        const double tm = 0.5 * (t0 + t1), fm = value(e, tm)[normal] - at;
        if ((fm < 0.0) == (f0 < 0.0)) {
          t0 = tm;
          f0 = fm;
        } else {
          t1 = tm;
        }
      }
      const Eigen::Vector3d x = value(e, 0.5 * (t0 + t1));
      if (x[along] > lo[along] && x[along] < hi[along] && x[other] >= lo[other] &&
          x[other] <= hi[other])
        found.push_back(x[along]);
    }
  }
  return found;
}

std::vector<double> EdgeCrossings::turning_points(const Eigen::Vector3d& lo,
                                                  const Eigen::Vector3d& hi, int along) {
  std::vector<double> found;
  const auto keep = [&](const Eigen::Vector3d& x) {
    if ((x.array() > lo.array()).all() && (x.array() < hi.array()).all()) found.push_back(x[along]);
  };
  for (size_t e = 0; e < edges_->size(); ++e) {
    const Edge& edge = (*edges_)[e];
    if (!meets(edge, lo, hi)) continue;
    keep(edge.x.front());
    keep(edge.x.back());
    // A turning point along the axis: the derivative's component changes sign.
    const auto slope = [&](double t) {
      gp_Pnt p;
      gp_Vec d;
      curves_[e]->D1(t, p, d);
      return Eigen::Vector3d(d.X(), d.Y(), d.Z())[along];
    };
    double previous = slope(edge.t.front());
    for (size_t k = 1; k < edge.t.size(); ++k) {
      const double current = slope(edge.t[k]);
      if ((previous < 0.0) != (current < 0.0) && previous != 0.0 && current != 0.0) {
        double t0 = edge.t[k - 1], t1 = edge.t[k];
        const bool rising = previous > 0.0;
        for (int i = 0; i < kBisections && t1 - t0 > 0.0; ++i) {
          const double tm = 0.5 * (t0 + t1);
          ((slope(tm) > 0.0) == rising ? t0 : t1) = tm;
        }
        keep(value(e, 0.5 * (t0 + t1)));
      }
      previous = current;
    }
  }
  return found;
}

}  // namespace isospring::geometry::detail
