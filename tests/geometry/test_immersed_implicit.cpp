// Immersed domains of analytic shapes: areas, volumes and moments against closed forms, the
// boundary against the divergence theorem, and the input checks.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/geometry/immersed_implicit.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

// [0, L]^2 minus the disc of radius a at the origin (the Kirsch quarter plate).
ImplicitShape plate_with_hole(double a, double L) {
  ImplicitShape shape;
  shape.box_max = {L, L, 0};
  shape.circles.push_back({Eigen::Vector2d::Zero(), a, false});
  return shape;
}

// Quarter annulus ri..ro in the first quadrant.
ImplicitShape quarter_annulus(double ri, double ro) {
  ImplicitShape shape;
  shape.box_max = {ro, ro, 0};
  shape.circles.push_back({Eigen::Vector2d::Zero(), ri, false});
  shape.circles.push_back({Eigen::Vector2d::Zero(), ro, true});
  return shape;
}

ImplicitGrid grid(int degree, int elements) {
  ImplicitGrid g;
  g.degree = degree;
  g.elements = {elements, elements, elements};
  return g;
}

// int over the part of x^a y^b (z^c) from the cell quadrature.
double cell_moment(const ImmersedDomain& d, int a, int b, int c = 0) {
  double sum = 0;
  for (const auto& cell : d.cells)
    for (size_t q = 0; q < cell.points.size(); ++q)
      sum += cell.weights[q] * std::pow(cell.points[q].x(), a) * std::pow(cell.points[q].y(), b) *
             std::pow(cell.points[q].z(), c);
  return sum;
}

// The same moment from the boundary by the divergence theorem: int x^(a+1)/(a+1) y^b z^c n_x.
double boundary_moment(const ImmersedDomain& d, int a, int b, int c = 0) {
  double sum = 0;
  for (const auto& p : d.boundary)
    sum += p.weight * std::pow(p.point.x(), a + 1) / (a + 1) * std::pow(p.point.y(), b) *
           std::pow(p.point.z(), c) * p.normal.x();
  return sum;
}

double face_measure(const ImmersedDomain& d, int face) {
  double sum = 0;
  for (const auto& p : d.boundary)
    if (p.face == face) sum += p.weight;
  return sum;
}

// Area to round-off for grids aligned with the box, coarse and fine, every degree: the lines
// intersect the circle exactly and the pieces between tangents are smooth (exponential
// convergence, with as many points across the lines as the nearest tangent asks for).
TEST(ImmersedImplicit, PlateWithHoleAreaAndMoments) {
  const double a = 1.0, L = 4.0;
  for (int p : {1, 2, 3}) {
    for (int n : {3, 4, 8, 16}) {
      const ImmersedDomain d = immerse_implicit(plate_with_hole(a, L), grid(p, n));
      EXPECT_NEAR(cell_moment(d, 0, 0), L * L - M_PI * a * a / 4, 1e-12) << p << " " << n;
      // int x dA = L^3 / 2 - a^3 / 3 (quarter disc moment).
      EXPECT_NEAR(cell_moment(d, 1, 0), L * L * L / 2 - a * a * a / 3, 1e-11) << p << " " << n;
      // Degree 7 along the arc: the boundary rule of 2 (p + 1) points is exact enough from p = 2.
      if (p >= 2) {
        EXPECT_NEAR(cell_moment(d, 2, 3), boundary_moment(d, 2, 3), 1e-9) << p << n;
      }
      EXPECT_NEAR(face_measure(d, 4), M_PI * a / 2, 1e-12);
      EXPECT_NEAR(face_measure(d, 0), L - a, 1e-12);
      EXPECT_NEAR(face_measure(d, 1), L, 1e-12);
      EXPECT_TRUE(d.warnings.empty());
    }
  }
}

TEST(ImmersedImplicit, QuarterAnnulusOnAShiftedLargerGrid) {
  const double ri = 1.0, ro = 2.0;
  for (const double shift : {0.0, 1e-3, 0.0371, 0.13}) {
    ImplicitGrid g = grid(2, 9);
    g.grid_min = {-0.3 + shift, -0.25 - shift, 0};
    g.grid_max = {2.2 + shift, 2.3 - shift, 0};
    const ImmersedDomain d = immerse_implicit(quarter_annulus(ri, ro), g);
    const double area = M_PI * (ro * ro - ri * ri) / 4;
    EXPECT_NEAR(cell_moment(d, 0, 0), area, 1e-12) << shift;
    EXPECT_NEAR(cell_moment(d, 1, 0), (ro * ro * ro - ri * ri * ri) / 3, 1e-12) << shift;
    EXPECT_NEAR(cell_moment(d, 3, 1), boundary_moment(d, 3, 1), 1e-10) << shift;
    EXPECT_NEAR(face_measure(d, 4), M_PI * ri / 2, 1e-12);
    EXPECT_NEAR(face_measure(d, 5), M_PI * ro / 2, 1e-12);
    EXPECT_NEAR(face_measure(d, 0), ro - ri, 1e-12);
    EXPECT_EQ(face_measure(d, 1), 0.0);  // x = ro touches the disc at one point only
    // Closed boundary: int n ds = 0, and the normals are unit and outward (int x.n = 2 A).
    Eigen::Vector3d n_sum = Eigen::Vector3d::Zero();
    double flux = 0;
    for (const auto& p : d.boundary) {
      EXPECT_NEAR(p.normal.norm(), 1.0, 1e-14);
      n_sum += p.weight * p.normal;
      flux += p.weight * p.point.dot(p.normal);
    }
    EXPECT_LT(n_sum.norm(), 1e-13);
    EXPECT_NEAR(flux, 2 * area, 1e-12);
    // Cells are either inside (full cells) or cut, and weights are positive.
    for (const auto& cell : d.cells)
      for (double w : cell.weights) EXPECT_GT(w, 0.0);
  }
}

// A hole that is small next to the cells (several tangents per cell): bisection finds
// tangent-free directions; an off-centre hole checks the general position.
TEST(ImmersedImplicit, SmallOffCentreHoleInCoarseCells) {
  ImplicitShape shape;
  shape.box_max = {1, 1, 0};
  shape.circles.push_back({Eigen::Vector2d(0.43, 0.61), 0.17, false});
  const ImmersedDomain d = immerse_implicit(shape, grid(2, 2));
  EXPECT_NEAR(cell_moment(d, 0, 0), 1 - M_PI * 0.17 * 0.17, 1e-13);
  // int x dA = 1/2 - pi r^2 cx
  EXPECT_NEAR(cell_moment(d, 1, 0), 0.5 - M_PI * 0.17 * 0.17 * 0.43, 1e-13);
  EXPECT_NEAR(face_measure(d, 4), 2 * M_PI * 0.17, 1e-13);
}

TEST(ImmersedImplicit, ExtrudedBoxWithCylindricalHoleAndThickCylinder) {
  ImplicitShape plate = plate_with_hole(1.0, 4.0);
  plate.dimension = 3;
  plate.box_min.z() = -0.5;
  plate.box_max.z() = 1.5;
  const ImmersedDomain d = immerse_implicit(plate, grid(2, 4));
  const double area = 16 - M_PI / 4;
  EXPECT_NEAR(cell_moment(d, 0, 0), 2 * area, 1e-11);
  EXPECT_NEAR(cell_moment(d, 0, 0, 1), 0.5 * area * (1.5 * 1.5 - 0.25), 1e-11);
  EXPECT_NEAR(cell_moment(d, 1, 2, 1), boundary_moment(d, 1, 2, 1), 1e-9);
  EXPECT_NEAR(face_measure(d, 6), M_PI / 2 * 2, 1e-12);  // cylinder face
  EXPECT_NEAR(face_measure(d, 4), area, 1e-12);          // z = box_min.z
  EXPECT_EQ(d.face_count, 7);
  ImplicitShape ring = quarter_annulus(1.0, 2.0);
  ring.dimension = 3;
  ring.box_max.z() = 0.5;
  ImplicitGrid g = grid(3, 5);
  g.elements.z() = 1;
  const ImmersedDomain r = immerse_implicit(ring, g);
  EXPECT_NEAR(cell_moment(r, 0, 0), 0.5 * M_PI * 3 / 4, 1e-12);
}

// Spheres: an octant of a ball, a box with an off-centre spherical void in coarse cells, and an
// octant of a hollow sphere (two nested spheres), against closed forms.
TEST(ImmersedImplicit, SpheresVolumesAreasAndMoments) {
  ImplicitShape octant;
  octant.dimension = 3;
  octant.box_max = {1, 1, 1};
  octant.spheres.push_back({Eigen::Vector3d::Zero(), 1.0, true});
  for (int n : {2, 5}) {
    const ImmersedDomain d = immerse_implicit(octant, grid(2, n));
    EXPECT_NEAR(cell_moment(d, 0, 0), M_PI / 6, 1e-10) << n;
    EXPECT_NEAR(cell_moment(d, 1, 0), M_PI / 16, 1e-10) << n;  // int x over the octant
    EXPECT_NEAR(face_measure(d, 6), M_PI / 2, 1e-10) << n;     // an eighth of 4 pi
    EXPECT_NEAR(face_measure(d, 0), M_PI / 4, 1e-12) << n;     // quarter disc on x = 0
    EXPECT_NEAR(face_measure(d, 1), 0.0, 1e-15) << n;          // x = 1 touches at a point
    EXPECT_NEAR(cell_moment(d, 1, 1, 1), boundary_moment(d, 1, 1, 1), 1e-10) << n;
    EXPECT_TRUE(d.warnings.empty()) << d.warnings.front();
  }
  ImplicitShape void_box;
  void_box.dimension = 3;
  void_box.box_min = {-1, -1, -1};
  void_box.box_max = {1, 1, 1};
  const Eigen::Vector3d c(0.1, -0.05, 0.2);
  const double r = 0.37;
  void_box.spheres.push_back({c, r, false});
  const ImmersedDomain v = immerse_implicit(void_box, grid(2, 3));
  EXPECT_NEAR(cell_moment(v, 0, 0), 8 - 4 * M_PI * r * r * r / 3, 1e-10);
  EXPECT_NEAR(cell_moment(v, 0, 0, 1), -4 * M_PI * r * r * r / 3 * c.z(), 1e-10);
  EXPECT_NEAR(face_measure(v, 6), 4 * M_PI * r * r, 1e-10);
  ImplicitShape hollow = octant;
  hollow.box_max = {2, 2, 2};
  hollow.spheres = {{Eigen::Vector3d::Zero(), 2.0, true}, {Eigen::Vector3d::Zero(), 1.0, false}};
  const ImmersedDomain h = immerse_implicit(hollow, grid(2, 4));
  EXPECT_NEAR(cell_moment(h, 0, 0), 7 * M_PI / 6, 1e-10);
  EXPECT_NEAR(face_measure(h, 7), M_PI / 2, 1e-10);
  EXPECT_NEAR(face_measure(h, 6), 2 * M_PI, 1e-10);
  EXPECT_NEAR(face_measure(h, 2), 3 * M_PI / 4, 1e-12);  // quarter annulus on y = 0
  double flux = 0;
  for (const auto& p : h.boundary) flux += p.weight * p.point.dot(p.normal);
  EXPECT_NEAR(flux, 3 * 7 * M_PI / 6, 1e-9);
}

TEST(ImmersedImplicit, BackgroundIsTheAffineBoxAndSpansAreKnotSpans) {
  ImplicitGrid g = grid(3, 5);
  g.grid_min = {-1, -2, 0};
  g.grid_max = {5, 4, 0};
  const ImmersedDomain d = immerse_implicit(plate_with_hole(1.0, 4.0), g);
  EXPECT_EQ(d.origin, Eigen::Vector3d(-1, -2, 0));
  EXPECT_EQ(d.extent.head<2>(), Eigen::Vector2d(6, 6));
  for (const nurbs::Param u : {nurbs::Param{0.3, 0.7, 0}, nurbs::Param{0.91, 0.05, 0}}) {
    const Eigen::Vector3d x = d.background.point(u);
    EXPECT_NEAR(x.x(), -1 + 6 * u[0], 1e-13);
    EXPECT_NEAR(x.y(), -2 + 6 * u[1], 1e-13);
  }
  for (const auto& cell : d.cells)
    for (const auto& x : cell.points)
      for (int dir = 0; dir < 2; ++dir)
        EXPECT_EQ(cell.span[dir], d.background.knots(dir).find_span((x[dir] - d.origin[dir]) / 6));
}

TEST(ImmersedImplicit, BadInputNamesTheField) {
  const auto message = [](const ImplicitShape& s, const ImplicitGrid& g) {
    try {
      immerse_implicit(s, g);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ImplicitShape s = plate_with_hole(1.0, 4.0);
  ImplicitGrid g = grid(2, 4);
  g.grid_max = {3, 4, 0};
  g.grid_min = {0, 0, 0};
  EXPECT_NE(message(s, g).find("does not contain the shape's box along x"), std::string::npos);
  s.circles[0].radius = -1;
  EXPECT_NE(message(s, grid(2, 4)).find("circles[0].radius"), std::string::npos);
  s = plate_with_hole(10.0, 4.0);  // the hole removes everything
  EXPECT_NE(message(s, grid(2, 4)).find("covers no cell"), std::string::npos);
  EXPECT_NE(message(plate_with_hole(1, 4), grid(0, 4)).find("degree"), std::string::npos);
  ImplicitShape balls;
  balls.dimension = 3;
  balls.spheres = {{Eigen::Vector3d::Zero(), 0.5, true}, {Eigen::Vector3d(0.6, 0, 0), 0.3, false}};
  EXPECT_NE(message(balls, grid(2, 2)).find("spheres[0] and spheres[1] intersect"),
            std::string::npos);
}

}  // namespace
}  // namespace isospring::geometry
