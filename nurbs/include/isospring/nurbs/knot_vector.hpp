#pragma once
// Clamped (open) knot vectors: spans, unique knots, multiplicities and validation.
#include <string>
#include <vector>

namespace isospring::nurbs {

/// A non-decreasing, clamped knot vector t_0..t_{m} of degree p with n = m - p basis functions.
class KnotVector {
 public:
  KnotVector() = default;
  /// Throws InputError (with `context` in the message) unless check_knot_vector() accepts it.
  KnotVector(int degree, std::vector<double> knots, const std::string& context = "knot vector");

  /// Open uniform knot vector with `elements` equal spans on [a, b].
  static KnotVector uniform(int degree, int elements, double a = 0.0, double b = 1.0);

  int degree() const { return degree_; }
  const std::vector<double>& values() const { return knots_; }
  double operator[](int i) const { return knots_[static_cast<size_t>(i)]; }
  int size() const { return static_cast<int>(knots_.size()); }
  int num_basis() const { return size() - degree_ - 1; }
  double first() const { return knots_.front(); }
  double last() const { return knots_.back(); }

  /// Index i with t_i <= u < t_{i+1} and p <= i < num_basis(); u is clamped to [first, last] and
  /// u == last belongs to the last non-empty span.
  int find_span(double u) const;
  /// Distinct knot values (element boundaries) and how often each appears.
  std::vector<double> unique() const;
  std::vector<int> multiplicities() const;
  /// Multiplicity of the knot value u (0 when u is not a knot).
  int multiplicity(double u) const;
  int num_elements() const { return static_cast<int>(unique().size()) - 1; }
  /// Span index (as from find_span) of every non-empty knot interval, in order.
  std::vector<int> element_spans() const;

 private:
  int degree_ = 0;
  std::vector<double> knots_;
};

/// Empty when `knots` is a valid clamped knot vector of `degree` (with `expected_num_basis` basis
/// functions when that is >= 0); otherwise a sentence saying what is wrong and how to fix it.
/// Checks: finite values, non-decreasing, first and last knot repeated degree+1 times, interior
/// multiplicity <= degree, at least degree+1 basis functions, a non-empty parameter range.
std::string check_knot_vector(int degree, const std::vector<double>& knots,
                              int expected_num_basis = -1);

}  // namespace isospring::nurbs
