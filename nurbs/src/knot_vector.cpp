#include "isospring/nurbs/knot_vector.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isospring/nurbs/error.hpp"

namespace isospring::nurbs {

KnotVector::KnotVector(int degree, std::vector<double> knots, const std::string& context)
    : degree_(degree), knots_(std::move(knots)) {
  const std::string problem = check_knot_vector(degree_, knots_);
  if (!problem.empty()) throw InputError(context + ": " + problem);
}

KnotVector KnotVector::uniform(int degree, int elements, double a, double b) {
  if (degree < 0 || elements < 1 || !(b > a))
    throw InputError("uniform knot vector: need degree >= 0, elements >= 1 and a < b");
  std::vector<double> knots(static_cast<size_t>(degree + 1), a);
  for (int e = 1; e < elements; ++e) knots.push_back(a + (b - a) * e / elements);
  knots.insert(knots.end(), static_cast<size_t>(degree + 1), b);
  return KnotVector(degree, std::move(knots));
}

int KnotVector::find_span(double u) const {
  const int n = num_basis();
  if (u >= knots_[static_cast<size_t>(n)]) return n - 1;
  if (u <= knots_[static_cast<size_t>(degree_)]) {
    // First non-empty span (interior knots may coincide with the first knot only when clamped).
    int span = degree_;
    while (knots_[static_cast<size_t>(span + 1)] <= u) ++span;
    return span;
  }
  // upper_bound gives the first knot > u; the span starts one before it.
  const auto it = std::upper_bound(knots_.begin() + degree_, knots_.begin() + n + 1, u);
  return static_cast<int>(it - knots_.begin()) - 1;
}

std::vector<double> KnotVector::unique() const {
  std::vector<double> values;
  for (double t : knots_)
    if (values.empty() || t != values.back()) values.push_back(t);
  return values;
}

std::vector<int> KnotVector::multiplicities() const {
  std::vector<int> counts;
  for (size_t i = 0; i < knots_.size(); ++i) {
    if (i == 0 || knots_[i] != knots_[i - 1])
      counts.push_back(1);
    else
      ++counts.back();
  }
  return counts;
}

int KnotVector::multiplicity(double u) const {
  return static_cast<int>(std::count(knots_.begin(), knots_.end(), u));
}

std::vector<int> KnotVector::element_spans() const {
  std::vector<int> spans;
  for (int i = degree_; i < num_basis(); ++i)
    if (knots_[static_cast<size_t>(i + 1)] > knots_[static_cast<size_t>(i)]) spans.push_back(i);
  return spans;
}

std::string check_knot_vector(int degree, const std::vector<double>& knots,
                              int expected_num_basis) {
  std::ostringstream msg;
  if (degree < 1 || degree > 20) {
    msg << "degree " << degree << " is not supported; use a degree from 1 to 20";
    return msg.str();
  }
  const int m = static_cast<int>(knots.size());
  for (int i = 0; i < m; ++i) {
    if (!std::isfinite(knots[static_cast<size_t>(i)])) {
      msg << "knot " << i << " is not a finite number; every knot must be finite";
      return msg.str();
    }
  }
  if (m < 2 * (degree + 1)) {
    msg << "has " << m << " knots but degree " << degree << " needs at least " << 2 * (degree + 1)
        << " (the first and last knot each repeated degree+1 times)";
    return msg.str();
  }
  for (int i = 1; i < m; ++i) {
    if (knots[static_cast<size_t>(i)] < knots[static_cast<size_t>(i - 1)]) {
      msg << "knots must not decrease, but knot " << i << " (" << knots[static_cast<size_t>(i)]
          << ") is smaller than knot " << i - 1 << " (" << knots[static_cast<size_t>(i - 1)]
          << "); sort the knot vector";
      return msg.str();
    }
  }
  if (!(knots.back() > knots.front()))
    return "all knots are equal; the parameter range must not be empty";
  const int first_mult = static_cast<int>(std::count(knots.begin(), knots.end(), knots.front()));
  const int last_mult = static_cast<int>(std::count(knots.begin(), knots.end(), knots.back()));
  if (first_mult != degree + 1 || last_mult != degree + 1) {
    msg << "is not clamped: the first and last knots must each appear exactly degree+1 = "
        << degree + 1 << " times (found " << first_mult << " and " << last_mult
        << "); isospring reads open (clamped) knot vectors only";
    return msg.str();
  }
  int run = 1;
  for (int i = 1; i < m; ++i) {
    run = knots[static_cast<size_t>(i)] == knots[static_cast<size_t>(i - 1)] ? run + 1 : 1;
    const double value = knots[static_cast<size_t>(i)];
    if (run > degree && value != knots.front() && value != knots.back()) {
      msg << "interior knot " << value << " has multiplicity above the degree " << degree
          << " (the basis would be discontinuous); reduce it to at most " << degree;
      return msg.str();
    }
  }
  const int num_basis = m - degree - 1;
  if (expected_num_basis >= 0 && num_basis != expected_num_basis) {
    msg << "has " << m << " knots, which with degree " << degree << " give " << num_basis
        << " control points per row, but " << expected_num_basis
        << " are given; the knot count must be control points + degree + 1";
    return msg.str();
  }
  return {};
}

}  // namespace isospring::nurbs
