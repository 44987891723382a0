// Strain-point terms (spring_strain_point.hpp): forces and tangent against finite differences,
// no energy or force under large rigid motions, and the identity that makes them worth having:
// at the analysis' Gauss points with the material's moduli their rest stiffness is the IGA
// stiffness matrix (2D and 3D, curved NURBS patches).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "analysis_models.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_strain_point.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::analysis {
namespace {

Problem curved(int dim) {
  Problem problem;
  problem.formulation = dim == 2 ? Formulation::kPlaneStrain : Formulation::kSolid;
  problem.material = {200.0, 0.3, 1.0, 1.0};
  problem.patches.push_back(dim == 2 ? nurbs::refine_uniform(testing::kirsch_plate(), 1, 2)
                                     : testing::sphere_octant(1.0, 1.5));
  return problem;
}

// One particle per DOF-map node (no springs), a volume and a shear term per site with moduli
// kappa and mu (per site when `jitter` > 0: moduli scaled by 1 +- jitter).
SpringNetwork point_network(const Problem& problem, const DofMap& dofs, int points, double kappa,
                            double mu, double jitter = 0.0) {
  const int dim = problem.formulation == Formulation::kSolid ? 3 : 2;
  SpringNetwork net;
  net.dimension = dim;
  net.positions = dofs.node_positions();
  net.masses.assign(net.positions.size(), 1.0);
  net.fixed.assign(net.positions.size(), false);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> scale(1.0 - jitter, 1.0 + jitter);
  for (const auto& site : strain_point_sites(problem.patches[0], points)) {
    VolumeTerm term;
    term.rest_volume = site.volume;
    for (size_t a = 0; a < site.control_points.size(); ++a) {
      term.points.push_back(dofs.node(0, site.control_points[a]));
      term.gradients.push_back(site.gradients[a]);
    }
    term.kind = CellEnergy::kVolume;
    term.modulus = kappa * scale(rng);
    net.volumes.push_back(term);
    term.kind = CellEnergy::kShear;
    term.modulus = mu * scale(rng);
    net.volumes.push_back(term);
  }
  return net;
}

TEST(SpringStrainPoint, GaussPointsReproduceTheIgaStiffness) {
  for (int dim : {2, 3}) {
    const Problem problem = curved(dim);
    const DofMap dofs(problem);
    const LameParameters lame = lame_parameters(problem.material, problem.formulation);
    // mu |dev eps|^2 + kappa/2 (tr eps)^2 = mu eps:eps + lambda/2 (tr eps)^2 for
    // kappa = lambda + 2 mu / d.
    const SpringNetwork net =
        point_network(problem, dofs, 0, lame.lambda + 2.0 * lame.mu / dim, lame.mu);
    const Eigen::MatrixXd spring = Eigen::MatrixXd(rest_stiffness(net));
    const Eigen::SparseMatrix<double> upper = assemble_stiffness(problem, dofs);
    const Eigen::MatrixXd iga =
        Eigen::MatrixXd(Eigen::SparseMatrix<double>(upper.selfadjointView<Eigen::Upper>()));
    ASSERT_EQ(spring.rows(), iga.rows());
    EXPECT_LT((spring - iga).norm(), 1e-10 * iga.norm()) << "dim " << dim;
  }
}

TEST(SpringStrainPoint, ForcesAndTangentMatchFiniteDifferencesOfTheEnergy) {
  for (int dim : {2, 3}) {
    const Problem problem = curved(dim);
    const DofMap dofs(problem);
    const SpringNetwork net = point_network(problem, dofs, 1, 300.0, 70.0, 0.5);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> move(-0.1, 0.1);
    Eigen::VectorXd x = flat_positions(net);
    for (Eigen::Index e = 0; e < x.size(); ++e) x[e] += move(rng);
    ASSERT_GT(spring_energy(net, x), 1e-2);
    const Eigen::VectorXd f = spring_forces(net, x);
    const Eigen::MatrixXd k = Eigen::MatrixXd(tangent_stiffness(net, x));
    const double h = 1e-6;
    for (Eigen::Index e = 0; e < x.size(); ++e) {
      Eigen::VectorXd plus = x, minus = x;
      plus[e] += h;
      minus[e] -= h;
      const double df = -(spring_energy(net, plus) - spring_energy(net, minus)) / (2 * h);
      EXPECT_NEAR(f[e], df, 1e-6 * (1.0 + f.cwiseAbs().maxCoeff())) << "dim " << dim;
      const Eigen::VectorXd dk = -(spring_forces(net, plus) - spring_forces(net, minus)) / (2 * h);
      EXPECT_LT((k.col(e) - dk).norm(), 1e-7 * (1.0 + k.norm())) << "dim " << dim << " dof " << e;
    }
    // At rest the exact tangent is the linearised stiffness the fits use.
    const Eigen::VectorXd rest = flat_positions(net);
    EXPECT_LT((Eigen::MatrixXd(tangent_stiffness(net, rest)) - Eigen::MatrixXd(rest_stiffness(net)))
                  .norm(),
              1e-10 * Eigen::MatrixXd(rest_stiffness(net)).norm());
  }
}

TEST(SpringStrainPoint, LargeRigidMotionsCarryNoEnergyOrForce) {
  for (int dim : {2, 3}) {
    const Problem problem = curved(dim);
    const DofMap dofs(problem);
    const SpringNetwork net = point_network(problem, dofs, 2, 300.0, 70.0, 0.5);
    const Eigen::Matrix3d rotation =
        dim == 2
            ? Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix()
            : Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
    Eigen::VectorXd x = flat_positions(net);
    for (size_t q = 0; q < net.positions.size(); ++q) {
      const Eigen::Vector3d moved = rotation * net.positions[q] + Eigen::Vector3d(0.3, -2, 1);
      x.segment(static_cast<Eigen::Index>(q) * dim, dim) = moved.head(dim);
    }
    EXPECT_LT(spring_energy(net, x), 1e-20) << "dim " << dim;
    EXPECT_LT(spring_forces(net, x).norm(), 1e-11) << "dim " << dim;
    // A small strain does store energy: the terms are not empty.
    x *= 1.01;
    EXPECT_GT(spring_energy(net, x), 1e-4) << "dim " << dim;
  }
}

}  // namespace
}  // namespace isospring::analysis
