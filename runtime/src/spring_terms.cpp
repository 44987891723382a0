// Springs and their damping: forces and Jacobian-vector products (runtime.h).
#include <cmath>

#include "terms.hpp"

namespace isospring::runtime {

template <int Dim>
double spring_forces(const Model& model, const double* x, const double* v, double* f) {
  double energy = 0.0;
  for (const SpringTerm& s : model.springs) {
    const long i = static_cast<long>(s.i) * Dim, j = static_cast<long>(s.j) * Dim;
    double l[Dim];
    double length_squared = 0.0;
    for (int c = 0; c < Dim; ++c) {
      l[c] = x[i + c] - x[j + c];
      length_squared += l[c] * l[c];
    }
    if (length_squared == 0.0) continue;  // no direction: no force (as analysis)
    const double length = std::sqrt(length_squared);
    const double stretch = length - s.rest_length;
    energy += 0.5 * s.stiffness * stretch * stretch;
    double scale = -s.stiffness * stretch / length;
    if (v && s.damping != 0.0) {
      double rate = 0.0;  // l . dl/dt
      for (int c = 0; c < Dim; ++c) rate += l[c] * (v[i + c] - v[j + c]);
      scale -= s.damping * rate / length_squared;
    }
    for (int c = 0; c < Dim; ++c) {
      f[i + c] += scale * l[c];
      f[j + c] -= scale * l[c];
    }
  }
  return energy;
}

// df_i = -k [(1 - L0/|l|) dl + L0 (l . dl) l / |l|^3]
//        - c [((dl . l') + (l . dl')) l / |l|^2 + (l . l') dl / |l|^2 - 2 (l . l')(l . dl) l /
//        |l|^4]
template <int Dim>
void spring_jvp(const Model& model, const double* x, const double* v, const double* dx,
                const double* dv, double* df) {
  for (const SpringTerm& s : model.springs) {
    const long i = static_cast<long>(s.i) * Dim, j = static_cast<long>(s.j) * Dim;
    double l[Dim], dl[Dim];
    double length_squared = 0.0, l_dl = 0.0;
    for (int c = 0; c < Dim; ++c) {
      l[c] = x[i + c] - x[j + c];
      dl[c] = dx ? dx[i + c] - dx[j + c] : 0.0;
      length_squared += l[c] * l[c];
      l_dl += l[c] * dl[c];
    }
    if (length_squared == 0.0) continue;
    const double length = std::sqrt(length_squared);
    const double ratio = s.rest_length / length;
    double along = -s.stiffness * ratio * l_dl / length_squared;  // coefficient of l
    double across = -s.stiffness * (1.0 - ratio);                 // coefficient of dl
    if (v && s.damping != 0.0) {
      double rate = 0.0, d_rate = 0.0;  // l . l', d(l . l')
      for (int c = 0; c < Dim; ++c) {
        const double lv = v[i + c] - v[j + c];
        rate += l[c] * lv;
        d_rate += dl[c] * lv + (dv ? l[c] * (dv[i + c] - dv[j + c]) : 0.0);
      }
      const double c_over = s.damping / length_squared;
      along -= c_over * (d_rate - 2.0 * rate * l_dl / length_squared);
      across -= c_over * rate;
    }
    for (int c = 0; c < Dim; ++c) {
      const double d = along * l[c] + across * dl[c];
      df[i + c] += d;
      df[j + c] -= d;
    }
  }
}

double add_spring_forces(const Model& model, const double* x, const double* v, double* f) {
  return model.dimension == 2 ? spring_forces<2>(model, x, v, f) : spring_forces<3>(model, x, v, f);
}

void add_spring_jvp(const Model& model, const double* x, const double* v, const double* dx,
                    const double* dv, double* df) {
  if (model.dimension == 2)
    spring_jvp<2>(model, x, v, dx, dv, df);
  else
    spring_jvp<3>(model, x, v, dx, dv, df);
}

}  // namespace isospring::runtime
