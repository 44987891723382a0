// Frobenius matrix approach: normal equations built from closed-form inner products.
//
// With S_s = g_s g_s^T (blocks N_s = n_s n_s^T on (i,i), (j,j) and -N_s on (i,j), (j,i)):
//   <S_s, S_s>_F = 4, <S_s, S_t>_F = (n_s . n_t)^2 when s, t share one particle, else 0;
//   <K, S_s>_F = g_s^T K g_s.
// So the normal matrix is sparse (springs meeting at a particle) and never needs K vectorised.
#include "isospring/fitting/matrix_approach.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

using Clock = std::chrono::steady_clock;

Eigen::Vector3d rest_direction(const analysis::SpringNetwork& net, const analysis::Spring& s) {
  Eigen::Vector3d l = net.positions[s.j] - net.positions[s.i];
  if (net.dimension == 2) l.z() = 0.0;
  return l.normalized();
}

// The IGA stiffness (full, symmetric) in particle DOFs: nodes sharing a particle add up.
Eigen::SparseMatrix<double> reference_stiffness(const analysis::Problem& problem,
                                                const SpringMesh& mesh) {
  const analysis::DofMap dofs(problem);
  const Eigen::SparseMatrix<double> node_k =
      analysis::assemble_stiffness(problem, dofs).selfadjointView<Eigen::Upper>();
  const std::vector<int> particle = particle_of_node(problem, mesh);
  const int dim = dofs.dofs_per_node();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(node_k.nonZeros()));
  for (int col = 0; col < node_k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(node_k, col); it; ++it) {
      const auto row = static_cast<int>(it.row());
      entries.emplace_back(particle[row / dim] * dim + row % dim,
                           particle[col / dim] * dim + col % dim, it.value());
    }
  const auto n = static_cast<Eigen::Index>(mesh.network.positions.size()) * dim;
  Eigen::SparseMatrix<double> k(n, n);
  k.setFromTriplets(entries.begin(), entries.end());
  return k;
}

// g_s^T K g_s for every spring.
Eigen::VectorXd spring_projections(const analysis::SpringNetwork& net,
                                   const Eigen::SparseMatrix<double>& k) {
  const int dim = net.dimension;
  Eigen::VectorXd b(static_cast<Eigen::Index>(net.springs.size()));
  for (size_t s = 0; s < net.springs.size(); ++s) {
    const auto& spring = net.springs[s];
    const Eigen::Vector3d n = rest_direction(net, spring);
    double value = 0.0;
    for (int a = 0; a < dim; ++a)
      for (int c = 0; c < dim; ++c) {
        const int ia = spring.i * dim + a, ja = spring.j * dim + a;
        const int ic = spring.i * dim + c, jc = spring.j * dim + c;
        value +=
            n[a] * n[c] * (k.coeff(ia, ic) + k.coeff(ja, jc) - k.coeff(ia, jc) - k.coeff(ja, ic));
      }
    b[static_cast<Eigen::Index>(s)] = value;
  }
  return b;
}

// The sparse spring-by-spring normal matrix <S_s, S_t>_F.
Eigen::SparseMatrix<double> spring_gram(const analysis::SpringNetwork& net) {
  std::vector<std::vector<int>> incident(net.positions.size());
  for (size_t s = 0; s < net.springs.size(); ++s) {
    incident[net.springs[s].i].push_back(static_cast<int>(s));
    incident[net.springs[s].j].push_back(static_cast<int>(s));
  }
  std::vector<Eigen::Vector3d> n(net.springs.size());
  for (size_t s = 0; s < net.springs.size(); ++s) n[s] = rest_direction(net, net.springs[s]);
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t s = 0; s < net.springs.size(); ++s) entries.emplace_back(s, s, 4.0);
  for (const auto& springs : incident)
    for (int s : springs)
      for (int t : springs)
        if (s != t) entries.emplace_back(s, t, std::pow(n[s].dot(n[t]), 2));
  const auto count = static_cast<Eigen::Index>(net.springs.size());
  Eigen::SparseMatrix<double> gram(count, count);
  gram.setFromTriplets(entries.begin(), entries.end());
  return gram;
}

Eigen::VectorXd solve_spd(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& b) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(a);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("matrix approach: the normal equations are singular");
  return solver.solve(b);
}

double frobenius_residual(const Eigen::SparseMatrix<double>& k_ref, const SpringMesh& mesh,
                          const std::vector<double>& stiffness) {
  analysis::SpringNetwork net = mesh.network;
  for (size_t s = 0; s < net.springs.size(); ++s) net.springs[s].stiffness = stiffness[s];
  const Eigen::SparseMatrix<double> difference = k_ref - analysis::rest_stiffness(net);
  return difference.norm() / k_ref.norm();
}

void count_negative(MatrixFitResult& result) {
  for (double k : result.spring_stiffness) result.negative_springs += k < 0.0;
}

}  // namespace

MatrixFitResult fit_stiffness_matrix(const analysis::Problem& problem, const SpringMesh& mesh,
                                     const Grouping& grouping) {
  const auto start = Clock::now();
  const analysis::SpringNetwork& net = mesh.network;
  if (grouping.group_of_spring.size() != net.springs.size())
    throw nurbs::InputError("matrix approach: the grouping does not cover every spring");
  const Eigen::SparseMatrix<double> k_ref = reference_stiffness(problem, mesh);
  // Spring -> group incidence P: the grouped normal equations are P^T A P k = P^T b.
  std::vector<Eigen::Triplet<double>> incidence;
  for (size_t s = 0; s < net.springs.size(); ++s)
    incidence.emplace_back(s, grouping.group_of_spring[s], 1.0);
  Eigen::SparseMatrix<double> p(static_cast<Eigen::Index>(net.springs.size()),
                                grouping.num_groups());
  p.setFromTriplets(incidence.begin(), incidence.end());
  const Eigen::SparseMatrix<double> a = p.transpose() * spring_gram(net) * p;
  const Eigen::VectorXd k = solve_spd(a, p.transpose() * spring_projections(net, k_ref));

  MatrixFitResult result;
  result.group_stiffness.assign(k.data(), k.data() + k.size());
  for (int g : grouping.group_of_spring) result.spring_stiffness.push_back(k[g]);
  result.relative_residual = frobenius_residual(k_ref, mesh, result.spring_stiffness);
  count_negative(result);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

MatrixFitResult fit_stiffness_matrix_per_element(const analysis::Problem& problem,
                                                 const SpringMesh& mesh) {
  const auto start = Clock::now();
  const analysis::SpringNetwork& net = mesh.network;
  std::map<std::pair<int, int>, int> spring_of_pair;
  for (size_t s = 0; s < net.springs.size(); ++s)
    spring_of_pair[{std::min(net.springs[s].i, net.springs[s].j),
                    std::max(net.springs[s].i, net.springs[s].j)}] = static_cast<int>(s);

  MatrixFitResult result;
  result.spring_stiffness.assign(net.springs.size(), 0.0);
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const nurbs::Patch& patch = problem.patches[p];
    const int dims = patch.param_dim();
    for (int d = 0; d < dims; ++d)
      if (patch.degree(d) != 1)
        throw nurbs::InputError(
            "matrix approach per element: patch " + std::to_string(p) +
            " is not of degree 1; the element-by-element fit needs net cells that are elements "
            "(use the global fit for higher degrees)");
    const int n0 = patch.num_points(0), n1 = patch.num_points(1);
    const int n2 = dims == 3 ? patch.num_points(2) : 2;
    for (int k = 0; k + 1 < n2; ++k)
      for (int j = 0; j + 1 < n1; ++j)
        for (int i = 0; i + 1 < n0; ++i) {
          // The cell as a one-element patch: its element matrix is the bilinear/trilinear FE one.
          std::vector<int> corners;
          std::vector<Eigen::Vector3d> points;
          std::vector<double> weights;
          for (int c = 0; c < (dims == 3 ? 8 : 4); ++c) {
            const int index = dims == 3 ? patch.index(i + c % 2, j + (c / 2) % 2, k + c / 4)
                                        : patch.index(i + c % 2, j + c / 2, 0);
            corners.push_back(index);
            points.push_back(patch.control_points()[index]);
            weights.push_back(patch.weights()[index]);
          }
          analysis::Problem cell;
          cell.formulation = problem.formulation;
          cell.material = problem.material;
          cell.quadrature_points = problem.quadrature_points;
          cell.patches.emplace_back(
              std::vector<nurbs::KnotVector>(static_cast<size_t>(dims),
                                             nurbs::KnotVector::uniform(1, 1)),
              points, weights);
          const SpringMesh cell_mesh = build_spring_mesh(cell);
          const MatrixFitResult local =
              fit_stiffness_matrix(cell, cell_mesh, one_group_per_spring(cell_mesh.network));
          std::vector<int> corner_of_particle(cell_mesh.network.positions.size());
          for (size_t c = 0; c < corners.size(); ++c)
            corner_of_particle[cell_mesh.particle[0][c]] = static_cast<int>(c);
          for (size_t s = 0; s < cell_mesh.network.springs.size(); ++s) {
            const auto& spring = cell_mesh.network.springs[s];
            const int a = mesh.particle[p][corners[corner_of_particle[spring.i]]],
                      b = mesh.particle[p][corners[corner_of_particle[spring.j]]];
            const auto it = spring_of_pair.find({std::min(a, b), std::max(a, b)});
            if (it != spring_of_pair.end())
              result.spring_stiffness[it->second] += local.spring_stiffness[s];
          }
        }
  }
  result.relative_residual =
      frobenius_residual(reference_stiffness(problem, mesh), mesh, result.spring_stiffness);
  count_negative(result);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

double relative_matrix_residual(const analysis::Problem& problem, const SpringMesh& mesh,
                                const std::vector<double>& spring_stiffness) {
  return frobenius_residual(reference_stiffness(problem, mesh), mesh, spring_stiffness);
}

}  // namespace isospring::fitting
