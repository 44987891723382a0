#include "isospring/nurbs/bezier_extraction.hpp"

#include "curve_refinement.hpp"

namespace isospring::nurbs {

std::vector<Eigen::MatrixXd> bezier_extraction(const KnotVector& knots) {
  // Raise every interior knot to multiplicity p by knot insertion applied to the identity "control
  // points" e_i: afterwards N_i = sum_j Q_j[i] B_j, with B_j the Bezier (Bernstein) functions of
  // the elements. Element e owns B_{e p} .. B_{e p + p} (Borden et al. 2011, eq. 10).
  const int p = knots.degree();
  const int n = knots.num_basis();
  std::vector<double> inserted;
  const std::vector<double> breaks = knots.unique();
  for (size_t k = 1; k + 1 < breaks.size(); ++k)
    for (int r = knots.multiplicity(breaks[k]); r < p; ++r) inserted.push_back(breaks[k]);
  std::vector<Eigen::VectorXd> identity(static_cast<size_t>(n), Eigen::VectorXd::Zero(n));
  for (int i = 0; i < n; ++i) identity[static_cast<size_t>(i)](i) = 1.0;
  const std::vector<Eigen::VectorXd> q =
      inserted.empty() ? identity
                       : detail::refine_knot_vector_curve(knots, identity, inserted, nullptr);

  const std::vector<int> spans = knots.element_spans();
  std::vector<Eigen::MatrixXd> operators;
  operators.reserve(spans.size());
  for (size_t e = 0; e < spans.size(); ++e) {
    Eigen::MatrixXd c(p + 1, p + 1);
    const int first_old = spans[e] - p;
    for (int a = 0; a <= p; ++a)
      for (int k = 0; k <= p; ++k)
        c(a, k) = q[e * static_cast<size_t>(p) + static_cast<size_t>(k)](first_old + a);
    operators.push_back(c);
  }
  return operators;
}

Eigen::MatrixXd bernstein(int p, double t) {
  // Row 0: B_{i,p}(t) = C(p,i) t^i (1-t)^(p-i) by the stable triangular recurrence;
  // row 1: B'_{i,p} = p (B_{i-1,p-1} - B_{i,p-1}).
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(2, p + 1);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(p + 1);
  Eigen::VectorXd lower = Eigen::VectorXd::Zero(p + 1);
  b(0) = 1.0;
  for (int k = 1; k <= p; ++k) {
    if (k == p) lower = b;
    for (int i = k; i >= 1; --i) b(i) = (1.0 - t) * b(i) + t * b(i - 1);
    b(0) *= (1.0 - t);
  }
  out.row(0) = b.transpose();
  for (int i = 0; i <= p && p >= 1; ++i) {
    const double left = i >= 1 ? lower(i - 1) : 0.0;
    const double right = i <= p - 1 ? lower(i) : 0.0;
    out(1, i) = p * (left - right);
  }
  return out;
}

}  // namespace isospring::nurbs
