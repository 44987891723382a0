// Cell volume terms: V(x) = int det J over the (tri)linear cell, 2-point Gauss per direction
// (exact: det J is of degree 2 in each coordinate), forces and Jacobian-vector products.
#include <cmath>

#include "terms.hpp"

namespace isospring::runtime {
namespace {

// dN_a/dxi_m of the corner functions at the 2^Dim Gauss points; corner a has coordinate bit m.
template <int Dim>
struct CellRule {
  static constexpr int kCorners = 1 << Dim;
  double dn[kCorners][kCorners][Dim];  // [Gauss point][corner][direction]
  double weight = 1.0 / kCorners;      // (1/2)^Dim
  CellRule() {
    const double g = 0.5 / std::sqrt(3.0);
    const double points[2] = {0.5 - g, 0.5 + g};
    for (int p = 0; p < kCorners; ++p)
      for (int a = 0; a < kCorners; ++a)
        for (int m = 0; m < Dim; ++m) {
          double value = 1.0;
          for (int d = 0; d < Dim; ++d) {
            const bool upper = ((a >> d) & 1) != 0;
            const double xi = points[(p >> d) & 1];
            if (d == m)
              value *= upper ? 1.0 : -1.0;
            else
              value *= upper ? xi : 1.0 - xi;
          }
          dn[p][a][m] = value;
        }
  }
};

template <int Dim>
const CellRule<Dim>& cell_rule() {
  static const CellRule<Dim> rule;
  return rule;
}

// V, b = dV/dx (corner-major) and, when dx is given, db = (d2V/dx2) dx.
template <int Dim>
double volume_gradient(const double* cx, double* b, const double* dcx, double* db) {
  const CellRule<Dim>& rule = cell_rule<Dim>();
  constexpr int corners = CellRule<Dim>::kCorners;
  for (int e = 0; e < corners * Dim; ++e) {
    b[e] = 0.0;
    if (dcx) db[e] = 0.0;
  }
  double volume = 0.0;
  for (int p = 0; p < corners; ++p) {
    double j[Dim][Dim] = {}, dj[Dim][Dim] = {};
    for (int a = 0; a < corners; ++a)
      for (int i = 0; i < Dim; ++i)
        for (int m = 0; m < Dim; ++m) {
          j[i][m] += cx[a * Dim + i] * rule.dn[p][a][m];
          if (dcx) dj[i][m] += dcx[a * Dim + i] * rule.dn[p][a][m];
        }
    double c[Dim][Dim], dc[Dim][Dim];
    cofactor<Dim>(j, c);
    volume += rule.weight * determinant<Dim>(j, c);
    if (dcx) cofactor_derivative<Dim>(j, dj, dc);
    for (int a = 0; a < corners; ++a)
      for (int i = 0; i < Dim; ++i) {
        double sum = 0.0, dsum = 0.0;
        for (int m = 0; m < Dim; ++m) {
          sum += c[i][m] * rule.dn[p][a][m];
          if (dcx) dsum += dc[i][m] * rule.dn[p][a][m];
        }
        b[a * Dim + i] += rule.weight * sum;
        if (dcx) db[a * Dim + i] += rule.weight * dsum;
      }
  }
  return volume;
}

template <int Dim>
void gather(const CellVolumeTerm& t, const double* x, double* out) {
  for (int a = 0; a < (1 << Dim); ++a)
    for (int i = 0; i < Dim; ++i) out[a * Dim + i] = x[static_cast<long>(t.corners[a]) * Dim + i];
}

template <int Dim>
double forces(const Model& model, const double* x, double* f) {
  constexpr int size = (1 << Dim) * Dim;
  double energy = 0.0;
  for (const CellVolumeTerm& t : model.cell_volumes) {
    double cx[size], b[size];
    gather<Dim>(t, x, cx);
    const double change = volume_gradient<Dim>(cx, b, nullptr, nullptr) - t.rest_volume;
    energy += 0.5 * t.factor * change * change;
    const double scale = -t.factor * change;
    for (int a = 0; a < (1 << Dim); ++a)
      for (int i = 0; i < Dim; ++i)
        f[static_cast<long>(t.corners[a]) * Dim + i] += scale * b[a * Dim + i];
  }
  return energy;
}

// df = -factor ((b . dx) b + (V - V0) (d2V/dx2) dx).
template <int Dim>
void jvp(const Model& model, const double* x, const double* dx, double* df) {
  constexpr int size = (1 << Dim) * Dim;
  for (const CellVolumeTerm& t : model.cell_volumes) {
    double cx[size], dcx[size], b[size], db[size];
    gather<Dim>(t, x, cx);
    gather<Dim>(t, dx, dcx);
    const double change = volume_gradient<Dim>(cx, b, dcx, db) - t.rest_volume;
    double rate = 0.0;
    for (int e = 0; e < size; ++e) rate += b[e] * dcx[e];
    for (int a = 0; a < (1 << Dim); ++a)
      for (int i = 0; i < Dim; ++i)
        df[static_cast<long>(t.corners[a]) * Dim + i] -=
            t.factor * (rate * b[a * Dim + i] + change * db[a * Dim + i]);
  }
}

}  // namespace

double cell_volume(const double* corner_x, int dimension, double* gradient) {
  return dimension == 2 ? volume_gradient<2>(corner_x, gradient, nullptr, nullptr)
                        : volume_gradient<3>(corner_x, gradient, nullptr, nullptr);
}

double add_cell_volume_forces(const Model& model, const double* x, double* f) {
  return model.dimension == 2 ? forces<2>(model, x, f) : forces<3>(model, x, f);
}

void add_cell_volume_jvp(const Model& model, const double* x, const double* dx, double* df) {
  if (model.dimension == 2)
    jvp<2>(model, x, dx, df);
  else
    jvp<3>(model, x, dx, df);
}

}  // namespace isospring::runtime
