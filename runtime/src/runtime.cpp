// The C API (runtime.h): loading with errors as text, and the per-step calls, which neither
// allocate nor throw.
#include "isospring/runtime/runtime.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <sstream>

#include "corotation.hpp"
#include "json_fields.hpp"
#include "model.hpp"

namespace isospring::runtime {

Model parse_model(const std::string& text, const std::string& source) {
  const JsonFields fields(source);
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw LoadError(source + ": not valid JSON (" + e.what() + ")");
  }
  if (!document.is_object()) fields.fail("(document)", "must be a JSON object");
  const nlohmann::json& format = fields.require(document, "format", "");
  const int version = fields.integer(fields.require(document, "version", ""), "version");
  Model model;
  if (format == "isospring-spring-model") {
    if (version != 1) fields.fail("version", "unsupported version; this runtime reads version 1");
    read_network(document, fields, model);
  } else if (format == "isospring.reduced_spring_model") {
    if (version != 1) fields.fail("version", "unsupported version; this runtime reads version 1");
    read_reduced(document, fields, model);
  } else {
    fields.fail("format",
                "must be \"isospring-spring-model\" (model.json of `isospring calibrate`) or "
                "\"isospring.reduced_spring_model\" (`isospring export --format reduced`)");
  }
  return model;
}

namespace {

isospring_model* make(const std::string& text, const std::string& source, char* error,
                      size_t error_size) {
  try {
    auto* handle = new isospring_model{parse_model(text, source)};
    write_error(error, error_size, "");
    return handle;
  } catch (const LoadError& e) {
    write_error(error, error_size, e.what());
  } catch (const std::bad_alloc&) {
    write_error(error, error_size, source + ": out of memory while loading the model");
  } catch (const std::exception& e) {
    write_error(error, error_size, source + ": " + e.what());
  }
  return nullptr;
}

}  // namespace
}  // namespace isospring::runtime

using isospring::runtime::Model;

extern "C" {

isospring_model* isospring_model_load(const char* path, char* error, size_t error_size) {
  if (!path) {
    isospring::runtime::write_error(error, error_size, "isospring_model_load: path is NULL");
    return nullptr;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    isospring::runtime::write_error(
        error, error_size,
        std::string(path) + ": cannot open the model file (" + std::strerror(errno) + ")");
    return nullptr;
  }
  std::ostringstream text;
  text << in.rdbuf();
  std::string source = path;
  if (const size_t slash = source.find_last_of('/'); slash != std::string::npos)
    source = source.substr(slash + 1);
  return isospring::runtime::make(text.str(), source, error, error_size);
}

isospring_model* isospring_model_parse(const char* text, size_t length, const char* source,
                                       char* error, size_t error_size) {
  const std::string name = source ? source : "(model)";
  if (!text) {
    isospring::runtime::write_error(error, error_size, name + ": text is NULL");
    return nullptr;
  }
  return isospring::runtime::make(std::string(text, length), name, error, error_size);
}

void isospring_model_free(isospring_model* model) {
  delete model;
}

int isospring_model_kind(const isospring_model* m) {
  return m ? m->model.kind : -1;
}

int isospring_model_dimension(const isospring_model* m) {
  return m ? m->model.dimension : 0;
}

size_t isospring_model_particle_count(const isospring_model* m) {
  return m ? m->model.particles : 0;
}

size_t isospring_model_state_size(const isospring_model* m) {
  return m ? m->model.state_size() : 0;
}

const double* isospring_model_rest_positions(const isospring_model* m) {
  return m ? m->model.rest.data() : nullptr;
}

const double* isospring_model_masses(const isospring_model* m) {
  return m && !m->model.masses.empty() ? m->model.masses.data() : nullptr;
}

int isospring_model_particle_fixed(const isospring_model* m, size_t particle) {
  return m && particle < m->model.particles ? m->model.fixed[particle] : 0;
}

size_t isospring_model_term_count(const isospring_model* m, int term) {
  if (!m) return 0;
  const Model& model = m->model;
  switch (term) {
    case ISOSPRING_TERM_SPRINGS:
      return model.springs.size();
    case ISOSPRING_TERM_CELL_VOLUME:
      return model.cell_volumes.size();
    case ISOSPRING_TERM_CELL_SHEAR:
      return model.cell_shears.size();
    case ISOSPRING_TERM_POINT_VOLUME:
      return model.point_volumes.size();
    case ISOSPRING_TERM_POINT_SHEAR:
      return model.point_shears.size();
    case ISOSPRING_TERM_REDUCED:
      return model.basis_size;
    default:
      return 0;
  }
}

void isospring_model_set_terms(isospring_model* m, int mask) {
  if (m) m->model.mask = mask & ISOSPRING_TERM_ALL;
}

int isospring_model_terms(const isospring_model* m) {
  return m ? m->model.mask : 0;
}

double isospring_model_forces(const isospring_model* m, const double* x, const double* v,
                              double* f) {
  if (!m || !x || !f) return std::nan("");
  const Model& model = m->model;
  const size_t n = model.state_size();
  for (size_t e = 0; e < n; ++e) f[e] = 0.0;
  if (model.kind == ISOSPRING_MODEL_NETWORK)
    return isospring::runtime::network_forces(model, x, v, f);
  if (!(model.mask & ISOSPRING_TERM_REDUCED)) return 0.0;
  if (model.corotated()) return isospring::runtime::corotated_reduced_force(model, x, v, f);
  // f = -Lambda q - C_r qdot, E = 1/2 q^T Lambda q.
  double energy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    energy += 0.5 * model.eigenvalues[i] * x[i] * x[i];
    double sum = model.eigenvalues[i] * x[i];
    if (v)
      for (size_t j = 0; j < n; ++j) sum += model.damping[i * n + j] * v[j];
    f[i] = -sum;
  }
  return energy;
}

void isospring_model_force_jvp(const isospring_model* m, const double* x, const double* v,
                               const double* dx, const double* dv, double* df) {
  if (!m || !x || !df) return;
  const Model& model = m->model;
  const size_t n = model.state_size();
  for (size_t e = 0; e < n; ++e) df[e] = 0.0;
  if (model.kind == ISOSPRING_MODEL_NETWORK) {
    isospring::runtime::network_force_jvp(model, x, v, dx, v ? dv : nullptr, df);
    return;
  }
  if (!(model.mask & ISOSPRING_TERM_REDUCED)) return;
  if (model.corotated()) {
    isospring::runtime::corotated_reduced_jvp(model, x, dx, v ? dv : nullptr, df);
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    double sum = dx ? model.eigenvalues[i] * dx[i] : 0.0;
    if (v && dv)
      for (size_t j = 0; j < n; ++j) sum += model.damping[i * n + j] * dv[j];
    df[i] = -sum;
  }
}

double isospring_model_timestep(const isospring_model* m) {
  return m ? m->model.timestep : 0.0;
}

void isospring_model_reduce_force(const isospring_model* m, const double* particle_force,
                                  double* g) {
  if (!m || m->model.kind != ISOSPRING_MODEL_REDUCED || !particle_force || !g) return;
  const Model& model = m->model;
  const size_t r = model.basis_size, rows = model.basis.size() / r;
  for (size_t k = 0; k < r; ++k) g[k] = 0.0;
  for (size_t d = 0; d < rows; ++d) {
    const double fd = particle_force[d];
    if (fd == 0.0) continue;
    const double* row = model.basis.data() + d * r;
    for (size_t k = 0; k < r; ++k) g[k] += row[k] * fd;
  }
}

void isospring_model_expand(const isospring_model* m, const double* q, double* u) {
  if (!m || m->model.kind != ISOSPRING_MODEL_REDUCED || !q || !u) return;
  const Model& model = m->model;
  const size_t r = model.basis_size, rows = model.basis.size() / r;
  for (size_t d = 0; d < rows; ++d) {
    const double* row = model.basis.data() + d * r;
    double sum = 0.0;
    for (size_t k = 0; k < r; ++k) sum += row[k] * q[k];
    u[d] = sum;
  }
}

void isospring_model_reduced_step(isospring_model* m, const double* g, double* q, double* qdot) {
  if (!m || m->model.kind != ISOSPRING_MODEL_REDUCED || !g || !q || !qdot) return;
  Model& model = m->model;
  const size_t r = model.basis_size;
  const double dt = model.timestep;
  // rhs = dt (g - Lambda q - C_r qdot - dt Lambda qdot); qdot += A^-1 rhs; q += dt qdot.
  double* rhs = model.scratch.data();
  if (model.corotated()) {
    // The corotated forces replace -Lambda q - C_r qdot (docs/reduced_model.md).
    isospring::runtime::corotated_reduced_force(model, q, qdot, model.corot_g.data());
    for (size_t i = 0; i < r; ++i)
      rhs[i] = dt * (g[i] + model.corot_g[i] - dt * model.eigenvalues[i] * qdot[i]);
  }
  for (size_t i = 0; i < r && !model.corotated(); ++i) {
    double damping = 0.0;
    for (size_t j = 0; j < r; ++j) damping += model.damping[i * r + j] * qdot[j];
    const double lambda = model.eigenvalues[i];
    rhs[i] = dt * (g[i] - lambda * q[i] - damping - dt * lambda * qdot[i]);
  }
  for (size_t i = 0; i < r; ++i) {
    double sum = 0.0;
    for (size_t j = 0; j < r; ++j) sum += model.step_inverse[i * r + j] * rhs[j];
    qdot[i] += sum;
    q[i] += dt * qdot[i];
  }
}

}  // extern "C"
