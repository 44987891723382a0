// Mean-dilatation B-bar of the immersed assembly (derivation in immersed_bbar.hpp).
#include "immersed_bbar.hpp"

namespace isospring::analysis::detail {

Eigen::RowVectorXd cell_mean_divergence(const ImmersedContext& context, size_t cell) {
  const CellRule& rule = context.cell_rules[cell];
  const Element& e = context.cell_elements[cell];
  const int dim = context.basis.dim();
  const int count = context.basis.count();
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(count * dim);
  double volume = 0.0;
  BasisAt at;
  for (size_t q = 0; q < rule.points.size(); ++q) {
    context.basis.evaluate(e, rule.points[q], at);
    for (int a = 0; a < count; ++a)
      for (int c = 0; c < dim; ++c) row[a * dim + c] += rule.weights[q] * at.gradients(a, c);
    volume += rule.weights[q];
  }
  return row / volume;
}

void add_mean_dilatation(const ImmersedContext& context, const Eigen::MatrixXd& weighted_gradients,
                         double volume, Eigen::MatrixXd& local) {
  const int dim = context.basis.dim();
  const int count = context.basis.count();
  // b(a * dim + c) = int_K dN_a / dx_c (times the thickness): column c * count + a of WG summed.
  const Eigen::RowVectorXd column_sums = weighted_gradients.colwise().sum();
  Eigen::VectorXd b(count * dim);
  for (int a = 0; a < count; ++a)
    for (int c = 0; c < dim; ++c) b[a * dim + c] = column_sums[c * count + a];
  local.noalias() += (bbar_bulk_modulus(context.lame) / volume) * b * b.transpose();
}

Eigen::MatrixXd bbar_traction_operator(const ImmersedContext& context,
                                       const Eigen::Vector3d& normal,
                                       const Eigen::MatrixXd& gradients,
                                       const Eigen::RowVectorXd& mean_divergence) {
  const int dim = context.basis.dim();
  const Eigen::MatrixXd deviatoric = voigt_elasticity(bbar_deviatoric_lame(context.lame), dim);
  Eigen::MatrixXd T = normal_operator(normal, dim) * deviatoric * strain_operator(gradients, dim);
  T.noalias() += bbar_bulk_modulus(context.lame) * normal.head(dim) * mean_divergence;
  return T;
}

double bbar_strain_energy(const geometry::ImmersedDomain& domain, const ImmersedResult& result,
                          const ImmersedOptions& options) {
  const BackgroundBasis basis(domain, false);
  const LameParameters lame = lame_parameters(options.material, options.formulation);
  const double kappa = bbar_bulk_modulus(lame);
  const double thickness =
      options.formulation == Formulation::kSolid ? 1.0 : options.material.thickness;
  double energy = 0;
  BasisAt at;
  for (const auto& cell : domain.cells) {
    const Element e = element_of_cell(basis, cell.points);
    const CellRule rule = reduced_cell_rule(basis, e, cell.points, cell.weights);
    double volume = 0, divergence = 0, deviatoric = 0;
    for (size_t q = 0; q < rule.points.size(); ++q) {
      const Eigen::Matrix3d grad = value_on_element(basis, e, result, rule.points[q], at).gradient;
      const Eigen::Matrix3d strain = 0.5 * (grad + grad.transpose());
      const double trace = strain.trace();
      // |dev eps|^2 = eps : eps - tr(eps)^2 / 3 (the 3D deviator; eps_zz = 0 in plane strain).
      deviatoric += rule.weights[q] * (strain.squaredNorm() - trace * trace / 3.0);
      divergence += rule.weights[q] * trace;
      volume += rule.weights[q];
    }
    energy += thickness * (lame.mu * deviatoric + 0.5 * kappa * divergence * divergence / volume);
  }
  return energy;
}

}  // namespace isospring::analysis::detail
