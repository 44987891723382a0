// Reduced cell rules (analysis/src/immersed_cell_rule.hpp): on every cut cell of immersed sphere
// and plate-with-hole domains, the reduced rule integrates every tensor monomial of degree
// <= 2 p per direction as the cell's own rule does (to round-off), and not one of degree 2 p + 1;
// a cut cell's stiffness and the strain energy come out as the cell's own points give them.
#include <gtest/gtest.h>

#include <cmath>

#include "immersed_cell_rule.hpp"
#include "immersed_kernels.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_implicit.hpp"

namespace isospring::analysis {
namespace {

using geometry::ImmersedDomain;

ImmersedDomain sphere_domain(int degree) {
  geometry::ImplicitShape shape;
  shape.dimension = 3;
  shape.box_min = {-1, -1, -1};
  shape.box_max = {1, 1, 1};
  shape.spheres.push_back({Eigen::Vector3d(0.05, -0.02, 0.03), 0.93, true});
  geometry::ImplicitGrid grid;
  grid.degree = degree;
  grid.elements = {4, 4, 4};
  return geometry::immerse_implicit(shape, grid);
}

ImmersedDomain plate_domain(int degree) {
  geometry::ImplicitShape shape;
  shape.box_max = {4, 4, 0};
  shape.circles.push_back({Eigen::Vector2d::Zero(), 1.3, false});
  geometry::ImplicitGrid grid;
  grid.degree = degree;
  grid.elements = {5, 5, 1};
  grid.grid_min = {-0.31, -0.17, 0};
  grid.grid_max = {4.4, 4.2, 0};
  return geometry::immerse_implicit(shape, grid);
}

// sum_q w_q prod_d ((x_d - c_d) / h_d)^e_d and the same sum of |terms| (the scale of round-off).
std::pair<double, double> moment(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& weights, const Eigen::Vector3d& c,
                                 const Eigen::Vector3d& h, const Eigen::Vector3i& e, int dim) {
  double sum = 0, scale = 0;
  for (size_t q = 0; q < points.size(); ++q) {
    double f = weights[q];
    for (int d = 0; d < dim; ++d) f *= std::pow((points[q][d] - c[d]) / h[d], e[d]);
    sum += f;
    scale += std::abs(f);
  }
  return {sum, scale};
}

// Every monomial of degree <= 2p per direction to 1e-13 of its terms' scale on every reduced cut
// cell; the degree 2p + 1 in one direction is off by more than 1e-8 on some cell (so the
// comparison can fail, and the reduction is no identity in disguise).
void check_moments(const ImmersedDomain& domain) {
  const detail::BackgroundBasis basis(domain);
  const int dim = domain.dimension, p = basis.degree(0);
  int reduced = 0;
  double worst = 0, beyond = 0;
  for (const auto& cell : domain.cells) {
    const detail::Element e = detail::element_of_cell(basis, cell.points);
    const detail::CellRule rule = detail::reduced_cell_rule(basis, e, cell.points, cell.weights);
    if (rule.points.size() == cell.points.size()) continue;
    ++reduced;
    EXPECT_EQ(rule.points.size(), static_cast<size_t>(std::pow(2 * p + 1, dim)));
    const Eigen::Vector3d lo = basis.element_lo(e), hi = basis.element_hi(e);
    const Eigen::Vector3d c = 0.5 * (lo + hi), h = (0.5 * (hi - lo)).cwiseMax(1e-300);
    const int top = 2 * p;
    for (int a = 0; a <= top; ++a)
      for (int b = 0; b <= top; ++b)
        for (int z = 0; z <= (dim == 3 ? top : 0); ++z) {
          const Eigen::Vector3i exponents(a, b, z);
          const auto [full, scale] = moment(cell.points, cell.weights, c, h, exponents, dim);
          const double mine = moment(rule.points, rule.weights, c, h, exponents, dim).first;
          worst = std::max(worst, std::abs(mine - full) / scale);
        }
    const Eigen::Vector3i over(top + 1, 0, 0);
    const auto [full, scale] = moment(cell.points, cell.weights, c, h, over, dim);
    beyond = std::max(
        beyond, std::abs(moment(rule.points, rule.weights, c, h, over, dim).first - full) / scale);
  }
  EXPECT_GT(reduced, 0);
  EXPECT_LT(worst, 1e-13);
  EXPECT_GT(beyond, 1e-8);
  std::printf("dim %d p %d: %d reduced cells, moments to %.2e, degree 2p+1 off by %.2e\n", dim, p,
              reduced, worst, beyond);
}

TEST(ImmersedCellRule, ReducedRuleHasTheCellsMomentsUpToDegreeTwoP) {
  for (int p : {1, 2, 3}) check_moments(plate_domain(p));
  for (int p : {1, 2}) check_moments(sphere_domain(p));
}

// A cut cell's stiffness from the reduced rule against the same product over the cell's own
// points (B^T D B per point, the textbook form), to 1e-12 of its largest entry.
TEST(ImmersedCellRule, CutCellStiffnessMatchesTheCellsOwnPoints) {
  const ImmersedDomain domain = sphere_domain(2);
  ImmersedOptions options;
  options.material = {2e5, 0.3, 0.0, 1.0};
  detail::ImmersedContext context{
      &domain, &options, detail::BackgroundBasis(domain), {}, 1.0, {}, {}, {}, {}, {}};
  context.lame = lame_parameters(options.material, options.formulation);
  const Eigen::MatrixXd D = detail::voigt_elasticity(context.lame, 3);
  int checked = 0;
  for (size_t c = 0; c < domain.cells.size(); ++c) {
    const auto& cell = domain.cells[c];
    const detail::Element e = detail::element_of_cell(context.basis, cell.points);
    context.cell_elements.push_back(e);
    context.cell_rules.push_back(
        detail::reduced_cell_rule(context.basis, e, cell.points, cell.weights));
  }
  std::vector<int> cps;
  Eigen::MatrixXd local;
  detail::BasisAt at;
  for (size_t c = 0; c < domain.cells.size() && checked < 12; ++c) {
    const auto& cell = domain.cells[c];
    if (context.cell_rules[c].points.size() == cell.points.size()) continue;
    ++checked;
    detail::cell_stiffness(context, c, cps, local);
    Eigen::MatrixXd full = Eigen::MatrixXd::Zero(local.rows(), local.cols());
    for (size_t q = 0; q < cell.points.size(); ++q) {
      context.basis.evaluate(context.cell_elements[c], cell.points[q], at);
      const Eigen::MatrixXd B = detail::strain_operator(at.gradients, 3);
      full += cell.weights[q] * B.transpose() * D * B;
    }
    EXPECT_LT((local - full).cwiseAbs().maxCoeff(), 1e-12 * full.cwiseAbs().maxCoeff())
        << "cell " << c << " with " << cell.points.size() << " points";
  }
  EXPECT_EQ(checked, 12);
}

// The strain energy (reduced rules) against 1/2 sigma : eps summed over every cell's own points.
TEST(ImmersedCellRule, StrainEnergyMatchesTheCellsOwnPoints) {
  const ImmersedDomain domain = plate_domain(2);
  ImmersedOptions options;
  options.formulation = Formulation::kPlaneStress;
  options.material = {7e4, 0.3, 2.7, 1.0};
  options.gravity = {0.3, -9.81, 0};
  ImmersedSupport clamp;
  clamp.face = 2;  // y = 0
  clamp.fixed = {true, true, false};
  options.supports.push_back(clamp);
  const ImmersedResult result = solve_immersed(domain, options);
  double energy = 0;
  for (const auto& cell : domain.cells)
    for (size_t q = 0; q < cell.points.size(); ++q) {
      const Eigen::Matrix3d g = evaluate_immersed(domain, result, cell.points[q]).gradient;
      const Eigen::Matrix3d strain = 0.5 * (g + g.transpose());
      energy += 0.5 * cell.weights[q] *
                stress_from_strain(strain, options.material, options.formulation)
                    .cwiseProduct(strain)
                    .sum();
    }
  EXPECT_NEAR(result.strain_energy, energy, 1e-13 * energy);
}

}  // namespace
}  // namespace isospring::analysis
