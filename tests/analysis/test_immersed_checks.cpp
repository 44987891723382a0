// Immersed elasticity: consistency (fields in the spline space are reproduced to round-off with
// Nitsche supports, tractions, body force and the ghost penalty), conditioning independent of
// how the grid cuts the part, and the input checks.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

#include "immersed_closed_forms.hpp"
#include "isospring/analysis/block_cg.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

using geometry::ImmersedDomain;
using geometry::ImplicitGrid;
using geometry::ImplicitShape;

constexpr int kLeft = 0, kRight = 1, kBottom = 2, kTop = 3, kHole = 4;

ImplicitShape plate_with_hole() {
  ImplicitShape shape;
  shape.box_max = {4, 4, 0};
  shape.circles.push_back({Eigen::Vector2d::Zero(), 1.0, false});
  return shape;
}

// A grid of n cells of size 4 / n over the plate, shifted so that the part's left and bottom
// sides cut the first cells at `offset` cell sizes from their far edge (slivers when small).
ImplicitGrid shifted_grid(int p, int n, double offset) {
  ImplicitGrid g;
  g.degree = p;
  const double h = 4.0 / n;
  g.elements = {n + 2, n + 2, 1};
  g.grid_min = {-h + offset * h, -h + offset * h, 0};
  g.grid_max = g.grid_min + Eigen::Vector3d((n + 2) * h, (n + 2) * h, 0);
  return g;
}

std::string input_error(const ImmersedDomain& domain, const ImmersedOptions& options) {
  try {
    solve_immersed(domain, options);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no error";
}

// A linear displacement field is in the spline space: Nitsche's method, the traction terms and
// the ghost penalty are consistent, so the immersed solution is the field itself, on a grid that
// cuts the part's sides into slivers as well as on an aligned one.
TEST(ImmersedChecks, LinearFieldIsReproducedToRoundOff) {
  const Eigen::Matrix2d grad = (Eigen::Matrix2d() << 1.0e-3, 2.0e-4, -3.0e-4, -5.0e-4).finished();
  const Eigen::Vector2d shift(1e-4, -2e-4);
  const auto u = [&](const Eigen::Vector3d& x) {
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    out.head<2>() = shift + grad * x.head<2>();
    return out;
  };
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStrain;
  options.material = {2e5, 0.3, 0.0, 1.0};
  Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();
  strain.topLeftCorner<2, 2>() = 0.5 * (grad + grad.transpose());
  const Eigen::Matrix3d sigma = stress_from_strain(strain, options.material, options.formulation);
  for (int face : {kLeft, kBottom}) {
    ImmersedSupport s;
    s.face = face;
    s.fixed = {true, face == kLeft, false};  // x and y on the left, x at the bottom
    s.value_function = u;
    options.supports.push_back(s);
  }
  // The bottom holds x only: its y traction is a load (it acts through I - P on that face).
  for (int face : {kRight, kTop, kHole, kBottom}) {
    ImmersedTraction t;
    t.face = face;
    t.function = [&](const Eigen::Vector3d&, const Eigen::Vector3d& n) -> Eigen::Vector3d {
      return sigma * n;
    };
    options.tractions.push_back(t);
  }
  for (const double offset : {0.0, 0.5, 1e-3}) {
    for (int p : {2, 3}) {
      const ImmersedDomain domain =
          geometry::immerse_implicit(plate_with_hole(), shifted_grid(p, 6, offset));
      const ImmersedResult result = solve_immersed(domain, options);
      double worst = 0;
      for (const auto& cell : domain.cells)
        for (const auto& x : cell.points)
          worst =
              std::max(worst, (evaluate_immersed(domain, result, x).displacement - u(x)).norm());
      EXPECT_LT(worst, 1e-12) << "offset " << offset << " p " << p;
      // The strain energy is 1/2 sigma : eps times the area.
      const double area = 16 - M_PI / 4;
      EXPECT_NEAR(result.strain_energy, 0.5 * sigma.cwiseProduct(strain).sum() * area,
                  1e-10 * result.strain_energy);
    }
  }
}

// A bar hanging under gravity, nu = 0 (no lateral contraction): u_y = -rho g (H y - y^2 / 2) / E
// for a clamp at y = 0 and gravity -g along y; quadratic, so p = 2 reproduces it exactly. The
// grid cuts all four sides.
TEST(ImmersedChecks, GravityAndBodyForceOnACutBar) {
  const double H = 3.0, E = 7e4, rho = 2.7, g = 9.81, b = 5.0;
  ImplicitShape bar;
  bar.box_max = {1.0, H, 0};
  ImplicitGrid grid;
  grid.degree = 2;
  grid.elements = {4, 9, 1};
  grid.grid_min = {-0.13, -0.21, 0};
  grid.grid_max = {1.11, H + 0.17, 0};
  const ImmersedDomain domain = geometry::immerse_implicit(bar, grid);
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStress;
  options.material = {E, 0.0, rho, 1.0};
  options.gravity = {0, -g, 0};
  options.body_force = {0, -b, 0};
  ImmersedSupport clamp;
  clamp.face = kBottom;
  clamp.fixed = {true, true, false};
  options.supports.push_back(clamp);
  const ImmersedResult result = solve_immersed(domain, options);
  const double load = rho * g + b;
  for (const Eigen::Vector3d& x :
       {Eigen::Vector3d(0.5, 1.0, 0), Eigen::Vector3d(0.1, H, 0), Eigen::Vector3d(0.93, 2.2, 0)}) {
    const Eigen::Vector3d uh = evaluate_immersed(domain, result, x).displacement;
    const double exact = -load * (H * x.y() - 0.5 * x.y() * x.y()) / E;
    EXPECT_NEAR(uh.y(), exact, 1e-12 * std::abs(load * H * H / E)) << x.transpose();
    EXPECT_NEAR(uh.x(), 0.0, 1e-12 * std::abs(load * H * H / E));
  }
  // Strain energy: int sigma^2 / (2E) with sigma = load (H - y): load^2 H^3 / (6 E).
  EXPECT_NEAR(result.strain_energy, load * load * H * H * H / (6 * E),
              1e-10 * result.strain_energy);
}

// Jacobi-scaled condition number (dense, the system is small) and block-Jacobi CG iterations as
// the grid slides under the part, down to slivers of 1e-6 cells along the supported sides: with
// the ghost penalty both stay put; without it the Nitsche penalty of the slivers cannot be
// bounded and the system is not even positive definite.
TEST(ImmersedChecks, ConditioningDoesNotDependOnTheCut) {
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStress;
  options.material = {1e5, 0.3, 0.0, 1.0};
  for (int face : {kLeft, kBottom}) {
    ImmersedSupport s;
    s.face = face;
    s.symmetry = true;
    options.supports.push_back(s);
  }
  ImmersedPressure pressure;
  pressure.face = kRight;
  pressure.value = -10.0;
  options.pressures.push_back(pressure);
  struct Conditioning {
    bool definite = false;
    double kappa = 0;
    int iterations = 0;
  };
  const auto measure = [&](double offset, double gamma) {
    ImmersedOptions o = options;
    o.ghost_penalty = gamma;
    const ImmersedDomain domain =
        geometry::immerse_implicit(plate_with_hole(), shifted_grid(2, 8, offset));
    const ImmersedSystem system = assemble_immersed(domain, o);
    const Eigen::MatrixXd K = Eigen::MatrixXd(system.stiffness).selfadjointView<Eigen::Upper>();
    Conditioning out;
    if (K.diagonal().minCoeff() <= 0) return out;
    const Eigen::VectorXd d = K.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd scaled = d.asDiagonal() * K * d.asDiagonal();
    const Eigen::VectorXd ev =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(scaled, Eigen::EigenvaluesOnly)
            .eigenvalues();
    if (ev.minCoeff() <= 0) return out;
    out.definite = true;
    out.kappa = ev.maxCoeff() / ev.minCoeff();
    Eigen::VectorXd u;
    BlockCgOptions cg;
    cg.tolerance = 1e-8;
    out.iterations =
        block_cg(SymmetricBlockMatrix(system.stiffness, 2), system.force, u, cg).iterations;
    return out;
  };
  std::vector<Conditioning> stabilised;
  bool plain_sliver_definite = true;
  for (const double offset : {0.5, 0.1, 1e-2, 1e-3, 1e-4, 1e-6}) {
    const Conditioning c = measure(offset, options.ghost_penalty);
    const Conditioning plain = measure(offset, 0.0);
    std::printf(
        "offset %.0e h: condition %.3e, CG iterations %d; without ghost penalty %s %.3e "
        "(%d)\n",
        offset, c.kappa, c.iterations, plain.definite ? "" : "not positive definite", plain.kappa,
        plain.iterations);
    EXPECT_TRUE(c.definite) << offset;
    stabilised.push_back(c);
    if (offset <= 1e-3) plain_sliver_definite = plain_sliver_definite && plain.definite;
  }
  // Cells with at least ghost_fraction of the part are left alone, so the condition number varies
  // with the cut (offsets 0.5 and 0.1, measured 320 and 990), within a bounded range; below
  // that fraction the ghost penalty takes over and nothing depends on the sliver's size.
  double lowest = 1e300, highest = 0;
  int fewest = 1 << 30, most = 0;
  for (const auto& c : stabilised) {
    lowest = std::min(lowest, c.kappa), highest = std::max(highest, c.kappa);
    fewest = std::min(fewest, c.iterations), most = std::max(most, c.iterations);
  }
  EXPECT_LT(highest / lowest, 8.0);
  EXPECT_LT(most, 3 * fewest);
  for (size_t k = 3; k < stabilised.size(); ++k) {
    EXPECT_NEAR(stabilised[k].kappa, stabilised[2].kappa, 0.01 * stabilised[2].kappa);
    EXPECT_LE(std::abs(stabilised[k].iterations - stabilised[2].iterations), 2);
  }
  EXPECT_FALSE(plain_sliver_definite);
}

TEST(ImmersedChecks, SupportsThatLeaveARigidMotionFreeAreTheUsualError) {
  const ImmersedDomain domain =
      geometry::immerse_implicit(plate_with_hole(), shifted_grid(2, 4, 0.3));
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStress;
  options.material = {1e5, 0.3, 0.0, 1.0};
  ImmersedSupport s;
  s.face = kLeft;
  s.symmetry = true;
  options.supports.push_back(s);
  EXPECT_EQ(input_error(domain, options),
            "the supports leave free: translation y (rigid-body motion of the immersed part); add "
            "supports (fixed components or symmetry faces) that block this motion");
  options.supports[0].symmetry = false;
  options.supports[0].fixed = {false, true, false};  // u_y on x = 0: x and rotation free
  EXPECT_EQ(input_error(domain, options)
                .find("the supports leave free: translation x, rotation "
                      "about z"),
            0u)
      << input_error(domain, options);
  options.supports[0].face = 5;
  EXPECT_NE(
      input_error(domain, options).find("support face 5 does not exist; the part has faces 0..4"),
      std::string::npos);
  options.supports[0].face = kLeft;
  options.formulation = Formulation::kSolid;
  EXPECT_NE(input_error(domain, options).find("needs formulation plane stress or plane strain"),
            std::string::npos);
}

// The project's two solvers give the same immersed solution: sparse Cholesky and block-Jacobi
// CG (to its tolerance); and points are evaluated inside the background grid only.
TEST(ImmersedChecks, CholeskyAndConjugateGradientsAgree) {
  const ImmersedDomain domain =
      geometry::immerse_implicit(plate_with_hole(), shifted_grid(3, 8, 1e-3));
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStress;
  options.material = {1e5, 0.3, 0.0, 1.0};
  for (int face : {kLeft, kBottom}) {
    ImmersedSupport s;
    s.face = face;
    s.symmetry = true;
    options.supports.push_back(s);
  }
  ImmersedPressure pull;
  pull.face = kRight;
  pull.value = -10.0;
  options.pressures.push_back(pull);
  const ImmersedResult direct = solve_immersed(domain, options);
  options.method = SolverOptions::Method::kConjugateGradient;
  options.cg_tolerance = 1e-12;
  const ImmersedResult iterative = solve_immersed(domain, options);
  EXPECT_GT(iterative.iterations, 0);
  EXPECT_EQ(direct.iterations, 0);
  double scale = 0, difference = 0;
  int inactive = 0;  // the grid reaches beyond the part: basis functions that are no DOF
  for (size_t a = 0; a < direct.control_displacements.size(); ++a) {
    scale = std::max(scale, direct.control_displacements[a].norm());
    difference = std::max(
        difference, (direct.control_displacements[a] - iterative.control_displacements[a]).norm());
    if (!direct.active[a]) {
      EXPECT_EQ(direct.control_displacements[a].norm(), 0.0);
    }
    inactive += direct.active[a] ? 0 : 1;
  }
  EXPECT_GT(inactive, 0);
  EXPECT_EQ(2 * (static_cast<int>(direct.active.size()) - inactive), direct.dofs);
  EXPECT_LT(difference, 1e-8 * scale);
  EXPECT_NEAR(direct.strain_energy, iterative.strain_energy, 1e-9 * direct.strain_energy);
  EXPECT_THROW(evaluate_immersed(domain, direct, Eigen::Vector3d(10, 1, 0)), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::analysis
