// The reduced model document ("isospring.reduced_spring_model", version 1,
// docs/reduced_model.md) into the runtime's arrays.
#include "corotation.hpp"
#include "json_fields.hpp"

namespace isospring::runtime {
namespace {

using nlohmann::json;

// An rows x cols matrix given as rows, row-major into out.
void read_matrix(const json& document, const char* key, size_t rows, size_t cols,
                 const JsonFields& fields, std::vector<double>& out) {
  const json& value = fields.array(fields.require(document, key, ""), key, rows);
  out.reserve(rows * cols);
  for (size_t r = 0; r < rows; ++r) {
    const std::string row = std::string(key) + "[" + std::to_string(r) + "]";
    const json& entries = fields.array(value[r], row, cols);
    for (size_t c = 0; c < cols; ++c)
      out.push_back(fields.number(entries[c], row + "[" + std::to_string(c) + "]"));
  }
}

}  // namespace

void read_reduced(const json& document, const JsonFields& fields, Model& model) {
  model.kind = 1;
  model.dimension = fields.integer(fields.require(document, "dimension", ""), "dimension");
  if (model.dimension != 2 && model.dimension != 3) fields.fail("dimension", "must be 2 or 3");
  model.timestep = fields.number(fields.require(document, "timestep", ""), "timestep");
  if (!(model.timestep > 0)) fields.fail("timestep", "must be > 0");
  const int particles = fields.integer(fields.require(document, "particles", ""), "particles");
  if (particles < 1) fields.fail("particles", "must be a positive count");
  model.particles = static_cast<size_t>(particles);
  const auto dim = static_cast<size_t>(model.dimension);
  read_matrix(document, "rest_positions", model.particles, dim, fields, model.rest);
  model.fixed.assign(model.particles, 0);
  if (document.contains("fixed")) {
    const json& fixed = document["fixed"];
    if (!fixed.is_array()) fields.fail("fixed", "must be an array of particle indices");
    for (size_t k = 0; k < fixed.size(); ++k)
      model.fixed[static_cast<size_t>(
          fields.index(fixed[k], "fixed[" + std::to_string(k) + "]", model.particles))] = 1;
  }
  const json& eigenvalues = fields.require(document, "eigenvalues", "");
  if (!eigenvalues.is_array() || eigenvalues.empty())
    fields.fail("eigenvalues", "must be a non-empty array (one per basis vector)");
  model.basis_size = eigenvalues.size();
  for (size_t k = 0; k < eigenvalues.size(); ++k)
    model.eigenvalues.push_back(
        fields.number(eigenvalues[k], "eigenvalues[" + std::to_string(k) + "]"));
  const size_t r = model.basis_size;
  read_matrix(document, "damping", r, r, fields, model.damping);
  read_matrix(document, "step_inverse", r, r, fields, model.step_inverse);
  read_matrix(document, "basis", model.particles * dim, r, fields, model.basis);
  model.scratch.assign(r, 0.0);
  if (document.contains("corotation")) {
    read_corotation(document["corotation"], fields, model);
    model.corot_g.assign(r, 0.0);
  }
}

}  // namespace isospring::runtime
