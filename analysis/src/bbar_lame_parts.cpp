// The Lame split of the B-bar stiffness (bbar_lame_parts.hpp).
#include "bbar_lame_parts.hpp"

#include "isospring/analysis/elasticity.hpp"
#include "volumetric_projection.hpp"

namespace isospring::analysis::detail {

namespace {

// G_w per weight: int w N_A N_B over every element, with the solve's quadrature (as the
// projection's own Gram in volumetric_projection).
std::vector<Eigen::SparseMatrix<double>> weighted_grams(const Problem& problem,
                                                        const AssemblyStructure& structure,
                                                        const VolumetricProjection& projection,
                                                        const std::vector<SpatialWeight>& weights) {
  const int dim = spatial_dimension(problem.formulation);
  const int rows = projection.offset.back();
  std::vector<std::vector<Eigen::Triplet<double>>> entries(weights.size());
  QuadraturePoint point;
  Eigen::MatrixXd gradients;
  std::vector<int> indices;
  Eigen::VectorXd values;
  Eigen::MatrixXd local;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const PatchQuadrature& quadrature = structure.quadratures[p];
    const PressureSpace& space = projection.spaces[p];
    const int m = space.local_count(), offset = projection.offset[p];
    indices.resize(static_cast<size_t>(m));
    values.resize(m);
    gradients.resize(quadrature.basis_count(), dim);
    for (int e = 0; e < quadrature.num_elements(); ++e) {
      const std::array<int, 3> position = quadrature.element_position(e);
      for (size_t k = 0; k < weights.size(); ++k) {
        local.setZero(m, m);
        for (int q = 0; q < quadrature.points_per_element(); ++q) {
          quadrature.evaluate(e, q, point);
          const double dv =
              point.weight * physical_gradients(point, dim, static_cast<int>(p), e, gradients);
          space.evaluate(position, point.param, indices.data(), values.data());
          const double w = weights[k] ? weights[k](point.point) : 1.0;
          local.noalias() += (w * dv) * values * values.transpose();
        }
        for (int a = 0; a < m; ++a)
          for (int b = 0; b < m; ++b)
            entries[k].emplace_back(offset + indices[static_cast<size_t>(a)],
                                    offset + indices[static_cast<size_t>(b)], local(a, b));
      }
    }
  }
  std::vector<Eigen::SparseMatrix<double>> grams(weights.size());
  for (size_t k = 0; k < weights.size(); ++k) {
    grams[k].resize(rows, rows);
    grams[k].setFromTriplets(entries[k].begin(), entries[k].end());
  }
  return grams;
}

}  // namespace

std::vector<Eigen::SparseMatrix<double>> bbar_weighted_volumetric(
    const Problem& problem, const DofMap& dofs, const AssemblyStructure& structure,
    const std::vector<SpatialWeight>& weights) {
  check_volumetric(problem);
  const VolumetricProjection projection =
      volumetric_projection(problem, structure.quadratures, dofs.num_dofs(),
                            [&](int patch, int cp, int i) { return dofs.dof(patch, cp, i); });
  const Eigen::SparseMatrix<double> c = projection.projection;
  const double thickness = thickness_factor(problem);
  std::vector<Eigen::SparseMatrix<double>> out;
  for (const Eigen::SparseMatrix<double>& gram :
       weighted_grams(problem, structure, projection, weights)) {
    const Eigen::SparseMatrix<double> gc = gram * c;
    out.push_back(thickness * Eigen::SparseMatrix<double>(c.transpose() * gc));
  }
  return out;
}

void make_bbar_lame_parts(const Eigen::SparseMatrix<double>& volumetric, LameStiffness& parts) {
  parts.mu_part = parts.mu_part - (2.0 / 3.0) * (parts.lambda_part - volumetric);
  parts.lambda_part = volumetric;
}

}  // namespace isospring::analysis::detail
