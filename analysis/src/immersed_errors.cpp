// Error norms of an immersed solution (see immersed_errors.hpp).
#include "isospring/analysis/immersed_errors.hpp"

#include <cmath>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::analysis {
namespace {

using Vector3d = Eigen::Vector3d;
using Matrix3d = Eigen::Matrix3d;

/// The tensor Gauss rule of `n` points per direction on an inside cell (its knot span).
void inside_rule(const geometry::ImmersedDomain& domain, const geometry::ImmersedCell& cell,
                 const nurbs::GaussRule& rule, std::vector<Vector3d>& points,
                 std::vector<double>& weights) {
  points.clear();
  weights.clear();
  const int dim = domain.dimension;
  Vector3d lo = Vector3d::Zero(), size = Vector3d::Zero();
  for (int d = 0; d < dim; ++d) {
    const nurbs::KnotVector& knots = domain.background.knots(d);
    lo[d] = domain.origin[d] + domain.extent[d] * knots[cell.span[d]];
    size[d] = domain.extent[d] * (knots[cell.span[d] + 1] - knots[cell.span[d]]);
  }
  const int n = static_cast<int>(rule.points.size());
  const int nz = dim == 3 ? n : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int idx[3] = {i, j, k};
        Vector3d x = Vector3d::Zero();
        double w = 1;
        for (int d = 0; d < dim; ++d) {
          const size_t q = static_cast<size_t>(idx[d]);
          x[d] = lo[d] + 0.5 * size[d] * (rule.points[q] + 1);
          w *= 0.5 * size[d] * rule.weights[q];
        }
        points.push_back(domain.to_world(x));  // x is in grid coordinates
        weights.push_back(w);
      }
}

}  // namespace

ErrorNorms immersed_error_norms(const geometry::ImmersedDomain& domain,
                                const ImmersedResult& result, const ImmersedOptions& options,
                                const std::function<Vector3d(const Vector3d&)>& exact_u,
                                const std::function<Matrix3d(const Vector3d&)>& exact_stress,
                                int inside_points) {
  const int degree = domain.background.degree(0);
  const nurbs::GaussRule rule =
      nurbs::gauss_legendre(inside_points > 0 ? inside_points : degree + 3);
  double l2 = 0, l2_norm = 0, energy = 0, energy_norm = 0;
  std::vector<Vector3d> points;
  std::vector<double> weights;
  for (const geometry::ImmersedCell& cell : domain.cells) {
    if (cell.kind == geometry::CellKind::kInside) {
      inside_rule(domain, cell, rule, points, weights);
    } else {
      points = cell.points;
      weights = cell.weights;
    }
    for (size_t q = 0; q < points.size(); ++q) {
      const Vector3d& x = points[q];
      const double w = weights[q];
      const Vector3d ue = exact_u(x);
      const Vector3d uh = evaluate_immersed(domain, result, x).displacement;
      l2 += w * (ue - uh).squaredNorm();
      l2_norm += w * ue.squaredNorm();
      const Matrix3d se = exact_stress(x);
      const Matrix3d sh = immersed_stress(domain, result, options, x);
      const Matrix3d ee = strain_from_stress(se, options.material, options.formulation);
      const Matrix3d eh = strain_from_stress(sh, options.material, options.formulation);
      energy += w * (se - sh).cwiseProduct(ee - eh).sum();
      energy_norm += w * se.cwiseProduct(ee).sum();
    }
  }
  ErrorNorms e;
  e.l2_error = std::sqrt(l2);
  e.l2_norm = std::sqrt(l2_norm);
  e.energy_error = std::sqrt(std::max(energy, 0.0));
  e.energy_norm = std::sqrt(energy_norm);
  return e;
}

}  // namespace isospring::analysis
