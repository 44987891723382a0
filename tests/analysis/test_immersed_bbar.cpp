// Immersed mean-dilatation B-bar (analysis/src/immersed_bbar.hpp) on the Lame thick cylinder
// under internal pressure (plane strain), nearly incompressible: the quarter ring cut from a
// B-spline grid that is not aligned with it, symmetry by Nitsche, against the closed form. The
// displacement formulation locks at p = 2 (its error grows as nu -> 0.5: 25 times at nu = 0.4999
// on the finest grid here); B-bar must not: its error stays the same at nu = 0.49 and 0.4999.
// The closed form's divergence is constant, which the cell means represent exactly; what the
// piecewise-constant pressure costs where it is not is measured on the t20 nut
// (docs/immersed.md), not here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "immersed_closed_forms.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::analysis {
namespace {

using geometry::ImmersedDomain;
using geometry::ImplicitGrid;
using geometry::ImplicitShape;

struct Level {
  testing::ErrorNorms errors;
  double strain_energy = 0;  // the solver's, to compare with the exact compliance
  int dofs = 0;
};

// Faces: 0 x = 0 and 2 y = 0 (symmetry), 4 the inner arc (pressure), 5 the outer arc.
Level solve_ring(const testing::LameCylinder& c, int n, Volumetric volumetric) {
  ImplicitShape shape;
  shape.dimension = 2;
  shape.box_max = {c.ro, c.ro, 0.25};
  shape.circles.push_back({Eigen::Vector2d::Zero(), c.ri, false});
  shape.circles.push_back({Eigen::Vector2d::Zero(), c.ro, true});
  ImplicitGrid g;
  g.degree = 2;
  const double h = (c.ro + 0.1) / n;
  g.elements = {n, n, 1};
  g.grid_min = {-0.07, -0.03, 0};
  g.grid_max = {-0.07 + n * h, -0.03 + n * h, 0.25};
  const ImmersedDomain domain = geometry::immerse_implicit(shape, g);
  g.points = 5;
  g.cut_points = 10;
  const ImmersedDomain fine = geometry::immerse_implicit(shape, g);
  ImmersedOptions o;
  o.formulation = Formulation::kPlaneStrain;
  o.material = {c.E, c.nu, 0.0, 1.0};
  o.volumetric = volumetric;
  for (int face : {0, 2}) {
    ImmersedSupport s;
    s.face = face;
    s.symmetry = true;
    o.supports.push_back(s);
  }
  o.pressures.push_back({4, c.P});
  const ImmersedResult result = solve_immersed(domain, o);
  Level level;
  level.dofs = result.dofs;
  level.strain_energy = result.strain_energy;
  level.errors = testing::immersed_errors(
      domain, result, o, fine, [&](const Eigen::Vector3d& x) { return c.displacement(x); },
      [&](const Eigen::Vector3d& x) { return c.stress(x); });
  return level;
}

double relative_l2(const Level& l) {
  return l.errors.l2 / l.errors.l2_exact;
}

// The exact strain energy equals the compliance 1/2 int P u_r(ri) ds over the quarter inner arc.
double exact_energy(const testing::LameCylinder& c) {
  return 0.5 * c.P * c.radial(c.ri) * (M_PI / 2) * c.ri;
}

TEST(ImmersedBbar, LameCylinderDoesNotLock) {
  for (double nu : {0.49, 0.4999}) {
    testing::LameCylinder c;
    c.nu = nu;
    const std::vector<int> levels{6, 12, 24};
    std::vector<Level> bbar, plain;
    for (int n : levels) {
      bbar.push_back(solve_ring(c, n, Volumetric::kBbar));
      plain.push_back(solve_ring(c, n, Volumetric::kDisplacement));
      std::printf(
          "Lame nu %.4f n %2d (%d DOFs): L2 rel B-bar %.3e, displacement %.3e; energy rel "
          "B-bar %+.3e, displacement %+.3e\n",
          nu, n, bbar.back().dofs, relative_l2(bbar.back()), relative_l2(plain.back()),
          bbar.back().strain_energy / exact_energy(c) - 1,
          plain.back().strain_energy / exact_energy(c) - 1);
    }
    for (size_t k = 1; k < levels.size(); ++k)
      std::printf("  rates: B-bar %.2f, displacement %.2f\n",
                  std::log2(relative_l2(bbar[k - 1]) / relative_l2(bbar[k])),
                  std::log2(relative_l2(plain[k - 1]) / relative_l2(plain[k])));
    // Measured (both nu): B-bar 3.8e-3 / 9.3e-3, 1.5e-4 / 1.6e-4, 2.6e-5 / 6.5e-5 on 6, 12, 24
    // cells; the displacement formulation 8.1e-3 / 0.17, 3.6e-4 / 1.8e-2, 3.7e-5 / 1.6e-3. The
    // bounds hold B-bar's error independent of nu (the same bound for both) and at least ten
    // times below the locked formulation's at nu = 0.4999.
    for (size_t k = 1; k < levels.size(); ++k) {
      EXPECT_LT(relative_l2(bbar[k]), 2.5e-4) << nu << " n " << levels[k];
      // The exact energy is approached to the quadrature's and the pressure's accuracy.
      EXPECT_LT(std::abs(bbar[k].strain_energy / exact_energy(c) - 1), 2e-5) << nu;
    }
    EXPECT_LT(relative_l2(bbar.back()), 1e-4) << nu;
    EXPECT_LT(relative_l2(bbar.back()), relative_l2(bbar.front()) / 50) << nu;
    if (nu > 0.499) {
      EXPECT_LT(10 * relative_l2(bbar.back()), relative_l2(plain.back()));
      EXPECT_LT(10 * std::abs(bbar.back().strain_energy / exact_energy(c) - 1),
                std::abs(plain.back().strain_energy / exact_energy(c) - 1));
    }
  }
}

// A cantilever whose divergence is not constant: plane strain, nu = 0.4999, the strip
// [0, 10] x [0, 2] clamped at x = 0 and sheared at x = 10, cut from a grid not aligned with it.
// Reference: the body-fitted B-bar (splines of one degree lower, another projection) at p = 3 on
// 64 x 16 elements.
double strip_tip_immersed(int p, int n, Volumetric volumetric) {
  ImplicitShape shape;
  shape.dimension = 2;
  shape.box_max = {10, 2, 0.25};
  ImplicitGrid g;
  g.degree = p;
  const double h = 10.6 / n;
  g.elements = {n, static_cast<int>(std::ceil(2.6 / h)), 1};
  g.grid_min = {-0.3, -0.27, 0};
  g.grid_max = {-0.3 + n * h, -0.27 + g.elements[1] * h, 0.25};
  const ImmersedDomain domain = geometry::immerse_implicit(shape, g);
  ImmersedOptions o;
  o.formulation = Formulation::kPlaneStrain;
  o.material = {1e5, 0.4999, 0.0, 1.0};
  o.volumetric = volumetric;
  ImmersedSupport clamp;
  clamp.face = 0;
  clamp.fixed = {true, true, false};
  o.supports.push_back(clamp);
  ImmersedTraction t;
  t.face = 1;
  t.value = {0, 10, 0};
  o.tractions.push_back(t);
  const ImmersedResult result = solve_immersed(domain, o);
  return evaluate_immersed(domain, result, {10, 1, 0}).displacement.y();
}

double strip_tip_body_fitted(int p, int nx, int ny) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  const nurbs::Patch strip({linear, linear}, {{0, 0, 0}, {10, 0, 0}, {0, 2, 0}, {10, 2, 0}});
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.volumetric = Volumetric::kBbar;
  problem.material = {1e5, 0.4999, 1.0, 1.0};
  problem.patches.push_back(nurbs::k_refine(strip, {p, p, 0}, {nx, ny, 1}));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "shear";
  load.tractions.push_back({{0, 0, 1}, Eigen::Vector3d(0.0, 10.0, 0.0), {}});
  problem.load_cases.push_back(load);
  const StaticResult result = solve_static(problem);
  return evaluate_field(problem, result.load_cases[0].control_displacements, 0, {1.0, 0.5, 0.0})
      .displacement.y();
}

// Measured (tip deflection relative to the body-fitted p = 3 on 128 x 32, 7.6144e-2; on 64 x 16
// 7.6066e-2, p = 4 on 64 x 16 7.6108e-2: the clamp's corners are singular, so the reference
// itself converges like h and its limit lies about 0.1 % higher): immersed B-bar p = 2 on 10,
// 20, 40, 80 cells along +1.7, +0.30, +0.21, +0.12 %, p = 3 +6.3, +0.46, +0.49, +0.21 %; the
// displacement formulation p = 2 -21, -8.5, -4.1, -1.4 % (locked). B-bar approaches from above
// (its pressure is not conforming, so its energy is no bound) and is soft on coarse grids,
// strongly so at p = 3 on 10 cells.
TEST(ImmersedBbar, ShearedStripAgainstBodyFittedBbar) {
  const double reference = strip_tip_body_fitted(3, 128, 32);
  std::vector<double> bbar2;
  for (int p : {2, 3})
    for (int n : {10, 20, 40, 80}) {
      const double bbar = strip_tip_immersed(p, n, Volumetric::kBbar) / reference - 1;
      const double plain = strip_tip_immersed(p, n, Volumetric::kDisplacement) / reference - 1;
      std::printf(
          "strip p=%d n=%2d: tip relative to body-fitted B-bar: B-bar %+.3e, "
          "displacement %+.3e\n",
          p, n, bbar, plain);
      if (p == 2) bbar2.push_back(bbar);
      if (n >= 40) {
        EXPECT_LT(std::abs(bbar), 5e-3) << p << " " << n;
      }
      if (p == 2 && n == 40) {
        EXPECT_LT(plain, -0.03);  // locked
      }
    }
  // From 20 cells on, p = 2 approaches the reference.
  EXPECT_LT(std::abs(bbar2[3]), std::abs(bbar2[2]));
  EXPECT_LT(std::abs(bbar2[2]), std::abs(bbar2[1]));
}

TEST(ImmersedBbar, PlaneStressIsRefused) {
  const testing::LameCylinder c;
  ImplicitShape shape;
  shape.dimension = 2;
  shape.box_max = {c.ro, c.ro, 0.25};
  shape.circles.push_back({Eigen::Vector2d::Zero(), c.ro, true});
  ImplicitGrid g;
  g.elements = {4, 4, 1};
  g.grid_max = {c.ro + 0.1, c.ro + 0.1, 0.25};
  const ImmersedDomain domain = geometry::immerse_implicit(shape, g);
  ImmersedOptions o;
  o.formulation = Formulation::kPlaneStress;
  o.material = {c.E, c.nu, 0.0, 1.0};
  o.volumetric = Volumetric::kBbar;
  ImmersedSupport s;
  s.face = 0;
  s.fixed = {true, true, false};
  o.supports.push_back(s);
  EXPECT_THROW(solve_immersed(domain, o), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::analysis
