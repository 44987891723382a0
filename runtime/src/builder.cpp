// The C builder functions (runtime.h): a network from arrays, checked by model_build.cpp, each
// add all or nothing.
#include <cmath>
#include <cstring>
#include <new>

#include "isospring/runtime/runtime.h"
#include "model.hpp"

namespace isospring::runtime {
namespace {

// Runs `add` on the model; on a LoadError restores every term array to its size before.
template <typename Add>
int all_or_nothing(isospring_model* handle, const char* function, char* error, size_t size,
                   Add add) {
  if (!handle || handle->model.kind != ISOSPRING_MODEL_NETWORK) {
    write_error(error, size, std::string(function) + ": not a network model");
    return 0;
  }
  Model& m = handle->model;
  const size_t sizes[7] = {m.springs.size(),       m.cell_volumes.size(), m.cell_shears.size(),
                           m.point_volumes.size(), m.point_shears.size(), m.points.size(),
                           m.gradients.size()};
  try {
    add(m, Fields(function));
    write_error(error, size, "");
    return 1;
  } catch (const std::exception& e) {
    write_error(error, size, e.what());
  }
  m.springs.resize(sizes[0]);
  m.cell_volumes.resize(sizes[1]);
  m.cell_shears.resize(sizes[2]);
  m.point_volumes.resize(sizes[3]);
  m.point_shears.resize(sizes[4]);
  m.points.resize(sizes[5]);
  m.gradients.resize(sizes[6]);
  return 0;
}

std::string entry(const char* name, size_t k) {
  return std::string(name) + "[" + std::to_string(k) + "].";
}

}  // namespace
}  // namespace isospring::runtime

using isospring::runtime::entry;
using isospring::runtime::Fields;
using isospring::runtime::Model;

extern "C" {

isospring_model* isospring_model_create(int dimension, size_t particles,
                                        const double* rest_positions, const double* masses,
                                        const unsigned char* fixed, char* error,
                                        size_t error_size) {
  try {
    const Fields fields("isospring_model_create");
    if (!rest_positions || !masses) fields.fail("rest_positions, masses", "must not be NULL");
    auto* handle = new isospring_model{};
    try {
      add_particles(handle->model, dimension, particles, rest_positions, masses, fixed, fields);
    } catch (...) {
      delete handle;
      throw;
    }
    isospring::runtime::write_error(error, error_size, "");
    return handle;
  } catch (const std::exception& e) {
    isospring::runtime::write_error(error, error_size, e.what());
  }
  return nullptr;
}

isospring_model* isospring_model_create_reduced(
    int dimension, size_t particles, const double* rest_positions, const unsigned char* fixed,
    size_t r, double timestep, const double* eigenvalues, const double* damping,
    const double* step_inverse, const double* basis, char* error, size_t error_size) {
  try {
    const Fields fields("isospring_model_create_reduced");
    if (!rest_positions || !eigenvalues || !damping || !step_inverse || !basis)
      fields.fail("rest_positions, eigenvalues, damping, step_inverse, basis", "must not be NULL");
    const std::vector<double> masses(particles, 1.0);  // checked as particles, not kept
    Model model;
    add_particles(model, dimension, particles, rest_positions, masses.data(), fixed, fields);
    if (r == 0) fields.fail("r", "must be at least 1");
    if (!(timestep > 0) || !std::isfinite(timestep)) fields.fail("timestep", "must be > 0");
    const size_t rows = particles * static_cast<size_t>(dimension);
    auto finite = [&](const double* values, size_t count, const char* name) {
      for (size_t k = 0; k < count; ++k)
        if (!std::isfinite(values[k]))
          fields.fail(std::string(name) + "[" + std::to_string(k) + "]", "must be finite");
      return std::vector<double>(values, values + count);
    };
    model.kind = ISOSPRING_MODEL_REDUCED;
    model.masses.clear();
    model.basis_size = r;
    model.timestep = timestep;
    model.eigenvalues = finite(eigenvalues, r, "eigenvalues");
    model.damping = finite(damping, r * r, "damping");
    model.step_inverse = finite(step_inverse, r * r, "step_inverse");
    model.basis = finite(basis, rows * r, "basis");
    model.scratch.assign(r, 0.0);
    auto* handle = new isospring_model{std::move(model)};
    isospring::runtime::write_error(error, error_size, "");
    return handle;
  } catch (const std::exception& e) {
    isospring::runtime::write_error(error, error_size, e.what());
  }
  return nullptr;
}

int isospring_model_add_springs(isospring_model* model, size_t count, const int* ends,
                                const double* stiffness, const double* damping,
                                const double* rest_lengths, char* error, size_t error_size) {
  return isospring::runtime::all_or_nothing(
      model, "isospring_model_add_springs", error, error_size, [&](Model& m, const Fields& f) {
        if (count > 0 && (!ends || !stiffness || !rest_lengths))
          f.fail("ends, stiffness, rest_lengths", "must not be NULL");
        for (size_t s = 0; s < count; ++s) {
          isospring::runtime::SpringTerm t;
          t.i = ends[2 * s];
          t.j = ends[2 * s + 1];
          t.stiffness = stiffness[s];
          t.damping = damping ? damping[s] : 0.0;
          t.rest_length = rest_lengths[s];
          add_spring(m, t, f, entry("springs", s));
        }
      });
}

int isospring_model_add_cells(isospring_model* model, int term, size_t count, const int* corners,
                              const double* moduli, const double* rest_volumes, char* error,
                              size_t error_size) {
  return isospring::runtime::all_or_nothing(
      model, "isospring_model_add_cells", error, error_size, [&](Model& m, const Fields& f) {
        if (term != ISOSPRING_TERM_CELL_VOLUME && term != ISOSPRING_TERM_CELL_SHEAR)
          f.fail("term", "must be ISOSPRING_TERM_CELL_VOLUME or ISOSPRING_TERM_CELL_SHEAR");
        if (count > 0 && (!corners || !moduli || !rest_volumes))
          f.fail("corners, moduli, rest_volumes", "must not be NULL");
        const size_t n = size_t{1} << m.dimension;
        for (size_t c = 0; c < count; ++c)
          add_cell(m, term == ISOSPRING_TERM_CELL_SHEAR, corners + c * n, moduli[c],
                   rest_volumes[c], f, entry("cells", c));
      });
}

int isospring_model_add_points(isospring_model* model, int term, size_t count,
                               const size_t* offsets, const int* particles, const double* gradients,
                               const double* moduli, const double* rest_volumes, char* error,
                               size_t error_size) {
  return isospring::runtime::all_or_nothing(
      model, "isospring_model_add_points", error, error_size, [&](Model& m, const Fields& f) {
        if (term != ISOSPRING_TERM_POINT_VOLUME && term != ISOSPRING_TERM_POINT_SHEAR)
          f.fail("term", "must be ISOSPRING_TERM_POINT_VOLUME or ISOSPRING_TERM_POINT_SHEAR");
        if (count > 0 && (!offsets || !particles || !gradients || !moduli || !rest_volumes))
          f.fail("offsets, particles, gradients, moduli, rest_volumes", "must not be NULL");
        for (size_t k = 0; k < count; ++k) {
          if (offsets[k + 1] < offsets[k]) f.fail(entry("offsets", k + 1), "must not decrease");
          add_point(m, term == ISOSPRING_TERM_POINT_SHEAR, particles + offsets[k],
                    gradients + offsets[k] * static_cast<size_t>(m.dimension),
                    static_cast<int>(offsets[k + 1] - offsets[k]), moduli[k], rest_volumes[k], f,
                    entry("points", k));
        }
      });
}

}  // extern "C"
