// The St. Venant-Kirchhoff element kernel (analysis/src/svk_element.hpp) on one distorted
// rational element in 2D and 3D, degree 2 and 3: its forces equal a straightforward per-point
// evaluation of the Total Lagrangian formulas and the gradient of the SVK energy, and its tangent
// equals the per-point formula term by term and the derivative of its own force.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "isospring/nurbs/patch.hpp"
#include "svk_element.hpp"

namespace isospring::analysis {
namespace {

// One element of degree p in `dim` directions: a unit square or cube whose (p + 1)^dim control
// points are moved by up to 8 % of their spacing and weighted in [0.7, 1.3] (rational basis).
nurbs::Patch distorted_element(int dim, int p, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.08 / p, 0.08 / p), weight(0.7, 1.3);
  std::vector<nurbs::KnotVector> knots(static_cast<size_t>(dim), nurbs::KnotVector::uniform(p, 1));
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  const int nz = dim == 3 ? p + 1 : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j <= p; ++j)
      for (int i = 0; i <= p; ++i) {
        Eigen::Vector3d x(double(i) / p + jitter(rng), 0.8 * j / p + jitter(rng), 0.0);
        if (dim == 3) x.z() = 0.6 * k / p + jitter(rng);
        points.push_back(x);
        weights.push_back(weight(rng));
      }
  return nurbs::Patch(knots, points, weights);
}

struct Element {
  int basis_count = 0;
  detail::ElementGradients gradients;
};

// Its gradients with the Gauss rule of the assembly (p + 1 points per direction).
Element make_element(int dim, int p) {
  const nurbs::Patch patch = distorted_element(dim, p, 17u + static_cast<unsigned>(10 * dim + p));
  const detail::PatchQuadrature quadrature = detail::PatchQuadrature::volume(patch, 0);
  Element out;
  out.basis_count = quadrature.basis_count();
  detail::QuadraturePoint point;
  detail::element_gradients(quadrature, 0, 0, dim, 1.0, point, out.gradients);
  return out;
}

// The formulas of nonlinear_elasticity.hpp evaluated point by point and entry by entry: the
// forces of unit lambda and mu, the tangent for `lame`, and the energy
// int lambda / 2 tr(E)^2 + mu E:E dV.
struct Reference {
  Eigen::VectorXd force_lambda, force_mu;
  Eigen::MatrixXd tangent;
  double energy = 0.0;
};

Reference reference(const detail::ElementGradients& element, const Eigen::MatrixXd& u,
                    const LameParameters& lame, bool with_tangent = true) {
  const int dim = static_cast<int>(u.cols());
  const int n = static_cast<int>(u.rows());
  Reference out;
  out.force_lambda.setZero(n * dim);
  out.force_mu.setZero(n * dim);
  out.tangent.setZero(n * dim, n * dim);
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(dim, dim);
  for (Eigen::Index q = 0; q < element.weights.size(); ++q) {
    const double w = element.weights[q];
    const Eigen::MatrixXd G = element.gradients.middleCols(q * dim, dim);  // n x dim
    const Eigen::MatrixXd F = identity + u.transpose() * G;
    const Eigen::MatrixXd E = 0.5 * (F.transpose() * F - identity);
    const Eigen::MatrixXd S = lame.lambda * E.trace() * identity + 2.0 * lame.mu * E;
    const Eigen::MatrixXd C = F * F.transpose();
    const Eigen::MatrixXd g = G * F.transpose();  // g_a = F G_a
    const Eigen::MatrixXd Pl = E.trace() * F, Pm = 2.0 * F * E;
    out.energy += w * (0.5 * lame.lambda * E.trace() * E.trace() + lame.mu * E.squaredNorm());
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i) {
        out.force_lambda[a * dim + i] += w * Pl.row(i).dot(G.row(a));
        out.force_mu[a * dim + i] += w * Pm.row(i).dot(G.row(a));
        if (!with_tangent) continue;
        for (int b = 0; b < n; ++b)
          for (int k = 0; k < dim; ++k) {
            double v = lame.lambda * g(a, i) * g(b, k) + lame.mu * g(b, i) * g(a, k) +
                       lame.mu * C(i, k) * G.row(a).dot(G.row(b));
            if (i == k) v += G.row(a) * S * G.row(b).transpose();
            out.tangent(a * dim + i, b * dim + k) += w * v;
          }
      }
  }
  return out;
}

struct Kernel {
  Eigen::VectorXd force_lambda, force_mu;
  Eigen::MatrixXd tangent;
  Eigen::VectorXd force(const LameParameters& lame) const {
    return lame.lambda * force_lambda + lame.mu * force_mu;
  }
};

Kernel kernel(const detail::ElementGradients& element, const Eigen::MatrixXd& u,
              const LameParameters& lame, bool with_tangent) {
  Kernel out;
  detail::SvkElementScratch scratch;
  Eigen::MatrixXd* tangent = with_tangent ? &out.tangent : nullptr;
  if (u.cols() == 2)
    detail::svk_element<2>(element, u, lame, out.force_lambda, out.force_mu, tangent, scratch);
  else
    detail::svk_element<3>(element, u, lame, out.force_lambda, out.force_mu, tangent, scratch);
  return out;
}

// Nodal displacements (row a = u_a) of size `scale` in each component: strains of tens of
// percent on these unit-size elements.
Eigen::MatrixXd random_displacements(int n, int dim, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::MatrixXd u(n, dim);
  for (Eigen::Index i = 0; i < u.size(); ++i) u.data()[i] = uniform(rng);
  return u;
}

// Flat DOF vector (a * dim + i) as the nodal matrix and back.
Eigen::MatrixXd nodal(const Eigen::VectorXd& x, int dim) {
  return Eigen::Map<const Eigen::MatrixXd>(x.data(), dim, x.size() / dim).transpose();
}
Eigen::VectorXd flat(const Eigen::MatrixXd& u) {
  const Eigen::MatrixXd t = u.transpose();
  return Eigen::Map<const Eigen::VectorXd>(t.data(), t.size());
}

class SvkElementTest : public ::testing::TestWithParam<std::pair<int, int>> {};

const LameParameters kLame{1.7, 0.9};

// Same formulas, other summation order: equal to round-off (products of O(1) numbers summed over
// up to 64 points and 3 components).
TEST_P(SvkElementTest, EqualsThePerPointFormulas) {
  const auto [dim, p] = GetParam();
  const Element element = make_element(dim, p);
  const int n = element.basis_count;
  for (unsigned seed : {1u, 2u}) {
    const Eigen::MatrixXd u = random_displacements(n, dim, 0.1, seed);
    const Reference expected = reference(element.gradients, u, kLame);
    const Kernel got = kernel(element.gradients, u, kLame, true);
    EXPECT_LT((got.force_lambda - expected.force_lambda).norm(),
              1e-12 * expected.force_lambda.norm());
    EXPECT_LT((got.force_mu - expected.force_mu).norm(), 1e-12 * expected.force_mu.norm());
    EXPECT_LT((got.tangent - expected.tangent).norm(), 1e-12 * expected.tangent.norm());
    // The tangent is symmetric (both triangles filled) and the force-only path gives the same
    // forces bit for bit.
    EXPECT_EQ((got.tangent - got.tangent.transpose()).norm(), 0.0);
    const Kernel forces = kernel(element.gradients, u, kLame, false);
    EXPECT_EQ(forces.force_lambda, got.force_lambda);
    EXPECT_EQ(forces.force_mu, got.force_mu);
  }
}

// The SVK energy is a quartic polynomial in u and the force a cubic, so the central difference
// D(h) = f' + h^2/6 f''' (+ h^4/120 f^(5) = 0 for the energy) is exact after one Richardson
// step, (4 D(h/2) - D(h)) / 3: what remains is round-off, ~1e-16 |W| / h ~ 1e-12 relative for
// h = 1e-4.
TEST_P(SvkElementTest, ForceIsTheEnergyGradientAndTangentItsDerivative) {
  const auto [dim, p] = GetParam();
  const Element element = make_element(dim, p);
  const int n = element.basis_count;
  const Eigen::VectorXd u = flat(random_displacements(n, dim, 0.1, 5u));
  const Kernel at = kernel(element.gradients, nodal(u, dim), kLame, true);
  const Eigen::VectorXd force = at.force(kLame);
  auto energy = [&](const Eigen::VectorXd& x) {
    return reference(element.gradients, nodal(x, dim), kLame, false).energy;
  };
  auto force_at = [&](const Eigen::VectorXd& x) {
    return kernel(element.gradients, nodal(x, dim), kLame, false).force(kLame);
  };
  const double h = 1e-4;
  Eigen::VectorXd gradient(u.size());
  Eigen::MatrixXd derivative(u.size(), u.size());
  for (Eigen::Index d = 0; d < u.size(); ++d) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(u.size(), d);
    auto energy_difference = [&](double s) {
      return (energy(u + s * e) - energy(u - s * e)) / (2.0 * s);
    };
    auto force_difference = [&](double s) -> Eigen::VectorXd {
      return (force_at(u + s * e) - force_at(u - s * e)) / (2.0 * s);
    };
    gradient[d] = (4.0 * energy_difference(0.5 * h) - energy_difference(h)) / 3.0;
    derivative.col(d) = (4.0 * force_difference(0.5 * h) - force_difference(h)) / 3.0;
  }
  EXPECT_LT((gradient - force).norm(), 1e-7 * force.norm());
  EXPECT_LT((derivative - at.tangent).norm(), 1e-7 * at.tangent.norm());
}

// At u = 0 the tangent is the linear stiffness: B^T D B with the strain-displacement matrix.
TEST_P(SvkElementTest, TangentAtRestIsTheLinearStiffness) {
  const auto [dim, p] = GetParam();
  const Element element = make_element(dim, p);
  const int n = element.basis_count;
  const Kernel at = kernel(element.gradients, Eigen::MatrixXd::Zero(n, dim), kLame, true);
  EXPECT_EQ(at.force(kLame).norm(), 0.0);
  Eigen::MatrixXd linear = Eigen::MatrixXd::Zero(n * dim, n * dim);
  for (Eigen::Index q = 0; q < element.gradients.weights.size(); ++q) {
    const Eigen::MatrixXd G = element.gradients.gradients.middleCols(q * dim, dim);
    // sigma_ij = lambda div u delta_ij + mu (u_i,j + u_j,i): K = int lambda G_a,i G_b,k +
    // mu (G_a,k G_b,i + delta_ik G_a . G_b).
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        for (int i = 0; i < dim; ++i)
          for (int k = 0; k < dim; ++k)
            linear(a * dim + i, b * dim + k) +=
                element.gradients.weights[q] *
                (kLame.lambda * G(a, i) * G(b, k) + kLame.mu * G(a, k) * G(b, i) +
                 (i == k ? kLame.mu * G.row(a).dot(G.row(b)) : 0.0));
  }
  EXPECT_LT((at.tangent - linear).norm(), 1e-13 * linear.norm());
}

INSTANTIATE_TEST_SUITE_P(DimensionAndDegree, SvkElementTest,
                         ::testing::Values(std::pair{2, 2}, std::pair{2, 3}, std::pair{3, 2},
                                           std::pair{3, 3}),
                         [](const auto& info) {
                           return std::to_string(info.param.first) + "D_degree" +
                                  std::to_string(info.param.second);
                         });

}  // namespace
}  // namespace isospring::analysis
