#pragma once
// One function pair per term kind (forces add into f and return the energy; JVPs add into df),
// and the small fixed-size matrix helpers they share. Private to the runtime.
#include "model.hpp"

namespace isospring::runtime {

double add_spring_forces(const Model& model, const double* x, const double* v, double* f);
void add_spring_jvp(const Model& model, const double* x, const double* v, const double* dx,
                    const double* dv, double* df);

double add_cell_volume_forces(const Model& model, const double* x, double* f);
void add_cell_volume_jvp(const Model& model, const double* x, const double* dx, double* df);

/// Shear energy scale |dev G|^2 on gradient terms (cell shear and point shear terms).
double add_shear_forces(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
                        double* f);
void add_shear_jvp(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
                   const double* dx, double* df);

/// Point volume energy 1/2 scale (det F - 1)^2.
double add_point_volume_forces(const Model& model, const double* x, double* f);
void add_point_volume_jvp(const Model& model, const double* x, const double* dx, double* df);

/// Cofactor matrix d det A / dA of a Dim x Dim matrix, and its derivative along dA.
template <int Dim>
void cofactor(const double a[Dim][Dim], double c[Dim][Dim]) {
  if constexpr (Dim == 2) {
    c[0][0] = a[1][1];
    c[0][1] = -a[1][0];
    c[1][0] = -a[0][1];
    c[1][1] = a[0][0];
  } else {
    // Column m of the cofactor matrix: column m+1 x column m+2.
    for (int m = 0; m < 3; ++m) {
      const int p = (m + 1) % 3, q = (m + 2) % 3;
      c[0][m] = a[1][p] * a[2][q] - a[2][p] * a[1][q];
      c[1][m] = a[2][p] * a[0][q] - a[0][p] * a[2][q];
      c[2][m] = a[0][p] * a[1][q] - a[1][p] * a[0][q];
    }
  }
}

template <int Dim>
void cofactor_derivative(const double a[Dim][Dim], const double da[Dim][Dim], double dc[Dim][Dim]) {
  if constexpr (Dim == 2) {
    cofactor<2>(da, dc);  // linear in a
  } else {
    for (int m = 0; m < 3; ++m) {
      const int p = (m + 1) % 3, q = (m + 2) % 3;
      dc[0][m] = da[1][p] * a[2][q] - da[2][p] * a[1][q] + a[1][p] * da[2][q] - a[2][p] * da[1][q];
      dc[1][m] = da[2][p] * a[0][q] - da[0][p] * a[2][q] + a[2][p] * da[0][q] - a[0][p] * da[2][q];
      dc[2][m] = da[0][p] * a[1][q] - da[1][p] * a[0][q] + a[0][p] * da[1][q] - a[1][p] * da[0][q];
    }
  }
}

/// det A from its cofactors: sum_i A_i0 C_i0.
template <int Dim>
double determinant(const double a[Dim][Dim], const double c[Dim][Dim]) {
  double det = 0.0;
  for (int i = 0; i < Dim; ++i) det += a[i][0] * c[i][0];
  return det;
}

}  // namespace isospring::runtime
