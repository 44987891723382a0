// The closed-form solutions of "analytic" are checked against the equations they must satisfy,
// independently of their derivation: Hooke's law applied to the (finite-difference) strain of the
// displacement reproduces the stated stress, the stress is in equilibrium (div sigma = 0), and the
// boundary tractions are the stated loads.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using Eigen::Matrix3d;
using Eigen::Vector3d;
using nlohmann::json;

analysis::Material material(double E, double nu) {
  analysis::Material m;
  m.youngs_modulus = E;
  m.poisson_ratio = nu;
  return m;
}

/// Central differences of the displacement (step h relative to the size of the problem).
Matrix3d gradient(const AnalyticSolution& s, const Vector3d& x, int dim, double h) {
  Matrix3d g = Matrix3d::Zero();
  for (int j = 0; j < dim; ++j) {
    const Vector3d dx = h * Vector3d::Unit(j);
    g.col(j) = (s.displacement(x + dx) - s.displacement(x - dx)) / (2 * h);
  }
  return g;
}

/// Hooke's law for the formulation (plane stress: in-plane with the reduced Lame constant).
Matrix3d hooke(const Matrix3d& grad, const analysis::Material& m, analysis::Formulation f) {
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  const double mu = E / (2 * (1 + nu));
  double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  const Matrix3d eps = 0.5 * (grad + grad.transpose());
  if (f == analysis::Formulation::kPlaneStress) {
    lambda = 2 * mu * lambda / (lambda + 2 * mu);
    Matrix3d s = lambda * eps.trace() * Matrix3d::Identity() + 2 * mu * eps;
    s.row(2).setZero();
    s.col(2).setZero();
    return s;
  }
  return lambda * eps.trace() * Matrix3d::Identity() + 2 * mu * eps;
}

Vector3d divergence(const AnalyticSolution& s, const Vector3d& x, int dim, double h) {
  Vector3d div = Vector3d::Zero();
  for (int j = 0; j < dim; ++j) {
    const Vector3d dx = h * Vector3d::Unit(j);
    div += (s.stress(x + dx) - s.stress(x - dx)).col(j) / (2 * h);
  }
  return div;
}

/// Constitutive + equilibrium at sample points. Central differences have error O(h^2) ~ 1e-8
/// relative with h = 1e-4 * size, far below the 1e-6 tolerance, and far above round-off.
void expect_elasticity(const AnalyticSolution& s, const std::vector<Vector3d>& points, int dim,
                       const analysis::Material& m, analysis::Formulation f, double size,
                       double stress_scale) {
  const double h = 1e-4 * size;
  for (const Vector3d& x : points) {
    const Matrix3d from_displacement = hooke(gradient(s, x, dim, h), m, f);
    EXPECT_LT((from_displacement - s.stress(x)).norm(), 1e-6 * stress_scale) << x.transpose();
    EXPECT_LT(divergence(s, x, dim, h).norm(), 1e-6 * stress_scale / size) << x.transpose();
  }
}

TEST(AnalyticSolution, KirschSatisfiesElasticityAndLoads) {
  for (auto f : {analysis::Formulation::kPlaneStress, analysis::Formulation::kPlaneStrain}) {
    const auto m = material(1e5, 0.3);
    const AnalyticSolution s = make_analytic_solution(
        json{{"type", "kirsch"}, {"traction", 10.0}, {"radius", 1.0}}, m, f, "case.json: analytic");
    std::vector<Vector3d> points;
    for (double r : {1.2, 2.0, 3.7})
      for (double t : {0.1, 1.0, 2.0, 2.9})
        points.emplace_back(r * std::cos(t), r * std::sin(t), 0);
    expect_elasticity(s, points, 2, m, f, 1.0, 10.0);
    // Traction-free hole and the far-field traction along x.
    for (double t : {0.3, 1.4, 2.5}) {
      const Vector3d n(std::cos(t), std::sin(t), 0);
      EXPECT_LT((s.stress(n) * n).norm(), 1e-13);
    }
    const Matrix3d far = s.stress(Vector3d(1e4, 3e3, 0));
    EXPECT_NEAR(far(0, 0), 10.0, 1e-6);
    EXPECT_NEAR(far(1, 1), 0.0, 1e-6);
  }
}

TEST(AnalyticSolution, LameCylinderPressureAndFreeOuterSurface) {
  for (auto f : {analysis::Formulation::kPlaneStress, analysis::Formulation::kPlaneStrain}) {
    const auto m = material(2e5, 0.25);
    const AnalyticSolution s = make_analytic_solution(json{{"type", "lame_cylinder"},
                                                           {"inner_radius", 1.0},
                                                           {"outer_radius", 2.0},
                                                           {"pressure", 3.0}},
                                                      m, f, "case.json: analytic");
    std::vector<Vector3d> points;
    for (double r : {1.1, 1.5, 1.9}) points.emplace_back(r * std::cos(0.7), r * std::sin(0.7), 0);
    expect_elasticity(s, points, 2, m, f, 1.0, 3.0);
    const Vector3d e(std::cos(0.4), std::sin(0.4), 0);
    EXPECT_NEAR(e.dot(s.stress(1.0 * e) * e), -3.0, 1e-13);
    EXPECT_NEAR(e.dot(s.stress(2.0 * e) * e), 0.0, 1e-13);
  }
}

TEST(AnalyticSolution, TimoshenkoEndLoadAndFreeEdges) {
  const auto m = material(1e5, 0.3);
  const double L = 10, D = 2, P = -5;
  const AnalyticSolution s = make_analytic_solution(
      json{
          {"type", "timoshenko"}, {"length", L}, {"depth", D}, {"load", P}, {"origin", {1.0, 2.0}}},
      m, analysis::Formulation::kPlaneStress, "case.json: analytic");
  std::vector<Vector3d> points{{2.0, 2.3, 0}, {6.0, 1.2, 0}, {10.5, 2.9, 0}};
  expect_elasticity(s, points, 2, m, analysis::Formulation::kPlaneStress, L, 100.0);
  // Clamp: no displacement at the mid-depth point of x = 0.
  EXPECT_LT(s.displacement(Vector3d(1, 2, 0)).norm(), 1e-15);
  // Free top and bottom edges; the end traction sums to the shear force -P along y... by Gauss.
  EXPECT_LT((s.stress(Vector3d(4, 3, 0)) * Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((s.stress(Vector3d(4, 1, 0)) * Vector3d::UnitY()).norm(), 1e-12);
  const double g = 1 / std::sqrt(3.0);  // 2-point Gauss is exact for the parabola
  const double fy =
      (s.stress(Vector3d(1 + L, 2 + g, 0))(1, 0) + s.stress(Vector3d(1 + L, 2 - g, 0))(1, 0)) * D /
      2;
  EXPECT_NEAR(fy, -P, 1e-12);
  // Euler-Bernoulli plus shear: tip deflection of the neutral axis.
  const double I = D * D * D / 12;
  EXPECT_NEAR(s.displacement(Vector3d(1 + L, 2, 0)).y(),
              -P * L * L * L / (3 * 1e5 * I) - P * (4 + 5 * 0.3) * D * D * L / (24 * 1e5 * I),
              1e-12 * std::abs(P * L * L * L / (3 * 1e5 * I)));
}

TEST(AnalyticSolution, HollowSphereSatisfiesElasticity) {
  const auto m = material(3e5, 0.2);
  const AnalyticSolution s =
      make_analytic_solution(json{{"type", "hollow_sphere"},
                                  {"inner_radius", 1.0},
                                  {"outer_radius", 1.5},
                                  {"pressure", 2.0}},
                             m, analysis::Formulation::kSolid, "case.json: analytic");
  std::vector<Vector3d> points{{1.1, 0.2, 0.3}, {0.5, 0.8, 0.7}, {0.1, 0.1, 1.4}};
  expect_elasticity(s, points, 3, m, analysis::Formulation::kSolid, 1.0, 2.0);
  const Vector3d e = Vector3d(1, 2, 2) / 3;
  EXPECT_NEAR(e.dot(s.stress(1.0 * e) * e), -2.0, 1e-13);
  EXPECT_NEAR(e.dot(s.stress(1.5 * e) * e), 0.0, 1e-13);
}

TEST(AnalyticSolution, BadInputNamesTheField) {
  const auto m = material(1e5, 0.3);
  auto message = [&](const json& j, analysis::Formulation f) {
    try {
      make_analytic_solution(j, m, f, "case.json: analytic");
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(json{{"type", "kirch"}, {"traction", 1}, {"radius", 1}},
                    analysis::Formulation::kPlaneStress)
                .find("case.json: analytic.type: unknown analytic solution 'kirch'; did you mean "
                      "'kirsch'?"),
            0u);
  EXPECT_NE(message(json{{"type", "kirsch"}, {"traction", 1}}, analysis::Formulation::kPlaneStress)
                .find("analytic.radius is missing"),
            std::string::npos);
  EXPECT_NE(
      message(
          json{
              {"type", "hollow_sphere"}, {"inner_radius", 2}, {"outer_radius", 1}, {"pressure", 1}},
          analysis::Formulation::kSolid)
          .find("analytic.outer_radius must be larger"),
      std::string::npos);
  EXPECT_NE(message(json{{"type", "kirsch"}, {"traction", 1}, {"radius", 1}},
                    analysis::Formulation::kSolid)
                .find("2D solution"),
            std::string::npos);
  EXPECT_NE(message(json{{"type", "kirsch"}, {"traction", 1}, {"radius", 1}, {"radus", 1}},
                    analysis::Formulation::kPlaneStress)
                .find("analytic.radus: unknown field; did you mean 'radius'?"),
            std::string::npos);
}

}  // namespace
}  // namespace isospring::io
