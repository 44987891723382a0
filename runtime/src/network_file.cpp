// model.json ("isospring-spring-model", version 1) into the runtime's arrays: the JSON types are
// checked here, the values by model_build.cpp; every problem names the file and the field.
#include "json_fields.hpp"

namespace isospring::runtime {
namespace {

using nlohmann::json;

std::string at(const std::string& name, size_t index) {
  return name + "[" + std::to_string(index) + "]";
}

void read_particles(const json& document, const JsonFields& fields, int dim, Model& model) {
  const json& particles = fields.require(document, "particles", "");
  if (!particles.is_array() || particles.empty())
    fields.fail("particles", "must be a non-empty array");
  std::vector<double> rest, masses;
  std::vector<unsigned char> fixed;
  for (size_t p = 0; p < particles.size(); ++p) {
    const std::string path = at("particles", p) + ".";
    const json& item = particles[p];
    const json& x = fields.require(item, "x", path);
    if (!x.is_array() || (x.size() != 3 && x.size() != static_cast<size_t>(dim)))
      fields.fail(path + "x", "must be an array of 3 coordinates");
    for (int c = 0; c < dim; ++c)
      rest.push_back(fields.number(x[static_cast<size_t>(c)], path + at("x", c)));
    masses.push_back(fields.number(fields.require(item, "mass", path), path + "mass"));
    bool held = false;
    if (item.contains("fixed")) {
      if (!item["fixed"].is_boolean()) fields.fail(path + "fixed", "must be true or false");
      held = item["fixed"].get<bool>();
    }
    fixed.push_back(held ? 1 : 0);
  }
  add_particles(model, dim, particles.size(), rest.data(), masses.data(), fixed.data(), fields);
}

void read_springs(const json& document, const JsonFields& fields, Model& model) {
  const json& springs = fields.require(document, "springs", "");
  if (!springs.is_array()) fields.fail("springs", "must be an array");
  model.springs.reserve(springs.size());
  for (size_t s = 0; s < springs.size(); ++s) {
    const std::string path = at("springs", s) + ".";
    const json& item = springs[s];
    SpringTerm t;
    t.i = fields.integer(fields.require(item, "i", path), path + "i");
    t.j = fields.integer(fields.require(item, "j", path), path + "j");
    t.stiffness = fields.number(fields.require(item, "k", path), path + "k");
    t.damping = item.contains("c") ? fields.number(item["c"], path + "c") : 0.0;
    t.rest_length = fields.number(fields.require(item, "L0", path), path + "L0");
    add_spring(model, t, fields, path);
  }
}

void read_volume(const json& item, const std::string& path, const JsonFields& fields,
                 Model& model) {
  const bool shear = item.contains("mu");
  if (item.contains("kappa") == shear)
    fields.fail(path.substr(0, path.size() - 1),
                "give either \"kappa\" (a volume term) or \"mu\" (a shear term)");
  const char* key = shear ? "mu" : "kappa";
  const double modulus = fields.number(item[key], path + key);
  const double v0 = fields.number(fields.require(item, "V0", path), path + "V0");
  const auto dim = static_cast<size_t>(model.dimension);
  std::vector<int> ids;
  if (item.contains("points")) {
    // A strain point: F = sum_a x_{points[a]} gradients[a]^T.
    const json& points = item["points"];
    const json& gradients = fields.require(item, "gradients", path);
    if (!points.is_array() || points.empty() || !gradients.is_array() ||
        gradients.size() != points.size())
      fields.fail(path + "points", "must list one particle per row of \"gradients\"");
    std::vector<double> h;
    for (size_t a = 0; a < points.size(); ++a) {
      ids.push_back(fields.integer(points[a], path + at("points", a)));
      const json& row = fields.array(gradients[a], path + at("gradients", a), dim);
      for (size_t c = 0; c < dim; ++c)
        h.push_back(fields.number(row[c], path + at("gradients", a) + at("", c)));
    }
    add_point(model, shear, ids.data(), h.data(), static_cast<int>(ids.size()), modulus, v0, fields,
              path);
    return;
  }
  const size_t count = size_t{1} << dim;
  const json& corners = fields.require(item, "particles", path);
  if (!corners.is_array() || corners.size() != count)
    fields.fail(path + "particles",
                "must list the " + std::to_string(count) + " corners of the cell in tensor order");
  for (size_t a = 0; a < count; ++a)
    ids.push_back(fields.integer(corners[a], path + at("particles", a)));
  add_cell(model, shear, ids.data(), modulus, v0, fields, path);
}

}  // namespace

void read_network(const json& document, const JsonFields& fields, Model& model) {
  const int dim =
      document.contains("dimension") ? fields.integer(document["dimension"], "dimension") : 3;
  if (dim != 2 && dim != 3) fields.fail("dimension", "must be 2 or 3");
  read_particles(document, fields, dim, model);
  read_springs(document, fields, model);
  if (!document.contains("volumes")) return;
  const json& volumes = document["volumes"];
  if (!volumes.is_array()) fields.fail("volumes", "must be an array");
  for (size_t v = 0; v < volumes.size(); ++v) {
    if (!volumes[v].is_object()) fields.fail(at("volumes", v), "must be an object");
    read_volume(volumes[v], at("volumes", v) + ".", fields, model);
  }
}

}  // namespace isospring::runtime
