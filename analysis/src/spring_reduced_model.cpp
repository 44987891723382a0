// Reduced (modal + load-dependent Ritz) model of a spring network, stepped in its subspace.
#include "isospring/analysis/spring_reduced_model.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "isospring/analysis/modal.hpp"
#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_linear_implicit.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

// Columns of v made M-orthonormal (m: the diagonal mass) by modified Gram-Schmidt, twice (one
// pass loses orthogonality when columns are nearly dependent: the static response of a load is
// close to the lowest modes). Columns whose remainder is below 1e-8 of their length are dropped:
// they add nothing to the span.
Eigen::MatrixXd m_orthonormal(const Eigen::MatrixXd& v, const Eigen::VectorXd& m) {
  Eigen::MatrixXd out(v.rows(), v.cols());
  Eigen::Index kept = 0;
  for (Eigen::Index c = 0; c < v.cols(); ++c) {
    Eigen::VectorXd x = v.col(c);
    const double length = std::sqrt(x.dot(m.cwiseProduct(x)));
    if (!(length > 0.0)) continue;
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index k = 0; k < kept; ++k) x -= out.col(k).dot(m.cwiseProduct(x)) * out.col(k);
    const double rest = std::sqrt(x.dot(m.cwiseProduct(x)));
    if (!(rest > 1e-8 * length)) continue;
    out.col(kept++) = x / rest;
  }
  return out.leftCols(kept);
}

void check_options(const SpringNetwork& network, double dt, const ReducedModelOptions& options,
                   int num_dofs, int num_free) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw nurbs::InputError("reduced spring model: time step " + std::to_string(dt) +
                            " is not a positive number");
  check_dynamics_input(network, rest_state(network));
  if (options.modes < 0 || options.modes > num_free - 1)
    throw nurbs::InputError("reduced spring model: modes = " + std::to_string(options.modes) +
                            " is not in 0 .. " + std::to_string(num_free - 1) +
                            " (the network has " + std::to_string(num_free) + " free DOFs)");
  if (options.modes == 0 && options.load_shapes.empty())
    throw nurbs::InputError(
        "reduced spring model: no basis vectors: ask for modes > 0 or give load shapes");
  for (size_t i = 0; i < options.load_shapes.size(); ++i) {
    const Eigen::VectorXd& f = options.load_shapes[i];
    if (f.size() != num_dofs)
      throw nurbs::InputError("reduced spring model: load shape " + std::to_string(i) + " has " +
                              std::to_string(f.size()) + " entries, the network " +
                              std::to_string(num_dofs) + " DOFs (particles x dimension)");
    if (!f.allFinite())
      throw nurbs::InputError("reduced spring model: load shape " + std::to_string(i) +
                              " has a NaN or infinite entry");
  }
}

}  // namespace

ReducedSpringModel::ReducedSpringModel(const SpringNetwork& network, double dt,
                                       const ReducedModelOptions& options)
    : dim_(network.dimension), dt_(dt) {
  const int num_dofs = static_cast<int>(network.positions.size()) * dim_;
  const FreeDofSet dofs(num_dofs, fixed_dofs(network));
  check_options(network, dt, options, num_dofs, dofs.num_free());
  const Eigen::SparseMatrix<double> k = dofs.restrict(rest_stiffness(network));
  const Eigen::VectorXd m = dofs.restrict(mass_diagonal(network));

  // Candidate vectors on the free DOFs: lowest modes, then static load responses.
  Eigen::MatrixXd v(dofs.num_free(), options.modes + static_cast<int>(options.load_shapes.size()));
  if (options.modes > 0) {
    Eigen::SparseMatrix<double> mass(m.size(), m.size());
    mass.reserve(Eigen::VectorXi::Constant(m.size(), 1));
    for (Eigen::Index d = 0; d < m.size(); ++d) mass.insert(d, d) = m[d];
    v.leftCols(options.modes) =
        lowest_generalized_modes(k, mass, options.modes, options.mode_tolerance).vectors;
  }
  if (!options.load_shapes.empty()) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> solver;
    solver.cholmod().print = 0;
    solver.compute(k);
    if (solver.info() != Eigen::Success)
      throw std::runtime_error(
          "reduced spring model: the rest stiffness is singular (fix particles so that the "
          "network cannot move as a rigid body) and load shapes need its static responses");
    for (size_t i = 0; i < options.load_shapes.size(); ++i)
      v.col(options.modes + static_cast<Eigen::Index>(i)) =
          solver.solve(dofs.restrict(options.load_shapes[i]));
  }

  // Rayleigh-Ritz: diagonalise K in the M-orthonormal span.
  const Eigen::MatrixXd w = m_orthonormal(v, m);
  const Eigen::MatrixXd k_reduced = w.transpose() * (k * w);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 *
                                                             (k_reduced + k_reduced.transpose()));
  if (eigen.info() != Eigen::Success)
    throw std::runtime_error("reduced spring model: the reduced eigenproblem failed");
  lambda_ = eigen.eigenvalues();
  const Eigen::MatrixXd phi = w * eigen.eigenvectors();
  basis_ = Eigen::MatrixXd::Zero(num_dofs, phi.cols());
  for (int f = 0; f < dofs.num_free(); ++f)
    basis_.row(dofs.free_dofs()[static_cast<size_t>(f)]) = phi.row(f);
  const Eigen::SparseMatrix<double> c = dofs.restrict(rest_damping(network));
  damping_ = phi.transpose() * (c * phi);
  damping_ = 0.5 * (damping_ + damping_.transpose());

  Eigen::MatrixXd a = dt_ * damping_;
  a.diagonal() += Eigen::VectorXd::Ones(size()) + dt_ * dt_ * lambda_;
  // A is symmetric positive definite (C_r >= 0, Lambda >= 0); r is small, so its inverse is
  // formed once and a step is two r x r products.
  const Eigen::LLT<Eigen::MatrixXd> llt(a);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error(
        "reduced spring model: I + dt C + dt^2 Lambda is not positive definite");
  step_inverse_ = llt.solve(Eigen::MatrixXd::Identity(size(), size()));
  reset();
}

Eigen::VectorXd ReducedSpringModel::reduce_force(const Eigen::VectorXd& force) const {
  if (force.size() != basis_.rows())
    throw nurbs::InputError("reduced spring model: a force of " + std::to_string(force.size()) +
                            " entries for " + std::to_string(basis_.rows()) + " DOFs");
  return basis_.transpose() * force;
}

Eigen::VectorXd ReducedSpringModel::reduce_particle_force(int particle,
                                                          const Eigen::Vector3d& force) const {
  if (particle < 0 || (particle + 1) * dim_ > basis_.rows())
    throw nurbs::InputError("reduced spring model: no particle " + std::to_string(particle));
  return basis_.middleRows(static_cast<Eigen::Index>(particle) * dim_, dim_).transpose() *
         force.head(dim_);
}

void ReducedSpringModel::step(const Eigen::VectorXd& reduced_force) {
  const Eigen::VectorXd lambda_q = lambda_.cwiseProduct(q_);
  const Eigen::VectorXd rhs =
      dt_ * (reduced_force - lambda_q - damping_ * qdot_ - dt_ * lambda_.cwiseProduct(qdot_));
  qdot_.noalias() += step_inverse_ * rhs;
  q_ += dt_ * qdot_;
}

void ReducedSpringModel::reset() {
  q_ = Eigen::VectorXd::Zero(size());
  qdot_ = Eigen::VectorXd::Zero(size());
}

Eigen::VectorXd ReducedSpringModel::displacement() const {
  return basis_ * q_;
}

Eigen::Vector3d ReducedSpringModel::particle_displacement(int particle) const {
  if (particle < 0 || (particle + 1) * dim_ > basis_.rows())
    throw nurbs::InputError("reduced spring model: no particle " + std::to_string(particle));
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  u.head(dim_) = basis_.middleRows(static_cast<Eigen::Index>(particle) * dim_, dim_) * q_;
  return u;
}

Eigen::VectorXd ReducedSpringModel::static_displacement(const Eigen::VectorXd& force) const {
  return basis_ * reduce_force(force).cwiseQuotient(lambda_);
}

ReductionError reduction_error(const SpringNetwork& network, ReducedSpringModel& model,
                               const Eigen::VectorXd& force, int steps) {
  ReductionError error;
  error.steps = steps;
  const Eigen::VectorXd full_static = solve_spring_linear(network, force).displacement;
  error.static_relative =
      (model.static_displacement(force) - full_static).norm() / full_static.norm();

  using Forces = LinearImplicitIntegrator::Forces;
  LinearImplicitIntegrator linear(network, model.dt(), Forces::kLinearised);
  LinearImplicitIntegrator exact(network, model.dt(), Forces::kExact);
  SpringState linear_state = rest_state(network), exact_state = linear_state;
  const Eigen::VectorXd rest = linear_state.x;
  const Eigen::VectorXd reduced_force = model.reduce_force(force);
  const int dim = model.dimension();
  model.reset();
  double projection_squared = 0.0, linear_squared = 0.0, largest_linear = 0.0;
  double exact_difference_squared = 0.0, exact_squared = 0.0;
  for (int s = 0; s < steps; ++s) {
    model.step(reduced_force);
    linear.step(linear_state, force);
    const Eigen::VectorXd u_reduced = model.displacement();
    const Eigen::VectorXd u_linear = linear_state.x - rest;
    projection_squared += (u_reduced - u_linear).squaredNorm();
    linear_squared += u_linear.squaredNorm();
    largest_linear = std::max(largest_linear, u_linear.cwiseAbs().maxCoeff());
    if (error.exact_diverged) continue;
    exact.step(exact_state, force);
    const Eigen::VectorXd u_exact = exact_state.x - rest;
    if (!u_exact.allFinite() || u_exact.cwiseAbs().maxCoeff() > 1e3 * largest_linear) {
      error.exact_diverged = true;
      continue;
    }
    const Eigen::VectorXd d = u_reduced - u_exact;
    exact_difference_squared += d.squaredNorm();
    exact_squared += u_exact.squaredNorm();
    for (Eigen::Index p = 0; p < d.size() / dim; ++p)
      error.dynamic_max = std::max(error.dynamic_max, d.segment(p * dim, dim).norm());
  }
  error.projection_relative =
      linear_squared > 0.0 ? std::sqrt(projection_squared / linear_squared) : 0.0;
  error.dynamic_relative =
      exact_squared > 0.0 ? std::sqrt(exact_difference_squared / exact_squared) : 0.0;
  if (error.exact_diverged) error.dynamic_relative = error.dynamic_max = std::nan("");
  model.reset();
  return error;
}

}  // namespace isospring::analysis
