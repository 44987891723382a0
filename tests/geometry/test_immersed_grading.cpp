// Graded background grids of immersed CAD solids (immersed_cad.hpp, GradingPlane): the knots
// against the geometric progression they stand for, the background patch against the identities
// every B-spline box must keep (partition of unity, the affine map of the Greville points), and
// the quadrature's volume, area and centroid against OpenCascade's, unchanged by the grading.
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBndLib.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "../../geometry/src/immersed_grading.hpp"
#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

using nurbs::InputError;

// Cells graded towards x = 0 on [0, 1] (base length 0.1) have lengths 0.01 * 1.5^n, then
// 0.1 ln(1.5) / 0.5. Their number is the density's integral rounded up, in closed form
// (r - 1) / ln(r) (ln(H / s) / (r - 1) + (1 - d_H) / H), d_H = (H - s) / (r - 1).
TEST(GradedTicks, FollowTheGeometricProgression) {
  const double s = 0.01, r = 1.5, H = 0.1;
  const std::vector<double> t = detail::graded_ticks(0.0, 1.0, 10, {{0, 0.0, s, r}}, 0);
  const double d_t = (H - s) / (r - 1);
  const double integral = (r - 1) / std::log(r) * (std::log(H / s) / (r - 1) + (1.0 - d_t) / H);
  ASSERT_EQ(static_cast<int>(t.size()) - 1, static_cast<int>(std::ceil(integral)));
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t.back(), 1.0);
  // Each cell holds `share` (<= 1) of the integral: near the plane the progression by r (up to
  // the midpoint rule's error), then cells of at most H.
  const double share = integral / (static_cast<double>(t.size()) - 1);
  for (size_t i = 1; i < t.size(); ++i) {
    const double length = t[i] - t[i - 1];
    ASSERT_GT(length, 0.0);
    EXPECT_LE(length, H * (1 + 1e-9));
    if (i < 2) continue;
    const double growth = length / (t[i - 1] - t[i - 2]);
    EXPECT_LE(growth, r * (1 + 1e-4));
    if (t[i] < d_t) {
      EXPECT_NEAR(growth, std::pow(r, share), 1e-4);
    }
  }
  // The first cell [0, t1] holds `share`: ln(1 + (r - 1) t1 / s) / ln(r) = share.
  EXPECT_NEAR(t[1], s * (std::pow(r, share) - 1) / (r - 1), 1e-4 * s);
}

TEST(GradedTicks, TwoPlanesAndAnUngradedAxis) {
  const std::vector<GradingPlane> planes = {{1, 0.2, 0.005, 1.3}, {1, 0.8, 0.005, 1.3}};
  const std::vector<double> x = detail::graded_ticks(0.0, 1.0, 10, planes, 0);
  ASSERT_EQ(x.size(), 11u);
  for (size_t i = 0; i < x.size(); ++i) EXPECT_DOUBLE_EQ(x[i], 0.1 * static_cast<double>(i));
  const std::vector<double> y = detail::graded_ticks(0.0, 1.0, 10, planes, 1);
  // Symmetric about 0.5, smallest next to 0.2 and 0.8.
  ASSERT_GT(y.size(), 20u);
  for (size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(y[i] + y[y.size() - 1 - i], 1.0, 1e-4);
  double at_plane = 1.0;
  for (size_t i = 1; i < y.size(); ++i)
    if (y[i - 1] <= 0.2 + 0.01 && y[i] >= 0.2 - 0.01)
      at_plane = std::min(at_plane, y[i] - y[i - 1]);
  EXPECT_LE(at_plane, 0.005 * (1 + 1e-9));
  EXPECT_GT(at_plane, 0.005 / 1.3);
}

// A block 100 x 60 x 40 mm with a through-hole (r 12 mm) and one rounded edge (r 10 mm).
CadSolid holed_block() {
  TopoDS_Shape block = BRepPrimAPI_MakeBox(0.1, 0.06, 0.04).Shape();
  block =
      BRepAlgoAPI_Cut(block, BRepPrimAPI_MakeCylinder(
                                 gp_Ax2(gp_Pnt(0.06, 0.03, -0.01), gp_Dir(0, 0, 1)), 0.012, 0.06)
                                 .Shape())
          .Shape();
  BRepFilletAPI_MakeFillet fillet(block);
  for (TopExp_Explorer e(block, TopAbs_EDGE); e.More(); e.Next()) {
    // The edge along z at x = 0.1, y = 0.06.
    Bnd_Box box;
    const TopoDS_Edge edge = TopoDS::Edge(e.Current());
    BRepBndLib::Add(edge, box);
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    if (x0 > 0.0999 && y0 > 0.0599 && z1 - z0 > 0.039) fillet.Add(0.01, edge);
  }
  return detail::make_cad_solid(fillet.Shape(), "holed block");
}

int face_at_x0(const CadSolid& solid) {
  const auto& shape = solid.shape();
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    Bnd_Box box;
    BRepBndLib::AddOptimal(shape.faces[k], box, false, false);
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    if (std::abs(x0) < 1e-9 && std::abs(x1) < 1e-9) return shape.face_index[k];
  }
  return -1;
}

TEST(ImmersedGrading, PlanesThroughTheFacesBoundingBox) {
  const CadSolid solid = holed_block();
  const int face = face_at_x0(solid);
  ASSERT_GE(face, 0);
  const std::vector<GradingPlane> planes = grading_towards_face(solid, face, 0.002, 1.4);
  // Flat in x: one plane x = 0; y from 0 to 0.06 and z from 0 to 0.04: two each.
  ASSERT_EQ(planes.size(), 5u);
  const double expected[5][2] = {{0, 0.0}, {1, 0.0}, {1, 0.06}, {2, 0.0}, {2, 0.04}};
  for (size_t i = 0; i < planes.size(); ++i) {
    EXPECT_EQ(planes[i].axis, expected[i][0]);
    EXPECT_NEAR(planes[i].at, expected[i][1], 1e-9);
    EXPECT_EQ(planes[i].smallest, 0.002);
    EXPECT_EQ(planes[i].ratio, 1.4);
  }
  EXPECT_THROW(grading_towards_face(solid, solid.face_count(), 0.002, 1.4), InputError);
  ImmersionOptions bad;
  bad.cell_size = 0.01;
  bad.grading = {{0, 0.0, 0.0, 1.4}};
  EXPECT_THROW(immerse_solid(solid, bad), InputError);
  bad.grading = {{0, 0.0, 0.002, 0.5}};
  EXPECT_THROW(immerse_solid(solid, bad), InputError);
  bad.grading = {{3, 0.0, 0.002, 1.4}};
  EXPECT_THROW(immerse_solid(solid, bad), InputError);
}

// The graded box is still an affine B-spline box over [origin, origin + extent] (its control
// points at the Greville abscissae of the graded knots reproduce x(u) = origin + extent u), its
// basis sums to one, its knots are the cells of the domain, and the quadrature's volume, area and
// centroid agree with OpenCascade's to 1e-6 as on the uniform grid.
TEST(ImmersedGrading, AffineBoxPartitionOfUnityAndMeasures) {
  const CadSolid solid = holed_block();
  ImmersionOptions options;
  options.cell_size = 0.01;
  options.tolerance = 1e-7;
  options.grading = grading_towards_face(solid, face_at_x0(solid), 0.002, 1.5);
  const ImmersedDomain domain = immerse_solid(solid, options);
  const nurbs::Patch& patch = domain.background;
  // Graded: more cells than 10 x 6 x 4, and the first cell along x 0.002 m or a little less.
  EXPECT_GT(patch.knots(0).num_elements(), 10);
  EXPECT_GT(patch.knots(1).num_elements(), 6);
  EXPECT_GT(patch.knots(2).num_elements(), 4);
  const auto first = patch.knots(0).unique();
  EXPECT_LE(first[1] * domain.extent.x(), 0.002 * (1 + 1e-9));
  EXPECT_GT(first[1] * domain.extent.x(), 0.002 / 1.5);

  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 200; ++n) {
    const nurbs::Param u = {unit(random), unit(random), unit(random)};
    const nurbs::RationalBasis basis = patch.basis(u, 1);
    EXPECT_NEAR(basis.values.sum(), 1.0, 1e-13);
    EXPECT_NEAR(basis.first.colwise().sum().norm(), 0.0, 1e-9);
    const Eigen::Vector3d expected =
        domain.origin + domain.extent.cwiseProduct(Eigen::Vector3d(u[0], u[1], u[2]));
    EXPECT_NEAR((patch.point(u) - expected).norm(), 0.0, 1e-13);
  }
  // Every inside cell's weights sum to its knot span's volume.
  for (const ImmersedCell& cell : domain.cells) {
    if (cell.kind != CellKind::kInside) continue;
    double volume = 1.0, sum = 0.0;
    for (int d = 0; d < 3; ++d) {
      const auto& kv = patch.knots(d);
      volume *= (kv[cell.span[d] + 1] - kv[cell.span[d]]) * domain.extent[d];
    }
    for (double w : cell.weights) sum += w;
    EXPECT_NEAR(sum, volume, 1e-12 * volume);
  }

  const SolidMeasures exact = measure_solid(solid);
  const SolidMeasures graded = measure_quadrature(domain);
  options.grading.clear();
  const SolidMeasures uniform = measure_quadrature(immerse_solid(solid, options));
  std::printf("holed block: volume error graded %.2e, uniform %.2e; area %.2e, %.2e\n",
              std::abs(graded.volume / exact.volume - 1),
              std::abs(uniform.volume / exact.volume - 1), std::abs(graded.area / exact.area - 1),
              std::abs(uniform.area / exact.area - 1));
  EXPECT_NEAR(graded.volume, exact.volume, 1e-6 * exact.volume);
  EXPECT_NEAR(graded.area, exact.area, 1e-6 * exact.area);
  EXPECT_NEAR((graded.centroid - exact.centroid).norm(), 0.0, 1e-6 * std::cbrt(exact.volume));
  EXPECT_NEAR(uniform.volume, exact.volume, 1e-6 * exact.volume);
}

// The face of `solid` lying in the plane x[axis] = at.
int face_in_plane(const CadSolid& solid, int axis, double at) {
  const auto& shape = solid.shape();
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    Bnd_Box box;
    BRepBndLib::AddOptimal(shape.faces[k], box, false, false);
    double lo[3], hi[3];
    box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    if (std::abs(lo[axis] - at) < 1e-9 && std::abs(hi[axis] - at) < 1e-9)
      return shape.face_index[k];
  }
  return -1;
}

// The analysis on a graded grid: a block in uniaxial tension (symmetry on x = 0, y = 0, z = 0,
// traction sigma on x = a) has the linear solution u = sigma / E (x, -nu y, -nu z); Nitsche's
// method and the ghost penalty are consistent, so a graded grid (with a margin, so that every
// face cuts cells) must reproduce it and its energy sigma^2 V / (2 E) up to the cut cells'
// quadrature, which is exact only to its tolerance (1e-7 of a cell's volume): measured 1.1e-9
// (energy) and 1.5e-6 of the largest displacement (at the part's corner, in a corner cell).
TEST(ImmersedGrading, LinearSolutionIsReproducedOnAGradedGrid) {
  const double a = 0.1, b = 0.06, c = 0.04, sigma = 1e6, E = 2e11, nu = 0.3;
  const CadSolid solid = detail::make_cad_solid(BRepPrimAPI_MakeBox(a, b, c).Shape(), "block");
  ImmersionOptions immersion;
  immersion.cell_size = 0.02;
  immersion.margin = 0.0037;
  immersion.grading = grading_towards_face(solid, face_in_plane(solid, 0, 0.0), 0.004, 1.5);
  const ImmersedDomain domain = immerse_solid(solid, immersion);
  ASSERT_GT(domain.background.knots(0).num_elements(), 6);

  analysis::ImmersedOptions options;
  options.material.youngs_modulus = E;
  options.material.poisson_ratio = nu;
  for (int axis = 0; axis < 3; ++axis) {
    analysis::ImmersedSupport symmetry;
    symmetry.face = face_in_plane(solid, axis, 0.0);
    symmetry.symmetry = true;
    options.supports.push_back(symmetry);
  }
  analysis::ImmersedTraction pull;
  pull.face = face_in_plane(solid, 0, a);
  pull.value = Eigen::Vector3d(sigma, 0, 0);
  options.tractions.push_back(pull);
  const analysis::ImmersedResult result = analysis::solve_immersed(domain, options);

  const double volume = a * b * c;
  EXPECT_NEAR(result.strain_energy, sigma * sigma * volume / (2 * E),
              1e-8 * sigma * sigma * volume / (2 * E));
  const double scale = sigma / E * a;
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.001, 0.002, 0.003),
                                   Eigen::Vector3d(0.05, 0.03, 0.02), Eigen::Vector3d(a, b, c)}) {
    const Eigen::Vector3d exact = sigma / E * Eigen::Vector3d(x.x(), -nu * x.y(), -nu * x.z());
    EXPECT_NEAR((analysis::evaluate_immersed(domain, result, x).displacement - exact).norm(), 0.0,
                1e-5 * scale);
  }
}

}  // namespace
}  // namespace isospring::geometry
