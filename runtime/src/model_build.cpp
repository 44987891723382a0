// Checked additions to a network model: the one place that decides what a valid particle,
// spring, cell or strain point is (the same rules as io's reader, io/model_file.hpp), for the
// file reader and the C builder functions alike.
#include <cmath>

#include "terms.hpp"

namespace isospring::runtime {
namespace {

void check_index(const Model& model, int q, const Fields& fields, const std::string& field) {
  if (q < 0 || static_cast<size_t>(q) >= model.particles)
    fields.fail(field, "particle index " + std::to_string(q) + " out of range [0, " +
                           std::to_string(model.particles) + ")");
}

void check_modulus(bool shear, double modulus, double rest_volume, const Fields& fields,
                   const std::string& path) {
  const std::string key = path + (shear ? "mu" : "kappa");
  if (!std::isfinite(modulus) || modulus < 0) fields.fail(key, "must be finite and >= 0");
  if (!std::isfinite(rest_volume) || rest_volume == 0)
    fields.fail(path + "V0", "must be finite and non-zero");
}

}  // namespace

void add_particles(Model& model, int dimension, size_t count, const double* rest,
                   const double* masses, const unsigned char* fixed, const Fields& fields) {
  if (dimension != 2 && dimension != 3) fields.fail("dimension", "must be 2 or 3");
  if (count == 0) fields.fail("particles", "must be a non-empty array");
  model.kind = 0;
  model.dimension = dimension;
  model.particles = count;
  for (size_t p = 0; p < count; ++p) {
    const std::string path = "particles[" + std::to_string(p) + "].";
    for (int c = 0; c < dimension; ++c)
      if (!std::isfinite(rest[p * static_cast<size_t>(dimension) + static_cast<size_t>(c)]))
        fields.fail(path + "x", "must be finite");
    const bool held = fixed && fixed[p] != 0;
    if (!std::isfinite(masses[p]) || masses[p] < 0 || (masses[p] == 0 && !held))
      fields.fail(path + "mass", "must be > 0 for a free particle (>= 0 when fixed)");
  }
  model.rest.assign(rest, rest + count * static_cast<size_t>(dimension));
  model.masses.assign(masses, masses + count);
  model.fixed.assign(count, 0);
  for (size_t p = 0; fixed && p < count; ++p) model.fixed[p] = fixed[p] != 0 ? 1 : 0;
}

void add_spring(Model& model, const SpringTerm& s, const Fields& fields, const std::string& path) {
  check_index(model, s.i, fields, path + "i");
  check_index(model, s.j, fields, path + "j");
  if (s.i == s.j) fields.fail(path + "j", "a spring must connect two different particles");
  if (!std::isfinite(s.stiffness) || s.stiffness < 0)
    fields.fail(path + "k", "must be finite and >= 0");
  if (!std::isfinite(s.damping) || s.damping < 0)
    fields.fail(path + "c", "must be finite and >= 0");
  if (!std::isfinite(s.rest_length) || s.rest_length <= 0)
    fields.fail(path + "L0", "must be finite and > 0");
  model.springs.push_back(s);
}

void add_cell(Model& model, bool shear, const int* corners, double modulus, double rest_volume,
              const Fields& fields, const std::string& path) {
  const int dim = model.dimension, count = 1 << dim;
  for (int a = 0; a < count; ++a)
    check_index(model, corners[a], fields, path + "particles[" + std::to_string(a) + "]");
  check_modulus(shear, modulus, rest_volume, fields, path);
  if (!shear) {
    CellVolumeTerm term;
    for (int a = 0; a < count; ++a) term.corners[a] = corners[a];
    term.factor = modulus / std::abs(rest_volume);
    term.rest_volume = rest_volume;
    model.cell_volumes.push_back(term);
    return;
  }
  // A shear term on F = sum_a x_a h_a^T with h_a = b_a / V0, b the rest volume gradient and V0
  // the corners' rest volume (as analysis::cell_shear_energy computes them).
  double cx[24], b[24];
  for (int a = 0; a < count; ++a)
    for (int c = 0; c < dim; ++c)
      cx[a * dim + c] = model.rest[static_cast<size_t>(corners[a]) * dim + c];
  const double v0 = cell_volume(cx, dim, b);
  if (!(std::abs(v0) > 0.0)) fields.fail(path + "particles", "the cell's rest volume is zero");
  GradientTerm term;
  term.first = static_cast<int>(model.points.size());
  term.count = count;
  term.scale = modulus * std::abs(v0);
  for (int a = 0; a < count; ++a) {
    model.points.push_back(corners[a]);
    for (int c = 0; c < dim; ++c) model.gradients.push_back(b[a * dim + c] / v0);
  }
  model.cell_shears.push_back(term);
}

void add_point(Model& model, bool shear, const int* particles, const double* gradients, int count,
               double modulus, double rest_volume, const Fields& fields, const std::string& path) {
  const int dim = model.dimension;
  if (count < 1) fields.fail(path + "points", "must list at least one particle");
  for (int a = 0; a < count; ++a) {
    check_index(model, particles[a], fields, path + "points[" + std::to_string(a) + "]");
    for (int c = 0; c < dim; ++c)
      if (!std::isfinite(gradients[a * dim + c]))
        fields.fail(path + "gradients[" + std::to_string(a) + "]", "must be finite");
  }
  check_modulus(shear, modulus, rest_volume, fields, path);
  GradientTerm term;
  term.first = static_cast<int>(model.points.size());
  term.count = count;
  term.scale = modulus * std::abs(rest_volume);
  model.points.insert(model.points.end(), particles, particles + count);
  model.gradients.insert(model.gradients.end(), gradients, gradients + count * dim);
  (shear ? model.point_shears : model.point_volumes).push_back(term);
}

}  // namespace isospring::runtime
