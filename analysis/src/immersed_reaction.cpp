// immersed_reaction (see immersed.hpp).
#include <algorithm>
#include <set>

#include "immersed_basis.hpp"
#include "immersed_kernels.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/immersed.hpp"

namespace isospring::analysis {

namespace {

bool supported(const ImmersedOptions& options, int face) {
  for (const ImmersedSupport& s : options.supports)
    if (s.face == face) return true;
  return false;
}

/// psi and its gradient at x (on element e): the sum over the basis functions in `layer`.
bool layer_function(const detail::BackgroundBasis& basis, const std::set<int>& layer,
                    const detail::Element& e, const Eigen::Vector3d& x, detail::BasisAt& at,
                    double& psi, Eigen::Vector3d& gradient) {
  basis.evaluate(e, x, at);
  psi = 0;
  gradient.setZero();
  bool any = false;
  for (size_t i = 0; i < at.control_points.size(); ++i) {
    if (!layer.count(at.control_points[i])) continue;
    any = true;
    const auto k = static_cast<Eigen::Index>(i);
    psi += at.values(k);
    for (int d = 0; d < basis.dim(); ++d) gradient[d] += at.gradients(k, d);
  }
  return any;
}

}  // namespace

Eigen::Vector3d immersed_reaction(const geometry::ImmersedDomain& domain,
                                  const ImmersedResult& result, const ImmersedOptions& options) {
  const detail::BackgroundBasis basis(domain, false);
  // The layer: every basis function that does not vanish at a support point.
  std::set<int> layer;
  std::vector<int> points;
  for (const geometry::BoundaryPoint& b : domain.boundary)
    if (supported(options, b.face)) {
      basis.control_points(basis.element_of(b.point), points);
      layer.insert(points.begin(), points.end());
    }
  const Eigen::Vector3d body = options.body_force + options.material.density * options.gravity;
  Eigen::Vector3d reaction = Eigen::Vector3d::Zero();
  detail::BasisAt at;
  double psi = 0;
  Eigen::Vector3d grad;
  // Cells whose basis misses the layer add nothing; the others are integrated over their reduced
  // rule (sigma grad psi and psi b lie in Q_2p on the cell's element).
  std::vector<int> cps;
  for (const geometry::ImmersedCell& cell : domain.cells) {
    const detail::Element e = detail::element_of_cell(basis, cell.points);
    basis.control_points(e, cps);
    if (std::none_of(cps.begin(), cps.end(), [&](int cp) { return layer.count(cp) > 0; })) continue;
    const detail::CellRule rule = detail::reduced_cell_rule(basis, e, cell.points, cell.weights);
    for (size_t q = 0; q < rule.points.size(); ++q) {
      if (!layer_function(basis, layer, e, rule.points[q], at, psi, grad)) continue;
      const Eigen::Matrix3d du =
          detail::value_on_element(basis, e, result, rule.points[q], at).gradient;
      const Eigen::Matrix3d sigma =
          stress_from_strain(0.5 * (du + du.transpose()), options.material, options.formulation);
      reaction += rule.weights[q] * (sigma * grad - psi * body);
    }
  }
  // Loads on the other faces within the layer's reach.
  for (const geometry::BoundaryPoint& b : domain.boundary) {
    Eigen::Vector3d load = Eigen::Vector3d::Zero();
    for (const ImmersedTraction& t : options.tractions)
      if (t.face == b.face) load += t.function ? t.function(b.point, b.normal) : t.value;
    for (const ImmersedPressure& p : options.pressures)
      if (p.face == b.face) load -= p.value * b.normal;
    if (load.squaredNorm() == 0 ||
        !layer_function(basis, layer, basis.element_of(b.point), b.point, at, psi, grad))
      continue;
    reaction -= b.weight * psi * load;
  }
  return reaction;
}

}  // namespace isospring::analysis
