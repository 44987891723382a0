#pragma once
// Where a solid's edges cross a cut cell (immersed_cad_cells.cpp): the places where a cell's
// line integrals stop being smooth although no line changes how it meets the part.
//
// Along a line's inside intervals the rule is exact, and between break points of the outer and
// middle axes it integrates the lengths of those intervals, which are smooth wherever the
// boundary is smooth. Across an edge of the B-rep they are not: a sharp edge puts a kink in them,
// a tangent edge (a fillet meeting a plane) a jump of their curvature. Two Gauss orders can agree
// across such a point while both miss (on 5^3 cells over the rounded bracket, the fillet's tangent
// edge cost 4e-5 of six cells). The singular outer coordinates are where an edge enters or leaves
// the cell's cross section (crosses one of the four box faces parallel to the outer axis), its
// ends, and its turning points along that axis; at an outer abscissa, the middle coordinate is
// where an edge crosses that section's plane.
#include <BRepAdaptor_Curve.hxx>
#include <TopoDS_Edge.hxx>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "cad_solid_shape.hpp"

namespace isospring::geometry::detail {

class EdgeCrossings {
 public:
  /// The solid's edges, except seams and degenerate ones (not where the boundary bends).
  explicit EdgeCrossings(const CadSolid::Shape& shape);
  /// A copy for another thread: the same samples, its own curve evaluators.
  EdgeCrossings(const EdgeCrossings& other);
  EdgeCrossings& operator=(const EdgeCrossings&) = delete;

  /// Coordinates `along` of the points where edges cross the plane x[normal] = at, inside the
  /// box [lo, hi] (in its other coordinate).
  std::vector<double> crossings(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int normal,
                                double at, int along);

  /// Coordinates `along` of the edges' ends and turning points along it inside the box.
  std::vector<double> turning_points(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                     int along);

 private:
  struct Edge {
    TopoDS_Edge edge;
    std::vector<double> t;             // curve parameters of the samples
    std::vector<Eigen::Vector3d> x;    // the samples
    Eigen::Vector3d box_min, box_max;  // of the edge, enlarged by its sampling's chord error
  };
  void make_curves();
  Eigen::Vector3d value(size_t e, double t) const;
  bool meets(const Edge& edge, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;

  std::shared_ptr<const std::vector<Edge>> edges_;
  std::vector<std::unique_ptr<BRepAdaptor_Curve>> curves_;  // per edge, this probe's own
};

}  // namespace isospring::geometry::detail
