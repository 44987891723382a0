// Forces and Jacobian-vector products of a network: the selected term kinds in turn.
#include "terms.hpp"

namespace isospring::runtime {

double network_forces(const Model& model, const double* x, const double* v, double* f) {
  double energy = 0.0;
  if (model.mask & 1) energy += add_spring_forces(model, x, v, f);
  if (model.mask & 2) energy += add_cell_volume_forces(model, x, f);
  if (model.mask & 4) energy += add_shear_forces(model, model.cell_shears, x, f);
  if (model.mask & 8) energy += add_point_volume_forces(model, x, f);
  if (model.mask & 16) energy += add_shear_forces(model, model.point_shears, x, f);
  return energy;
}

void network_force_jvp(const Model& model, const double* x, const double* v, const double* dx,
                       const double* dv, double* df) {
  if (model.mask & 1) add_spring_jvp(model, x, v, dx, dv, df);
  if (!dx) return;  // the other terms have no damping: no velocity derivative
  if (model.mask & 2) add_cell_volume_jvp(model, x, dx, df);
  if (model.mask & 4) add_shear_jvp(model, model.cell_shears, x, dx, df);
  if (model.mask & 8) add_point_volume_jvp(model, x, dx, df);
  if (model.mask & 16) add_shear_jvp(model, model.point_shears, x, dx, df);
}

}  // namespace isospring::runtime
