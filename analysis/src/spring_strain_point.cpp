// Strain-point terms (header: definition and why).
#include "isospring/analysis/spring_strain_point.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "patch_quadrature.hpp"

namespace isospring::analysis {

namespace {

double levi_civita(int i, int j, int k) {
  return static_cast<double>((i - j) * (j - k) * (k - i)) / 2.0;
}

template <int Dim>
Eigen::Matrix<double, Dim, Dim> deformation_gradient(const VolumeTerm& term,
                                                     const Eigen::VectorXd& x) {
  Eigen::Matrix<double, Dim, Dim> f = Eigen::Matrix<double, Dim, Dim>::Zero();
  for (size_t a = 0; a < term.points.size(); ++a)
    f += x.segment<Dim>(static_cast<Eigen::Index>(term.points[a]) * Dim) *
         term.gradients[a].head<Dim>().transpose();
  return f;
}

template <int Dim>
double volume_fixed(const VolumeTerm& term, const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                    Eigen::MatrixXd* hessian) {
  using M = Eigen::Matrix<double, Dim, Dim>;
  const M f = deformation_gradient<Dim>(term, x);
  const double v0 = term.rest_volume;
  const int n = static_cast<int>(term.points.size());
  if (gradient) {
    // d det F / dF = cof F.
    M cof;
    if constexpr (Dim == 2) {
      cof << f(1, 1), -f(1, 0), -f(0, 1), f(0, 0);
    } else {
      for (int m = 0; m < 3; ++m) cof.col(m) = f.col((m + 1) % 3).cross(f.col((m + 2) % 3));
    }
    gradient->resize(n * Dim);
    for (int a = 0; a < n; ++a)
      gradient->segment<Dim>(a * Dim) = v0 * cof * term.gradients[a].template head<Dim>();
  }
  if (hessian) {
    hessian->setZero(n * Dim, n * Dim);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j)
        for (int m = 0; m < Dim; ++m)
          for (int q = 0; q < Dim; ++q) {
            double second = 0.0;  // d2 det F / dF_im dF_jq
            if constexpr (Dim == 2) {
              second = static_cast<double>((j - i) * (q - m));
            } else {
              for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l)
                  second += levi_civita(i, j, k) * levi_civita(m, q, l) * f(k, l);
            }
            if (second == 0.0) continue;
            for (int a = 0; a < n; ++a)
              for (int b = 0; b < n; ++b)
                (*hessian)(a * Dim + i, b * Dim + j) +=
                    v0 * second * term.gradients[a][m] * term.gradients[b][q];
          }
  }
  return v0 * f.determinant();
}

template <int Dim>
double shear_fixed(const VolumeTerm& term, const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                   Eigen::MatrixXd* hessian) {
  using M = Eigen::Matrix<double, Dim, Dim>;
  using V = Eigen::Matrix<double, Dim, 1>;
  const int n = static_cast<int>(term.points.size());
  const M f = deformation_gradient<Dim>(term, x);
  const M identity = M::Identity();
  auto dev = [&](const M& m) { return M(m - m.trace() / Dim * identity); };
  const M dg = dev(0.5 * (f.transpose() * f - identity));
  const double scale = term.modulus * std::abs(term.rest_volume);
  if (gradient) {
    const M p = 2.0 * scale * f * dg;  // dE/dF
    gradient->resize(n * Dim);
    for (int a = 0; a < n; ++a)
      gradient->segment<Dim>(a * Dim) = p * term.gradients[a].template head<Dim>();
  }
  if (hessian) {
    hessian->resize(n * Dim, n * Dim);
    for (int b = 0; b < n; ++b)
      for (int j = 0; j < Dim; ++j) {
        const M df = V::Unit(j) * term.gradients[b].template head<Dim>().transpose();
        const M dsym = 0.5 * (f.transpose() * df + df.transpose() * f);
        const M dp = 2.0 * scale * (df * dg + f * dev(dsym));
        for (int a = 0; a < n; ++a)
          hessian->block<Dim, 1>(a * Dim, b * Dim + j) =
              dp * term.gradients[a].template head<Dim>();
      }
  }
  return scale * dg.squaredNorm();
}

}  // namespace

std::vector<StrainPointSite> strain_point_sites(const nurbs::Patch& patch,
                                                int points_per_direction) {
  const int dim = patch.param_dim();
  const detail::PatchQuadrature quadrature =
      detail::PatchQuadrature::volume(patch, points_per_direction);
  std::vector<StrainPointSite> sites;
  std::vector<int> cps(static_cast<size_t>(quadrature.basis_count()));
  detail::QuadraturePoint point;
  for (int e = 0; e < quadrature.num_elements(); ++e) {
    quadrature.element_control_points(e, cps.data());
    for (int q = 0; q < quadrature.points_per_element(); ++q) {
      quadrature.evaluate(e, q, point);
      const Eigen::MatrixXd jacobian = point.jacobian.topLeftCorner(dim, dim);
      const double det = jacobian.determinant();
      // Relative to the element's size: a pole or collapsed edge is on the boundary of a span,
      // so |det J| vanishes there only, never at an interior Gauss point.
      if (!(std::abs(det) > 1e-12 * std::pow(jacobian.norm(), dim))) continue;
      const Eigen::MatrixXd gradients = point.derivatives * jacobian.inverse();  // dR_a/dX
      StrainPointSite site;
      site.volume = point.weight * std::abs(det);
      site.position = point.point;
      for (int a = 0; a < quadrature.basis_count(); ++a) {
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        g.head(dim) = gradients.row(a).transpose();
        site.control_points.push_back(cps[static_cast<size_t>(a)]);
        site.gradients.push_back(g);
      }
      sites.push_back(std::move(site));
    }
  }
  return sites;
}

double strain_point_volume(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                           Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian) {
  return dimension == 2 ? volume_fixed<2>(term, x, gradient, hessian)
                        : volume_fixed<3>(term, x, gradient, hessian);
}

double strain_point_shear_energy(const VolumeTerm& term, const Eigen::VectorXd& x, int dimension,
                                 Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian) {
  return dimension == 2 ? shear_fixed<2>(term, x, gradient, hessian)
                        : shear_fixed<3>(term, x, gradient, hessian);
}

Eigen::VectorXd strain_point_rest_gradient(const VolumeTerm& term, int dimension) {
  Eigen::VectorXd b(static_cast<Eigen::Index>(term.points.size()) * dimension);
  for (size_t a = 0; a < term.points.size(); ++a)
    b.segment(static_cast<Eigen::Index>(a) * dimension, dimension) =
        term.rest_volume * term.gradients[a].head(dimension);
  return b;
}

}  // namespace isospring::analysis
