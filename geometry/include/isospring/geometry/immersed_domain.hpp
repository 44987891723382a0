// An immersed (finite-cell) domain: a part embedded in a B-spline background grid, with the
// quadrature that integrates over the part only. Built by geometry (from a CAD solid's exact B-rep,
// or from an implicit shape), consumed by analysis (immersed elasticity). No OpenCascade here.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

// Where a background cell lies relative to the part.
enum class CellKind { kInside, kCut };  // outside cells are not stored

// The quadrature of one background cell (a knot span of the background patch).
struct ImmersedCell {
  Eigen::Vector3i span = Eigen::Vector3i::Zero();  // knot-span index per direction (z = 0 in 2D)
  CellKind kind = CellKind::kInside;
  std::vector<Eigen::Vector3d> points;  // physical coordinates (z = 0 in 2D)
  std::vector<double> weights;          // physical volume (area in 2D) weights, > 0
};

// A quadrature point on the part's boundary (the B-rep face it lies on, exact position and normal).
struct BoundaryPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // physical coordinates
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit outward normal of the part
  double weight = 0.0;                               // physical area (length in 2D) weight
  int face = -1;  // index of the part's face (as `isospring info` lists them; 2D: boundary curve)
};

struct ImmersedDomain {
  int dimension = 3;
  // The background grid: an affine B-spline box (parametric [0,1]^d mapped linearly onto the box),
  // so grid coordinates y and parametric ones are related by `origin` and `extent`
  // (y = origin + extent * u), and world coordinates x by the rotation `frame`, whose columns are
  // the grid's axes in the world (x = frame * y; identity unless the grid was placed in a user
  // frame, always in 2D). Points, normals and the background's control points are world
  // coordinates; `origin` and `extent` are grid coordinates.
  nurbs::Patch background;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent = Eigen::Vector3d::Ones();
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  std::vector<ImmersedCell> cells;      // inside and cut cells only
  std::vector<BoundaryPoint> boundary;  // the part's whole boundary
  int face_count = 0;                   // number of boundary faces / curves
  std::vector<std::string> warnings;    // e.g. cells whose quadrature could not be refined further

  // Grid coordinates of a world point, and back.
  Eigen::Vector3d to_grid(const Eigen::Vector3d& x) const { return frame.transpose() * x; }
  Eigen::Vector3d to_world(const Eigen::Vector3d& y) const { return frame * y; }
};

}  // namespace isospring::geometry
