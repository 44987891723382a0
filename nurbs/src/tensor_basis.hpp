#pragma once
// Internal: the non-zero tensor-product B-spline functions of a patch at one parameter, with
// their first and second parametric derivatives, without heap allocation.
#include <array>

#include "isospring/nurbs/basis.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::nurbs::detail {

class TensorBasis {
 public:
  struct Values {
    double value;
    double first[3];
    double second[3][3];  // upper triangle (a <= b) filled
  };

  TensorBasis(const Patch& patch, const Param& u, int order) : patch_(patch), order_(order) {
    for (int d = 0; d < patch.param_dim(); ++d) {
      const KnotVector& kv = patch.knots(d);
      spans_[d] = kv.find_span(u[d]);
      degree_[d] = kv.degree();
      basis_derivatives(kv, spans_[d], u[d], order, ders_[d].data());
    }
  }

  int count() const {
    int n = 1;
    for (int d = 0; d < patch_.param_dim(); ++d) n *= degree_[d] + 1;
    return n;
  }

  /// Calls f(global control point index, Values) for each non-zero function, first direction
  /// fastest.
  template <class F>
  void for_each(F&& f) const {
    const int dim = patch_.param_dim();
    const int p0 = degree_[0], p1 = dim > 1 ? degree_[1] : 0, p2 = dim > 2 ? degree_[2] : 0;
    Values v{};
    for (int k = 0; k <= p2; ++k)
      for (int j = 0; j <= p1; ++j)
        for (int i = 0; i <= p0; ++i) {
          const int local[3] = {i, j, k};
          double n[3][3];  // n[dir][derivative order]
          for (int d = 0; d < 3; ++d)
            for (int o = 0; o < 3; ++o) n[d][o] = d < dim ? der(d, o, local[d]) : (o == 0);
          v.value = n[0][0] * n[1][0] * n[2][0];
          if (order_ >= 1) {
            v.first[0] = n[0][1] * n[1][0] * n[2][0];
            v.first[1] = n[0][0] * n[1][1] * n[2][0];
            v.first[2] = n[0][0] * n[1][0] * n[2][1];
          }
          if (order_ >= 2) {
            v.second[0][0] = n[0][2] * n[1][0] * n[2][0];
            v.second[1][1] = n[0][0] * n[1][2] * n[2][0];
            v.second[2][2] = n[0][0] * n[1][0] * n[2][2];
            v.second[0][1] = n[0][1] * n[1][1] * n[2][0];
            v.second[0][2] = n[0][1] * n[1][0] * n[2][1];
            v.second[1][2] = n[0][0] * n[1][1] * n[2][1];
          }
          const int index = patch_.index(spans_[0] - p0 + i, dim > 1 ? spans_[1] - p1 + j : 0,
                                         dim > 2 ? spans_[2] - p2 + k : 0);
          f(index, v);
        }
  }

 private:
  double der(int dir, int order, int local) const {
    if (order > order_) return 0.0;
    return ders_[dir][static_cast<size_t>(order * (degree_[dir] + 1) + local)];
  }

  const Patch& patch_;
  int order_;
  int spans_[3] = {0, 0, 0};
  int degree_[3] = {0, 0, 0};
  std::array<std::array<double, 3 * (kMaxDegree + 1)>, 3> ders_{};
};

}  // namespace isospring::nurbs::detail
