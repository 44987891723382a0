// B-bar: the local projection of the volumetric strain and its stiffness.
#include "volumetric_projection.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

#include "isospring/analysis/elasticity.hpp"
#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis::detail {

namespace {

// The open knot vector of degree p - 1 on the same breaks: the end knots once fewer, interior
// multiplicities capped at p - 1 (they are at most p).
nurbs::KnotVector reduced_knots(const nurbs::KnotVector& knots) {
  const int degree = knots.degree() - 1;
  const std::vector<double> breaks = knots.unique();
  const std::vector<int> multiplicity = knots.multiplicities();
  std::vector<double> values;
  for (size_t i = 0; i < breaks.size(); ++i) {
    const bool end = i == 0 || i + 1 == breaks.size();
    const int m = end ? degree + 1 : std::min(multiplicity[i], degree);
    values.insert(values.end(), static_cast<size_t>(m), breaks[i]);
  }
  return nurbs::KnotVector(degree, values, "projection space knot vector");
}

double bulk_modulus(const Problem& problem) {
  return bbar_bulk_modulus(lame_parameters(problem.material, problem.formulation));
}

// Per element: local Gram, local divergence operator (functions of Q x element DOFs a * dim + i),
// and the integrals of the local functions, all from the solve's quadrature rule.
struct ElementProjection {
  std::vector<int> rows;
  Eigen::MatrixXd gram, divergence;
  Eigen::VectorXd integrals;
};

void element_projection(const PressureSpace& space, const PatchQuadrature& quadrature, int patch,
                        int e, int dim, ElementProjection& out) {
  const int m = space.local_count();
  const int n = quadrature.basis_count();
  const std::array<int, 3> position = quadrature.element_position(e);
  out.rows.resize(static_cast<size_t>(m));
  out.gram.setZero(m, m);
  out.divergence.setZero(m, n * dim);
  out.integrals.setZero(m);
  QuadraturePoint point;
  Eigen::MatrixXd gradients(n, dim);
  Eigen::VectorXd values(m);
  for (int q = 0; q < quadrature.points_per_element(); ++q) {
    quadrature.evaluate(e, q, point);
    const double w = point.weight * physical_gradients(point, dim, patch, e, gradients);
    space.evaluate(position, point.param, out.rows.data(), values.data());
    out.gram.noalias() += w * values * values.transpose();
    out.integrals += w * values;
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        out.divergence.col(a * dim + i) += (w * gradients(a, i)) * values;
  }
}

}  // namespace

PressureSpace::PressureSpace(const nurbs::Patch& patch) : param_dim_(patch.param_dim()) {
  size_ = 1;
  for (int d = 0; d < param_dim_; ++d) {
    Direction& dir = directions_[static_cast<size_t>(d)];
    dir.displacement = patch.knots(d);
    dir.element_spans = dir.displacement.element_spans();
    dir.degree = dir.displacement.degree() - 1;
    if (dir.degree < 0)
      throw nurbs::InputError(
          "B-bar needs degree >= 1 in every direction of every patch (raise the degree or use "
          "\"volumetric\": \"displacement\")");
    if (dir.degree == 0) {
      dir.count = static_cast<int>(dir.element_spans.size());
      for (int k = 0; k < dir.count; ++k) dir.first.push_back(k);
    } else {
      dir.reduced = reduced_knots(dir.displacement);
      dir.count = dir.reduced.num_basis();
      for (int span : dir.reduced.element_spans()) dir.first.push_back(span - dir.degree);
      if (dir.first.size() != dir.element_spans.size())
        throw nurbs::InputError("projection space: element counts differ (internal error)");
    }
    size_ *= dir.count;
    local_count_ *= dir.degree + 1;
  }
}

std::array<int, 3> PressureSpace::element_of(const nurbs::Param& u) const {
  std::array<int, 3> element{0, 0, 0};
  for (int d = 0; d < param_dim_; ++d) {
    const Direction& dir = directions_[static_cast<size_t>(d)];
    const int span = dir.displacement.find_span(u[static_cast<size_t>(d)]);
    const auto it = std::lower_bound(dir.element_spans.begin(), dir.element_spans.end(), span);
    element[static_cast<size_t>(d)] = static_cast<int>(it - dir.element_spans.begin());
  }
  return element;
}

void PressureSpace::evaluate(const std::array<int, 3>& element, const nurbs::Param& u, int* indices,
                             double* values) const {
  // Univariate values per direction, then their tensor product (first direction fastest).
  // Directions beyond the parametric dimension: one function, 1.
  std::array<std::array<double, nurbs::kMaxDegree + 1>, 3> rows{};
  for (auto& row : rows) row[0] = 1.0;
  std::array<int, 3> first{0, 0, 0}, order{1, 1, 1}, count{1, 1, 1};
  for (int d = 0; d < param_dim_; ++d) {
    const Direction& dir = directions_[static_cast<size_t>(d)];
    const size_t sd = static_cast<size_t>(d);
    first[sd] = dir.first[static_cast<size_t>(element[sd])];
    order[sd] = dir.degree + 1;
    count[sd] = dir.count;
    if (dir.degree == 0)
      rows[sd][0] = 1.0;
    else
      nurbs::basis_functions(dir.reduced, first[sd] + dir.degree, u[sd], rows[sd].data());
  }
  int a = 0;
  for (int k = 0; k < order[2]; ++k)
    for (int j = 0; j < order[1]; ++j)
      for (int i = 0; i < order[0]; ++i, ++a) {
        indices[a] = first[0] + i + count[0] * (first[1] + j + count[1] * (first[2] + k));
        values[a] = rows[0][static_cast<size_t>(i)] * rows[1][static_cast<size_t>(j)] *
                    rows[2][static_cast<size_t>(k)];
      }
}

VolumetricProjection volumetric_projection(
    const Problem& problem, const std::vector<PatchQuadrature>& quadratures, int columns,
    const std::function<int(int patch, int control_point, int component)>& column) {
  const int dim = spatial_dimension(problem.formulation);
  VolumetricProjection result;
  result.offset.push_back(0);
  for (const auto& patch : problem.patches) {
    result.spaces.emplace_back(patch);
    result.offset.push_back(result.offset.back() + result.spaces.back().size());
  }
  const int rows = result.offset.back();
  // Row A of the projection: sum over the elements e of its support of I_Ae (M_e^-1 D_e)_A,
  // divided by sum_e I_Ae, I_Ae = int_e N_A: the weights sum to one, so a field already in Q
  // (whose element projections all agree) is reproduced.
  std::vector<Eigen::Triplet<double>> projection, gram;
  Eigen::VectorXd support_integral = Eigen::VectorXd::Zero(rows);
  ElementProjection element;
  std::vector<int> cps;
  for (size_t p = 0; p < problem.patches.size(); ++p) {
    const PatchQuadrature& quadrature = quadratures[p];
    const int offset = result.offset[p];
    cps.resize(static_cast<size_t>(quadrature.basis_count()));
    for (int e = 0; e < quadrature.num_elements(); ++e) {
      element_projection(result.spaces[p], quadrature, static_cast<int>(p), e, dim, element);
      quadrature.element_control_points(e, cps.data());
      const Eigen::LLT<Eigen::MatrixXd> llt(element.gram);
      if (llt.info() != Eigen::Success)
        throw nurbs::InputError("B-bar: the projection's element Gram matrix of patch " +
                                std::to_string(p) + ", element " + std::to_string(e) +
                                " is singular (a degenerate element?)");
      const Eigen::MatrixXd local = llt.solve(element.divergence);
      const int m = static_cast<int>(element.rows.size());
      for (int a = 0; a < m; ++a) {
        const int row = offset + element.rows[static_cast<size_t>(a)];
        support_integral[row] += element.integrals[a];
        for (int b = 0; b < m; ++b)
          gram.emplace_back(row, offset + element.rows[static_cast<size_t>(b)], element.gram(a, b));
        for (size_t c = 0; c < cps.size(); ++c)
          for (int i = 0; i < dim; ++i)
            projection.emplace_back(
                row, column(static_cast<int>(p), cps[c], i),
                element.integrals[a] * local(a, static_cast<Eigen::Index>(c) * dim + i));
      }
    }
  }
  result.projection.resize(rows, columns);
  result.projection.setFromTriplets(projection.begin(), projection.end());
  for (int r = 0; r < rows; ++r) result.projection.row(r) /= support_integral[r];
  result.gram.resize(rows, rows);
  result.gram.setFromTriplets(gram.begin(), gram.end());
  return result;
}

void check_volumetric(const Problem& problem) {
  if (problem.volumetric == Volumetric::kBbar && problem.formulation == Formulation::kPlaneStress)
    throw nurbs::InputError(
        "\"volumetric\": \"bbar\" applies to plane strain and solids; plane stress does not lock "
        "(its lambda* stays below 2 mu), use \"displacement\"");
}

Eigen::SparseMatrix<double> bbar_volumetric_stiffness(const Problem& problem, const DofMap& dofs,
                                                      const AssemblyStructure& structure) {
  check_volumetric(problem);
  const VolumetricProjection projection =
      volumetric_projection(problem, structure.quadratures, dofs.num_dofs(),
                            [&](int patch, int cp, int i) { return dofs.dof(patch, cp, i); });
  const Eigen::SparseMatrix<double> c = projection.projection;
  const Eigen::SparseMatrix<double> gc = projection.gram * c;
  const Eigen::SparseMatrix<double> full = (bulk_modulus(problem) * thickness_factor(problem)) *
                                           Eigen::SparseMatrix<double>(c.transpose() * gc);
  return full.triangularView<Eigen::Upper>();
}

double bbar_bulk_modulus(const LameParameters& lame) {
  return lame.lambda + 2.0 * lame.mu / 3.0;
}

LameParameters bbar_deviatoric_lame(const LameParameters& lame) {
  return {-2.0 * lame.mu / 3.0, lame.mu};
}

double kernel_lambda(const Problem& problem, double lambda, double mu) {
  return problem.volumetric == Volumetric::kBbar ? bbar_deviatoric_lame({lambda, mu}).lambda
                                                 : lambda;
}

Eigen::Matrix3d bbar_stress(const Eigen::Matrix3d& strain, double projected_dilatation,
                            const Problem& problem) {
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  Eigen::Matrix3d e = strain;
  if (problem.formulation == Formulation::kPlaneStrain) {
    e.row(2).setZero();
    e.col(2).setZero();
  }
  const Eigen::Matrix3d deviator = e - e.trace() / 3.0 * Eigen::Matrix3d::Identity();
  return 2.0 * lame.mu * deviator +
         bulk_modulus(problem) * projected_dilatation * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d bbar_strain(const Eigen::Matrix3d& strain, double projected_dilatation,
                            const Problem& problem) {
  Eigen::Matrix3d e = strain;
  if (problem.formulation == Formulation::kPlaneStrain) {
    e.row(2).setZero();
    e.col(2).setZero();
  }
  return e + (projected_dilatation - e.trace()) / 3.0 * Eigen::Matrix3d::Identity();
}

double bbar_energy_density(const Eigen::Matrix3d& strain, double projected_dilatation,
                           const Problem& problem) {
  const LameParameters lame = lame_parameters(problem.material, problem.formulation);
  Eigen::Matrix3d e = strain;
  if (problem.formulation == Formulation::kPlaneStrain) {
    e.row(2).setZero();
    e.col(2).setZero();
  }
  const Eigen::Matrix3d deviator = e - e.trace() / 3.0 * Eigen::Matrix3d::Identity();
  return lame.mu * deviator.squaredNorm() +
         0.5 * bulk_modulus(problem) * projected_dilatation * projected_dilatation;
}

ProjectedDilatation::ProjectedDilatation(
    const Problem& problem, const std::vector<std::vector<Eigen::Vector3d>>& displacements) {
  check_volumetric(problem);
  const int dim = spatial_dimension(problem.formulation);
  std::vector<int> first{0};
  for (const auto& patch : problem.patches)
    first.push_back(first.back() + patch.num_points() * dim);
  std::vector<PatchQuadrature> quadratures;
  for (const auto& patch : problem.patches)
    quadratures.push_back(PatchQuadrature::volume(patch, problem.quadrature_points));
  projection_ = volumetric_projection(
      problem, quadratures, first.back(),
      [&](int patch, int cp, int i) { return first[static_cast<size_t>(patch)] + cp * dim + i; });
  Eigen::VectorXd u(first.back());
  for (size_t p = 0; p < displacements.size(); ++p)
    for (size_t cp = 0; cp < displacements[p].size(); ++cp)
      for (int i = 0; i < dim; ++i)
        u[first[p] + static_cast<int>(cp) * dim + i] = displacements[p][cp][i];
  coefficients_ = projection_.projection * u;
}

double ProjectedDilatation::at(int patch, const nurbs::Param& u) const {
  const PressureSpace& space = projection_.spaces[static_cast<size_t>(patch)];
  thread_local std::vector<int> indices;
  thread_local std::vector<double> values;
  indices.resize(static_cast<size_t>(space.local_count()));
  values.resize(static_cast<size_t>(space.local_count()));
  space.evaluate(space.element_of(u), u, indices.data(), values.data());
  double theta = 0.0;
  const int offset = projection_.offset[static_cast<size_t>(patch)];
  for (size_t a = 0; a < indices.size(); ++a)
    theta += values[a] * coefficients_[offset + indices[a]];
  return theta;
}

}  // namespace isospring::analysis::detail
