// Field evaluation and error norms.
#include "isospring/analysis/post_processing.hpp"

#include <cmath>
#include <memory>

#include "assembly_structure.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/nurbs/error.hpp"
#include "volumetric_projection.hpp"

namespace isospring::analysis {

namespace {

// Displacement and its gradient du_i/dx_j at a quadrature point of a patch.
void displacement_and_gradient(const std::vector<Eigen::Vector3d>& u, const int* cps,
                               const Eigen::VectorXd& values, const Eigen::MatrixXd& gradients,
                               int dim, Eigen::Vector3d& displacement, Eigen::Matrix3d& grad) {
  displacement.setZero();
  grad.setZero();
  for (Eigen::Index a = 0; a < values.size(); ++a) {
    const Eigen::Vector3d& ua = u[static_cast<size_t>(cps[a])];
    displacement += values[a] * ua;
    for (int j = 0; j < dim; ++j) grad.col(j) += gradients(a, j) * ua;
  }
  if (dim == 2) {
    displacement.z() = 0.0;
    grad.row(2).setZero();
  }
}

Eigen::Matrix3d strain_of(const Eigen::Matrix3d& grad, const Problem& problem) {
  Eigen::Matrix3d strain = 0.5 * (grad + grad.transpose());
  if (problem.formulation == Formulation::kPlaneStress) {
    const double nu = problem.material.poisson_ratio;
    strain(2, 2) = -nu / (1.0 - nu) * (strain(0, 0) + strain(1, 1));
  }
  return strain;
}

double squared_norm(const Eigen::Vector3d& v, int dim) {
  double sum = 0.0;
  for (int c = 0; c < dim; ++c) sum += v[c] * v[c];
  return sum;
}

// s : C^-1 s with only the independent stress components of the formulation (in-plane in 2D).
double energy_product(Eigen::Matrix3d stress, const Problem& problem) {
  if (problem.formulation != Formulation::kSolid) {
    stress.row(2).setZero();
    stress.col(2).setZero();
  }
  return stress.cwiseProduct(strain_from_stress(stress, problem.material, problem.formulation))
      .sum();
}

void check_sizes(const Problem& problem, const ControlDisplacements& displacements) {
  bool ok = displacements.size() == problem.patches.size();
  for (size_t p = 0; ok && p < displacements.size(); ++p)
    ok = static_cast<int>(displacements[p].size()) == problem.patches[p].num_points();
  if (!ok)
    throw nurbs::InputError(
        "control displacements do not match the problem's patches (one "
        "vector per control point of every patch is needed)");
}

// f(point, displacement, grad u, dV, patch, parameter) at every point of a rule with `points`
// per direction (0: `extra` beyond degree + 1).
template <class F>
void integrate(const Problem& problem, const ControlDisplacements& displacements, int points,
               int extra, F&& f) {
  check_sizes(problem, displacements);
  const int dim = spatial_dimension(problem.formulation);
  const double thickness = thickness_factor(problem);
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const auto& patch = problem.patches[p];
    std::array<detail::DirectionRule, 3> rules;
    for (int d = 0; d < patch.param_dim(); ++d)
      rules[static_cast<size_t>(d)] =
          detail::gauss_rule(patch.knots(d), points > 0 ? points : patch.degree(d) + 1 + extra);
    const detail::PatchQuadrature quadrature(patch, std::move(rules));
    std::vector<int> cps(static_cast<size_t>(quadrature.basis_count()));
    detail::QuadraturePoint point;
    Eigen::MatrixXd gradients(quadrature.basis_count(), dim);
    Eigen::Vector3d u;
    Eigen::Matrix3d grad;
    for (int e = 0; e < quadrature.num_elements(); ++e) {
      quadrature.element_control_points(e, cps.data());
      for (int q = 0; q < quadrature.points_per_element(); ++q) {
        quadrature.evaluate(e, q, point);
        const double det =
            detail::physical_gradients(point, dim, static_cast<int>(p), e, gradients);
        displacement_and_gradient(displacements[p], cps.data(), point.values, gradients, dim, u,
                                  grad);
        f(point.point, u, grad, point.weight * det * thickness, static_cast<int>(p), point.param);
      }
    }
  }
}

}  // namespace

struct FieldEvaluator::Projection {
  detail::ProjectedDilatation dilatation;
};

FieldEvaluator::FieldEvaluator(const Problem& problem, const ControlDisplacements& displacements)
    : problem_(&problem), displacements_(&displacements) {
  check_sizes(problem, displacements);
  if (problem.volumetric == Volumetric::kBbar)
    projection_ = std::make_unique<const Projection>(
        Projection{detail::ProjectedDilatation(problem, displacements)});
}
FieldEvaluator::~FieldEvaluator() = default;
FieldEvaluator::FieldEvaluator(FieldEvaluator&&) noexcept = default;

FieldPoint FieldEvaluator::operator()(int patch_index, const nurbs::Param& u) const {
  const Problem& problem = *problem_;
  const auto& patch = problem.patches.at(static_cast<size_t>(patch_index));
  const int dim = spatial_dimension(problem.formulation);
  const nurbs::RationalBasis basis = patch.basis(u, 1);
  detail::QuadraturePoint point;
  point.param = u;
  point.values = basis.values;
  point.derivatives = basis.first;
  point.point.setZero();
  point.jacobian.setZero();
  for (size_t a = 0; a < basis.indices.size(); ++a) {
    const Eigen::Vector3d& x = patch.control_point(basis.indices[a]);
    point.point += basis.values[static_cast<Eigen::Index>(a)] * x;
    for (int c = 0; c < patch.param_dim(); ++c)
      point.jacobian.col(c) += basis.first(static_cast<Eigen::Index>(a), c) * x;
  }
  Eigen::MatrixXd gradients(basis.values.size(), dim);
  detail::physical_gradients(point, dim, patch_index, -1, gradients);
  FieldPoint field;
  field.point = point.point;
  Eigen::Matrix3d grad;
  displacement_and_gradient((*displacements_)[static_cast<size_t>(patch_index)],
                            basis.indices.data(), basis.values, gradients, dim, field.displacement,
                            grad);
  field.strain = strain_of(grad, problem);
  if (projection_) {
    const double dilatation = projection_->dilatation.at(patch_index, u);
    field.stress = detail::bbar_stress(field.strain, dilatation, problem);
    field.strain = detail::bbar_strain(field.strain, dilatation, problem);
  } else {
    field.stress = stress_from_strain(field.strain, problem.material, problem.formulation);
  }
  field.von_mises = von_mises(field.stress);
  return field;
}

FieldPoint evaluate_field(const Problem& problem, const ControlDisplacements& displacements,
                          int patch_index, const nurbs::Param& u) {
  return FieldEvaluator(problem, displacements)(patch_index, u);
}

ErrorNorms error_norms(const Problem& problem, const ControlDisplacements& displacements,
                       const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& exact_u,
                       const std::function<Eigen::Matrix3d(const Eigen::Vector3d&)>& exact_stress,
                       int quadrature_points) {
  const int dim = spatial_dimension(problem.formulation);
  check_sizes(problem, displacements);
  const std::unique_ptr<detail::ProjectedDilatation> projected =
      problem.volumetric == Volumetric::kBbar
          ? std::make_unique<detail::ProjectedDilatation>(problem, displacements)
          : nullptr;
  ErrorNorms norms;
  integrate(problem, displacements, quadrature_points, 2,
            [&](const Eigen::Vector3d& x, const Eigen::Vector3d& u, const Eigen::Matrix3d& grad,
                double dv, int patch, const nurbs::Param& param) {
              const Eigen::Vector3d ue = exact_u(x);
              norms.l2_error += squared_norm(ue - u, dim) * dv;
              norms.l2_norm += squared_norm(ue, dim) * dv;
              const Eigen::Matrix3d se = exact_stress(x);
              const Eigen::Matrix3d strain = strain_of(grad, problem);
              const Eigen::Matrix3d sh =
                  projected ? detail::bbar_stress(strain, projected->at(patch, param), problem)
                            : stress_from_strain(strain, problem.material, problem.formulation);
              norms.energy_error += energy_product(se - sh, problem) * dv;
              norms.energy_norm += energy_product(se, problem) * dv;
            });
  norms.l2_error = std::sqrt(norms.l2_error);
  norms.l2_norm = std::sqrt(norms.l2_norm);
  norms.energy_error = std::sqrt(std::max(0.0, norms.energy_error));
  norms.energy_norm = std::sqrt(std::max(0.0, norms.energy_norm));
  return norms;
}

double strain_energy(const Problem& problem, const ControlDisplacements& displacements) {
  check_sizes(problem, displacements);
  const std::unique_ptr<detail::ProjectedDilatation> projected =
      problem.volumetric == Volumetric::kBbar
          ? std::make_unique<detail::ProjectedDilatation>(problem, displacements)
          : nullptr;
  double energy = 0.0;
  integrate(
      problem, displacements, problem.quadrature_points, 0,
      [&](const Eigen::Vector3d&, const Eigen::Vector3d&, const Eigen::Matrix3d& grad, double dv,
          int patch, const nurbs::Param& param) {
        const Eigen::Matrix3d e = strain_of(grad, problem);
        if (projected) {
          energy += detail::bbar_energy_density(e, projected->at(patch, param), problem) * dv;
          return;
        }
        energy +=
            0.5 *
            stress_from_strain(e, problem.material, problem.formulation).cwiseProduct(e).sum() * dv;
      });
  return energy;
}

}  // namespace isospring::analysis
