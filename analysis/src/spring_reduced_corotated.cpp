// The reduced spring model stepped with corotated forces.
#include "isospring/analysis/spring_reduced_corotated.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

std::string scientific(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// The options with the modal-derivative forces appended to the load shapes.
ReducedModelOptions with_derivatives(const SpringNetwork& network, double dt,
                                     const CorotatedModelOptions& options) {
  if (options.derivative_modes < 0)
    throw nurbs::InputError("corotated reduced model: derivative_modes = " +
                            std::to_string(options.derivative_modes) + " must be >= 0");
  ReducedModelOptions out = options.reduced;
  if (options.derivative_modes == 0) return out;
  ReducedModelOptions lowest = options.reduced;
  lowest.modes = std::min(options.derivative_modes, options.reduced.modes);
  const ReducedSpringModel seed(network, dt, lowest);
  for (Eigen::VectorXd& f : modal_derivative_forces(network, seed.basis()))
    out.load_shapes.push_back(std::move(f));
  return out;
}

}  // namespace

std::vector<Eigen::VectorXd> modal_derivative_forces(const SpringNetwork& network,
                                                     const Eigen::MatrixXd& vectors) {
  const Eigen::VectorXd rest = flat_positions(network);
  const int dim = network.dimension;
  double spacing = 1e300;  // shortest spring: the scale of the difference step
  for (const Spring& s : network.springs) spacing = std::min(spacing, s.rest_length);
  if (!(spacing < 1e300)) spacing = 1.0;
  std::vector<Eigen::VectorXd> forces;
  for (Eigen::Index j = 0; j < vectors.cols(); ++j) {
    double largest = 0.0;
    for (Eigen::Index p = 0; p < vectors.rows() / dim; ++p)
      largest = std::max(largest, vectors.col(j).segment(p * dim, dim).norm());
    if (!(largest > 0.0)) continue;
    // A step moving no particle by more than 1e-4 of the shortest spring: central differences
    // are then accurate to ~1e-8 relative, far below what the span needs.
    const double h = 1e-4 * spacing / largest;
    const Eigen::SparseMatrix<double> dk = (tangent_stiffness(network, rest + h * vectors.col(j)) -
                                            tangent_stiffness(network, rest - h * vectors.col(j))) /
                                           (2.0 * h);
    for (Eigen::Index i = 0; i <= j; ++i) forces.push_back(-(dk * vectors.col(i)));
  }
  return forces;
}

CorotatedReducedModel::CorotatedReducedModel(const SpringNetwork& network, double dt,
                                             const CorotatedModelOptions& options)
    : linear_(network, dt, with_derivatives(network, dt, options)),
      corotation_(network),
      rest_(flat_positions(network)) {
  reset();
}

Eigen::VectorXd CorotatedReducedModel::elastic_force(const Eigen::VectorXd& q,
                                                     const Eigen::VectorXd& qdot) const {
  const Eigen::MatrixXd& phi = linear_.basis();
  x_ = rest_;
  x_.noalias() += phi * q;
  if (qdot.size() == q.size()) {
    v_.noalias() = phi * qdot;
  } else {
    v_.resize(0);
  }
  corotation_.rotations(x_, rotations_);
  corotation_.rotated_forces(rotations_, x_, v_, true, f_);
  return phi.transpose() * f_;
}

void CorotatedReducedModel::step(const Eigen::VectorXd& reduced_force) {
  const double dt = linear_.dt();
  const Eigen::VectorXd rhs = dt * (reduced_force + elastic_force(q_, qdot_) -
                                    dt * linear_.eigenvalues().cwiseProduct(qdot_));
  const Eigen::VectorXd q0 = q_, qdot0 = qdot_;
  qdot_.noalias() += linear_.step_inverse() * rhs;
  // Further chord iterations towards backward Euler, v1 = v0 + dt (g + g_el(q0 + dt v1, v1)),
  // with the same (rest) matrix.
  // At large rotation the chord iteration can diverge (its rate grows with the rotation): an
  // iterate whose residual grew is dropped for the one before.
  Eigen::VectorXd previous = qdot_;
  double previous_norm = std::numeric_limits<double>::infinity();
  for (int k = 1; k < iterations_; ++k) {
    const Eigen::VectorXd residual =
        qdot_ - qdot0 - dt * (reduced_force + elastic_force(q0 + dt * qdot_, qdot_));
    const double norm = residual.norm();
    if (!(norm <= previous_norm)) {
      if (k > 1) qdot_ = previous;
      break;
    }
    previous = qdot_;
    previous_norm = norm;
    qdot_.noalias() -= linear_.step_inverse() * residual;
  }
  q_ = q0 + dt * qdot_;
}

void CorotatedReducedModel::reset() {
  q_ = Eigen::VectorXd::Zero(size());
  qdot_ = Eigen::VectorXd::Zero(size());
}

Eigen::VectorXd CorotatedReducedModel::static_coordinates(const Eigen::VectorXd& reduced_force,
                                                          int load_steps, double tolerance) const {
  const int r = size();
  const Eigen::VectorXd none;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(r);
  const double scale = std::max(reduced_force.norm(), 1e-300);
  // The coordinates' natural size: the linear static response to the whole load.
  const double h =
      1e-6 * std::max(reduced_force.cwiseQuotient(linear_.eigenvalues()).norm(), 1e-12);
  for (int step = 1; step <= load_steps; ++step) {
    const Eigen::VectorXd g = (static_cast<double>(step) / load_steps) * reduced_force;
    Eigen::VectorXd residual = g + elastic_force(q, none);
    for (int iteration = 0; residual.norm() > tolerance * scale; ++iteration) {
      if (iteration == 50)
        throw std::runtime_error(
            "corotated reduced model: Newton did not reach the static state "
            "(relative residual " +
            scientific(residual.norm() / scale) + " at load step " + std::to_string(step) + ")");
      Eigen::MatrixXd jacobian(r, r);
      for (int k = 0; k < r; ++k) {
        Eigen::VectorXd plus = q, minus = q;
        plus[k] += h;
        minus[k] -= h;
        jacobian.col(k) = (elastic_force(plus, none) - elastic_force(minus, none)) / (2.0 * h);
      }
      const Eigen::VectorXd dq = jacobian.partialPivLu().solve(-residual);
      double alpha = 1.0;
      Eigen::VectorXd trial = g + elastic_force(q + dq, none);
      while (trial.norm() > residual.norm() && alpha > 1e-4) {
        alpha *= 0.5;
        trial = g + elastic_force(q + alpha * dq, none);
      }
      q += alpha * dq;
      residual = trial;
    }
  }
  return q;
}

}  // namespace isospring::analysis
