#pragma once
// The immersed (finite-cell) domain of a CAD solid, built on its exact B-rep.
//
// The part is embedded in an affine B-spline box (its bounding box plus a margin, or a box the
// user gives). Background cells are classified on the exact B-rep: a block of cells that no face
// comes near (OpenCascade's exact distance from the block's centre to every face whose bounding
// box meets the block, against the block's half-diagonal; for B-spline faces, whether the boxes of
// their Bezier pieces' control nets meet the block) lies wholly inside or outside, decided
// by OpenCascade's solid classifier at its centre; otherwise it is halved until single cells
// remain, which are cut. No Boolean operation touches the part.
//
// Cut cells are integrated by lines intersected exactly with the B-rep faces
// (IntCurvesFace_Intersector, whose transitions say where a line enters and leaves the part; on
// planes, cylinders, cones, spheres and tori its answer is reproduced from the closed-form
// surface intersection and a per-face grid of UV bins that no trimming curve meets, which
// replaces its point-in-face test wherever that test cannot change, and on B-spline faces from
// Bezier subdivision and Newton's method with the same bins), dimension by dimension:
// the outer interval of a cell is split where the cell's edges along it cross the boundary, each
// outer Gauss abscissa's middle interval where the lines through the cell's two faces normal to the
// line direction cross it, and along every Gauss line the inside intervals are exact. So the rule
// is Gauss-exact along each line and, between those break points, integrates functions that are
// smooth wherever the boundary is smooth inside the cell: it converges exponentially there. The
// line direction of a cell is the axis closest to the boundary normal nearest to its centre, so the
// boundary is a graph over the cell's cross section. What the break points do not catch (a sharp
// edge of the part crossing a cell obliquely, a tangent of a section curve along the outer
// direction) is found by comparing the cell's volume with two Gauss orders: the cell is then split
// into eight and each child treated the same way, up to `max_depth` levels. A Gauss rule over a
// singular point has the same relative error at any size, so the test is absolute (a fraction of
// the background cell's volume): each bisection divides such a piece's error by eight.
//
// Why not the alternatives: an octree with plain Gauss leaves converges only like the leaf size
// squared at the boundary (1e-6 would need millions of leaves); moment fitting needs the cut
// cells' exact moments, i.e. this integration anyway; a tessellated boundary is not the exact
// part.
//
// Boundary points are integrated on every face's exact trimmed parametrisation: Gauss in u
// between break points (vertices, u-extrema of the trimming curves, knots), the iso-line
// u = const clipped to the face by OpenCascade's hatcher (Geom2dHatch) on the trimming curves,
// and Gauss in v on each inside piece; the number of pieces is doubled (at most twice) until the
// face's area and first moments repeat to 1e-9.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::geometry {

/// One closed, valid solid of a CAD file (OpenCascade's B-rep, kept out of this header).
class CadSolid {
 public:
  struct Shape;  // OpenCascade's solid and its faces (../../geometry/src/cad_solid_shape.hpp)
  CadSolid(std::shared_ptr<const Shape> shape, std::string name);
  const Shape& shape() const { return *shape_; }
  const std::string& name() const { return name_; }  // the file (or what built the solid)
  int face_count() const;  // faces of the file (as `isospring info` numbers them)

 private:
  std::shared_ptr<const Shape> shape_;
  std::string name_;
};

/// Reads solid `solid` (0-based, as `isospring info` lists them; -1: the file must hold exactly
/// one) of a STEP/IGES file. Faces without a solid (IGES surfaces) are sewn (1e-6 m) and closed.
/// Throws nurbs::InputError naming the file and the fix for an open shell, an invalid solid
/// (BRepCheck_Analyzer), several solids without a choice, or a solid index out of range.
CadSolid read_cad_solid(const std::filesystem::path& file, int solid = -1);

/// The solid placed rigidly: every point x goes to rotation * x + translation. OpenCascade
/// transforms the B-rep's geometry itself (BRepBuilderAPI_Transform with a copy), which is exact
/// up to round-off; the faces keep their order and their indices as `isospring info` prints them
/// for the file, and the name stays the file's. Throws nurbs::InputError when `rotation` is not
/// orthonormal (|R^T R - I| > 1e-12) or is a reflection (det R = -1), naming the fix.
CadSolid transform_solid(const CadSolid& solid, const Eigen::Matrix3d& rotation,
                         const Eigen::Vector3d& translation = Eigen::Vector3d::Zero());

/// The solid's principal axes of inertia (OpenCascade's GProp_PrincipalProps of the volume),
/// as the columns of a rotation, ordered by increasing moment (so the first axis runs along the
/// part's longest extent). Signs: the first two axes point where their largest component (in
/// absolute value; the lower index on a tie to 1e-12) is positive, and the third is their cross
/// product (det = +1). Where two moments are equal to 1e-6 of the largest, the axes in their
/// plane are not defined by the part: the odd one keeps its place in the order, and the first of
/// the pair is the world axis least aligned with the odd one, projected into the plane (the
/// second follows by the cross product); where all three are equal the frame is the world's.
/// `note` says which fallback was taken (empty when none).
struct PrincipalFrame {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: the axes in world coordinates
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();   // about the centroid, per unit density
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::string note;
};
PrincipalFrame principal_frame(const CadSolid& solid);

/// OpenCascade's volume, area and centroid of the solid (BRepGProp, adaptive, 1e-10).
struct SolidMeasures {
  double volume = 0.0;
  double area = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};
SolidMeasures measure_solid(const CadSolid& solid);

/// The same measures from an immersed domain's quadrature: volume and centroid from the cells,
/// area from the boundary points.
SolidMeasures measure_quadrature(const ImmersedDomain& domain);

/// Background cells graded towards the plane x[axis] = at: the cells next to it are `smallest` long
/// (m) along `axis` and each further one `ratio` times longer, until they reach the grid's base
/// cell length H (from `cells` or `cell_size`); from there on an axis's cells are
/// H ln(ratio) / (ratio - 1) long, so that the growth never exceeds `ratio`. Several planes may
/// grade one axis; each point takes the smallest cells any plane asks for there.
struct GradingPlane {
  int axis = 0;           // 0, 1, 2 for x, y, z
  double at = 0.0;        // the plane's coordinate (m)
  double smallest = 0.0;  // cell length at the plane (m), > 0
  double ratio = 1.5;     // growth from one cell to the next, >= 1
};

struct ImmersionOptions {
  int degree = 2;  // of the background B-spline box, >= 1
  /// Cells per direction; when zero, from cell_size; when that is zero too, 10 cells along the
  /// longest side of the box and cells as close to cubes as the sides allow.
  Eigen::Vector3i cells = Eigen::Vector3i::Zero();
  double cell_size = 0.0;  // target cell edge (m), used when `cells` is zero
  /// Knots clustered towards planes (e.g. those of grading_towards_face); empty: uniform.
  std::vector<GradingPlane> grading;
  /// Coordinates (m) per axis kept as cell boundaries, e.g. the part's planar faces normal to the
  /// axes (planar_face_coordinates): such a face then lies on a grid plane and cuts no cell, also
  /// when the axis is graded. Between them the cells are uniform (a piece of length L holds
  /// ceil(L / H) equal cells, H the base cell length) or graded as above. A box end within 10
  /// confusions (1e-6 m) of a coordinate moves onto it; coordinates closer than 1e-3 H to an end
  /// or to each other count once (no cell thinner than that); outside the box: ignored; empty:
  /// none.
  std::array<std::vector<double>, 3> breaks;
  /// Added on every side of the part's bounding box (m); ignored with a user box.
  double margin = 0.0;
  /// The grid's axes: a rotation whose columns are the grid's x, y and z axes in world
  /// coordinates (identity: the file's axes). The grid is the box of the part's extent along
  /// these axes, so a part placed obliquely in its file gets a tight box and faces that lie on
  /// grid planes (e.g. with principal_frame's axes). `box_min`, `box_max`, `grading` and
  /// `breaks` are then coordinates along the frame's axes (y = frame^T x); the domain's points,
  /// normals and background control points are world coordinates (ImmersedDomain::frame).
  /// Throws nurbs::InputError for a matrix that is not a rotation (as transform_solid).
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  /// A user box (axis-aligned in the frame, m) instead of the bounding box; it must contain the
  /// part. Used when box_max > box_min in every direction.
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  /// Gauss points per direction and piece in cut cells and on faces (>= degree + 1; 0: degree
  /// + 2). Inside cells get the tensor rule of degree + 1 points.
  int gauss = 0;
  int max_depth = 4;  // bisections of a cut cell whose quadrature does not converge
  /// A cut cell (or a piece of it) is accepted when its volumes with `gauss` and `gauss` + 2
  /// points differ by less than this fraction of the background cell's volume.
  double tolerance = 1e-7;
  /// The boundary quadrature's points may take at most this much memory (GB, estimated before
  /// they are made: their pieces follow the grid's thinnest cell); above it immerse_solid throws
  /// naming the largest face and the fix instead of allocating.
  double max_quadrature_gb = 8.0;
  /// Threads integrating cut cells (0: one per core, OpenMP's default). The result does not
  /// depend on it.
  int threads = 0;
};

/// Where the time went and how much work it was (for benchmarks and reports).
struct ImmersionStats {
  double boundary_seconds = 0.0;        // face quadrature
  double classification_seconds = 0.0;  // inside / outside / cut
  double cut_cell_seconds = 0.0;        // cut-cell quadrature
  int inside_cells = 0, cut_cells = 0;
  int sliver_cells = 0;        // cut cells with under 1e-9 of their volume inside, left out
  long cut_boxes = 0;          // cut cells and their octree children integrated
  long lines = 0;              // lines intersected with the B-rep
  long classified_lines = 0;   // of which needed the solid classifier (crossings did not alternate)
  long distance_queries = 0;   // exact point-face distances of the classification
  long face_lines = 0;         // line-face intersections (lines x faces near them)
  long binned_face_lines = 0;  // of which every hit was classified by the face's UV bins
  long face_classifications = 0;  // hits near a trimming curve classified by OpenCascade
  int threads = 1;                // that integrated the cut cells
};

/// Grading planes through the bounding box of face `face` (its index as `isospring info` prints
/// it): per axis one plane where the face is flat in that axis, else one at each end of its extent.
/// So the cells are smallest along the face's outline, where a clamp's stresses are singular (a
/// held face meeting a free one). Throws nurbs::InputError for a face index out of range.
std::vector<GradingPlane> grading_towards_face(const CadSolid& solid, int face, double smallest,
                                               double ratio);

/// The coordinates of the solid's planar faces normal to an axis (within 1e-9 rad), per axis,
/// increasing, each once (those closer than 1e-9 of the part's size merged): the `breaks` that keep
/// such faces on grid planes. Taken from the planes' equations, not from the faces' vertices (which
/// may lie off them by up to the B-rep's tolerance).
std::array<std::vector<double>, 3> planar_face_coordinates(const CadSolid& solid);

/// The immersed domain of `solid`. Throws nurbs::InputError naming the option and the fix for a
/// degree below 1, no cells, a negative margin, a user box that does not contain the part, or a
/// part smaller than one cell in every direction (the grid could not resolve it).
ImmersedDomain immerse_solid(const CadSolid& solid, const ImmersionOptions& options = {},
                             ImmersionStats* stats = nullptr);

}  // namespace isospring::geometry
