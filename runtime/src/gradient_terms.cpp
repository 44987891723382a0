// Terms on a deformation gradient F = sum_a x_a h_a^T: shear (cells and strain points) and the
// strain points' volume term. Forces and Jacobian-vector products (runtime.h).
#include "terms.hpp"

namespace isospring::runtime {
namespace {

template <int Dim>
using Matrix = double[Dim][Dim];

// F (or dF from a direction dx) of one term.
template <int Dim>
void gradient_of(const Model& model, const GradientTerm& t, const double* x, Matrix<Dim>& f) {
  for (int i = 0; i < Dim; ++i)
    for (int m = 0; m < Dim; ++m) f[i][m] = 0.0;
  const int* points = model.points.data() + t.first;
  const double* h = model.gradients.data() + static_cast<long>(t.first) * Dim;
  for (int a = 0; a < t.count; ++a) {
    const double* xa = x + static_cast<long>(points[a]) * Dim;
    for (int i = 0; i < Dim; ++i)
      for (int m = 0; m < Dim; ++m) f[i][m] += xa[i] * h[a * Dim + m];
  }
}

// out_a -= P h_a for every particle a of the term.
template <int Dim>
void scatter(const Model& model, const GradientTerm& t, const Matrix<Dim>& p, double* out) {
  const int* points = model.points.data() + t.first;
  const double* h = model.gradients.data() + static_cast<long>(t.first) * Dim;
  for (int a = 0; a < t.count; ++a) {
    double* oa = out + static_cast<long>(points[a]) * Dim;
    for (int i = 0; i < Dim; ++i) {
      double sum = 0.0;
      for (int m = 0; m < Dim; ++m) sum += p[i][m] * h[a * Dim + m];
      oa[i] -= sum;
    }
  }
}

// Deviatoric part of the symmetric part of A^T B (so dev G = dev_sym(F, F) - dev(I)/2 = it / 2
// without the identity, whose deviator is zero).
template <int Dim>
void deviator_of_product(const Matrix<Dim>& a, const Matrix<Dim>& b, Matrix<Dim>& out) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      double sum = 0.0;
      for (int k = 0; k < Dim; ++k) sum += a[k][i] * b[k][j] + b[k][i] * a[k][j];
      out[i][j] = 0.5 * sum;
    }
  double trace = 0.0;
  for (int i = 0; i < Dim; ++i) trace += out[i][i];
  for (int i = 0; i < Dim; ++i) out[i][i] -= trace / Dim;
}

// P = 2 s (A B): the first Piola stress shape of the shear energy.
template <int Dim>
void add_product(double scale, const Matrix<Dim>& a, const Matrix<Dim>& b, Matrix<Dim>& out) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      double sum = 0.0;
      for (int k = 0; k < Dim; ++k) sum += a[i][k] * b[k][j];
      out[i][j] += scale * sum;
    }
}

// E = s |dev G|^2, G = (F^T F - I) / 2: dev G = 1/2 dev(F^T F); P = dE/dF = 2 s F dev G.
template <int Dim>
double shear_forces(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
                    double* f) {
  double energy = 0.0;
  for (const GradientTerm& t : terms) {
    Matrix<Dim> fg, d, p = {};
    gradient_of<Dim>(model, t, x, fg);
    deviator_of_product<Dim>(fg, fg, d);  // dev sym(F^T F) = dev(F^T F)
    double norm = 0.0;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        d[i][j] *= 0.5;  // dev G
        norm += d[i][j] * d[i][j];
      }
    energy += t.scale * norm;
    add_product<Dim>(2.0 * t.scale, fg, d, p);
    scatter<Dim>(model, t, p, f);
  }
  return energy;
}

// dP = 2 s (dF dev G + F dev sym(F^T dF)).
template <int Dim>
void shear_jvp(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
               const double* dx, double* df) {
  for (const GradientTerm& t : terms) {
    Matrix<Dim> fg, dfg, d, dd, dp = {};
    gradient_of<Dim>(model, t, x, fg);
    gradient_of<Dim>(model, t, dx, dfg);
    deviator_of_product<Dim>(fg, fg, d);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) d[i][j] *= 0.5;
    deviator_of_product<Dim>(fg, dfg, dd);  // dev sym(F^T dF)
    add_product<Dim>(2.0 * t.scale, dfg, d, dp);
    add_product<Dim>(2.0 * t.scale, fg, dd, dp);
    scatter<Dim>(model, t, dp, df);
  }
}

// E = 1/2 s (det F - 1)^2, P = s (det F - 1) cof F.
template <int Dim>
double volume_forces(const Model& model, const double* x, double* f) {
  double energy = 0.0;
  for (const GradientTerm& t : model.point_volumes) {
    Matrix<Dim> fg, c;
    gradient_of<Dim>(model, t, x, fg);
    cofactor<Dim>(fg, c);
    const double change = determinant<Dim>(fg, c) - 1.0;
    energy += 0.5 * t.scale * change * change;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) c[i][j] *= t.scale * change;
    scatter<Dim>(model, t, c, f);
  }
  return energy;
}

// dP = s ((cof F : dF) cof F + (det F - 1) d cof F).
template <int Dim>
void volume_jvp(const Model& model, const double* x, const double* dx, double* df) {
  for (const GradientTerm& t : model.point_volumes) {
    Matrix<Dim> fg, dfg, c, dc, dp;
    gradient_of<Dim>(model, t, x, fg);
    gradient_of<Dim>(model, t, dx, dfg);
    cofactor<Dim>(fg, c);
    cofactor_derivative<Dim>(fg, dfg, dc);
    const double change = determinant<Dim>(fg, c) - 1.0;
    double rate = 0.0;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) rate += c[i][j] * dfg[i][j];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) dp[i][j] = t.scale * (rate * c[i][j] + change * dc[i][j]);
    scatter<Dim>(model, t, dp, df);
  }
}

}  // namespace

double add_shear_forces(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
                        double* f) {
  return model.dimension == 2 ? shear_forces<2>(model, terms, x, f)
                              : shear_forces<3>(model, terms, x, f);
}

void add_shear_jvp(const Model& model, const std::vector<GradientTerm>& terms, const double* x,
                   const double* dx, double* df) {
  if (model.dimension == 2)
    shear_jvp<2>(model, terms, x, dx, df);
  else
    shear_jvp<3>(model, terms, x, dx, df);
}

double add_point_volume_forces(const Model& model, const double* x, double* f) {
  return model.dimension == 2 ? volume_forces<2>(model, x, f) : volume_forces<3>(model, x, f);
}

void add_point_volume_jvp(const Model& model, const double* x, const double* dx, double* df) {
  if (model.dimension == 2)
    volume_jvp<2>(model, x, dx, df);
  else
    volume_jvp<3>(model, x, dx, df);
}

}  // namespace isospring::runtime
