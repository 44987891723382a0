#include "isospring/io/model_file.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "case_file_json.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
using nlohmann::json;
using nurbs::InputError;

namespace {
constexpr const char* kFormat = "isospring-spring-model";
constexpr int kVersion = 1;

std::string describe(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

/// Reads one document field with its path for messages ("model.json: springs[3].k: ...").
class FieldReader {
 public:
  FieldReader(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw InputError(source_ + ": " + field + ": " + problem);
  }

  const json& require(const json& object, const std::string& key, const std::string& path) const {
    if (!object.contains(key)) fail(path + key, "missing; add it (see the model.json schema)");
    return object.at(key);
  }

  // Type checks are case_json::Field's, the one wording of every io reader.
  double number(const json& value, const std::string& field) const {
    return case_json::Field(value, source_, field).number();
  }

  int integer(const json& value, const std::string& field) const {
    return case_json::Field(value, source_, field).integer();
  }

  Eigen::Vector3d vector(const json& value, const std::string& field, int dimension) const {
    if (!value.is_array() || (value.size() != 3 && value.size() != static_cast<size_t>(dimension)))
      fail(field, "must be an array of 3 coordinates");
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (size_t c = 0; c < value.size(); ++c)
      x[static_cast<int>(c)] = number(value[c], field + "[" + std::to_string(c) + "]");
    return x;
  }

 private:
  std::string source_;
};

void check_keys(const FieldReader& reader, const json& object, const std::string& path,
                const std::set<std::string>& known) {
  case_json::reject_unknown_fields(object, std::vector<std::string>(known.begin(), known.end()),
                                   reader.source() + ": " + path);
}

// The document's object, known top-level keys, format and version.
void check_document(const FieldReader& reader, const json& document) {
  if (!document.is_object()) reader.fail("(document)", "must be a JSON object");
  check_keys(reader, document, "",
             {"format", "version", "units", "dimension", "particles", "springs", "volumes",
              "provenance", "gravity", "load_cases"});
  const json& format = reader.require(document, "format", "");
  if (format != kFormat)
    reader.fail("format", std::string("must be \"") + kFormat +
                              "\"; this file is not an isospring spring model");
  if (reader.integer(reader.require(document, "version", ""), "version") != kVersion)
    reader.fail("version", "unsupported version; this isospring reads version 1");
}

// Item `index` of the array `list` ("springs") as an object with only `known` keys; `path`
// gets its field prefix ("springs[3].").
const json& list_item(const FieldReader& reader, const json& array, const std::string& list,
                      size_t index, const std::set<std::string>& known, std::string& path) {
  path = list + "[" + std::to_string(index) + "].";
  const json& item = array[index];
  if (!item.is_object()) reader.fail(path.substr(0, path.size() - 1), "must be an object");
  check_keys(reader, item, path, known);
  return item;
}

void read_particles(const FieldReader& reader, const json& document,
                    analysis::SpringNetwork& network) {
  const json& particles = reader.require(document, "particles", "");
  if (!particles.is_array() || particles.empty())
    reader.fail("particles", "must be a non-empty array");
  for (size_t p = 0; p < particles.size(); ++p) {
    std::string path;
    const json& item = list_item(reader, particles, "particles", p, {"x", "mass", "fixed"}, path);
    network.positions.push_back(
        reader.vector(reader.require(item, "x", path), path + "x", network.dimension));
    network.masses.push_back(reader.number(reader.require(item, "mass", path), path + "mass"));
    bool fixed = false;
    if (item.contains("fixed")) {
      if (!item["fixed"].is_boolean()) reader.fail(path + "fixed", "must be true or false");
      fixed = item["fixed"].get<bool>();
    }
    network.fixed.push_back(fixed);
  }
}

void read_springs(const FieldReader& reader, const json& document,
                  analysis::SpringNetwork& network) {
  const json& springs = reader.require(document, "springs", "");
  if (!springs.is_array()) reader.fail("springs", "must be an array");
  for (size_t s = 0; s < springs.size(); ++s) {
    std::string path;
    const json& item =
        list_item(reader, springs, "springs", s, {"i", "j", "k", "c", "L0", "group"}, path);
    analysis::Spring spring;
    spring.i = reader.integer(reader.require(item, "i", path), path + "i");
    spring.j = reader.integer(reader.require(item, "j", path), path + "j");
    spring.stiffness = reader.number(reader.require(item, "k", path), path + "k");
    spring.damping = item.contains("c") ? reader.number(item["c"], path + "c") : 0.0;
    spring.rest_length = reader.number(reader.require(item, "L0", path), path + "L0");
    spring.group = item.contains("group") ? reader.integer(item["group"], path + "group") : -1;
    network.springs.push_back(spring);
  }
}

// A strain point's particles and their basis gradients, one row of `dimension` each.
void read_strain_point(const FieldReader& reader, const json& item, const std::string& path,
                       int dimension, analysis::VolumeTerm& term) {
  const json& points = item["points"];
  const json& gradients = reader.require(item, "gradients", path);
  if (!points.is_array() || points.empty() || !gradients.is_array() ||
      gradients.size() != points.size())
    reader.fail(path + "points", "must list one particle per row of \"gradients\"");
  for (size_t a = 0; a < points.size(); ++a) {
    const std::string at = "[" + std::to_string(a) + "]";
    term.points.push_back(reader.integer(points[a], path + "points" + at));
    const json& row = gradients[a];
    if (!row.is_array() || row.size() != static_cast<size_t>(dimension))
      reader.fail(path + "gradients" + at,
                  "must have " + std::to_string(dimension) + " components");
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int c = 0; c < dimension; ++c)
      g[c] = reader.number(row[static_cast<size_t>(c)],
                           path + "gradients" + at + "[" + std::to_string(c) + "]");
    term.gradients.push_back(g);
  }
}

// A cell's corners in tensor order.
void read_cell_corners(const FieldReader& reader, const json& item, const std::string& path,
                       int dimension, analysis::VolumeTerm& term) {
  const size_t corners = dimension == 2 ? 4 : 8;
  const json& particles_of = reader.require(item, "particles", path);
  if (!particles_of.is_array() || particles_of.size() != corners)
    reader.fail(path + "particles", "must list the " + std::to_string(corners) +
                                        " corners of the cell in tensor order");
  for (size_t a = 0; a < corners; ++a)
    term.particles[a] =
        reader.integer(particles_of[a], path + "particles[" + std::to_string(a) + "]");
}

void read_volumes(const FieldReader& reader, const json& document,
                  analysis::SpringNetwork& network) {
  if (!document.contains("volumes")) return;
  const json& volumes = document["volumes"];
  if (!volumes.is_array()) reader.fail("volumes", "must be an array");
  for (size_t v = 0; v < volumes.size(); ++v) {
    std::string path;
    const json& item =
        list_item(reader, volumes, "volumes", v,
                  {"particles", "points", "gradients", "kappa", "mu", "V0", "group"}, path);
    // "kappa": a volume term; "mu": a shear term (deviatoric energy of the mean strain).
    if (item.contains("kappa") == item.contains("mu"))
      reader.fail(path.substr(0, path.size() - 1),
                  "give either \"kappa\" (a volume term) or \"mu\" (a shear term)");
    analysis::VolumeTerm term;
    if (item.contains("points"))
      read_strain_point(reader, item, path, network.dimension, term);
    else
      read_cell_corners(reader, item, path, network.dimension, term);
    const char* key = item.contains("mu") ? "mu" : "kappa";
    if (item.contains("mu")) term.kind = analysis::CellEnergy::kShear;
    term.modulus = reader.number(item[key], path + key);
    term.rest_volume = reader.number(reader.require(item, "V0", path), path + "V0");
    term.group = item.contains("group") ? reader.integer(item["group"], path + "group") : -1;
    network.volumes.push_back(term);
  }
}

// One load case's forces, [particle, fx, fy(, fz)] rows.
void read_forces(const FieldReader& reader, const json& item, const std::string& path,
                 const analysis::SpringNetwork& network, ModelLoadCase& load) {
  const json& forces = reader.require(item, "forces", path);
  if (!forces.is_array()) reader.fail(path + "forces", "must be an array");
  for (size_t k = 0; k < forces.size(); ++k) {
    const std::string where = path + "forces[" + std::to_string(k) + "]";
    const json& f = forces[k];
    if (!f.is_array() || f.size() != static_cast<size_t>(network.dimension) + 1)
      reader.fail(
          where, "must be [particle, fx, fy" + std::string(network.dimension == 3 ? ", fz]" : "]"));
    const int particle = reader.integer(f[0], where + "[0]");
    if (particle < 0 || particle >= static_cast<int>(network.positions.size()))
      reader.fail(where + "[0]", "particle index " + std::to_string(particle) +
                                     " out of range [0, " +
                                     std::to_string(network.positions.size()) + ")");
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (int c = 0; c < network.dimension; ++c)
      force[c] =
          reader.number(f[static_cast<size_t>(c) + 1], where + "[" + std::to_string(c + 1) + "]");
    load.forces.emplace_back(particle, force);
  }
}

void read_load_cases(const FieldReader& reader, const json& document, SpringModel& model) {
  if (!document.contains("load_cases")) return;
  const json& cases = document["load_cases"];
  if (!cases.is_array()) reader.fail("load_cases", "must be an array");
  for (size_t l = 0; l < cases.size(); ++l) {
    std::string path;
    const json& item = list_item(reader, cases, "load_cases", l, {"id", "forces"}, path);
    ModelLoadCase load;
    const json& id = reader.require(item, "id", path);
    if (!id.is_string()) reader.fail(path + "id", "must be a string");
    load.id = id.get<std::string>();
    read_forces(reader, item, path, model.network, load);
    model.load_cases.push_back(std::move(load));
  }
}

}  // namespace

json default_model_units() {
  return json{{"length", "m"}, {"mass", "kg"}, {"time", "s"}, {"force", "N"}};
}

std::string check_spring_network(const analysis::SpringNetwork& network) {
  const size_t n = network.positions.size();
  if (network.dimension != 2 && network.dimension != 3)
    return "dimension: must be 2 or 3 (got " + std::to_string(network.dimension) + ")";
  if (network.masses.size() != n || network.fixed.size() != n)
    return "particles: positions, masses and fixed flags have different sizes";
  for (size_t p = 0; p < n; ++p) {
    const std::string where = "particles[" + std::to_string(p) + "]";
    if (!network.positions[p].allFinite()) return where + ".x: must be finite";
    const double m = network.masses[p];
    if (!std::isfinite(m) || m < 0 || (m == 0 && !network.fixed[p]))
      return where + ".mass: must be finite and > 0 for a free particle (got " + describe(m) + ")";
  }
  for (size_t s = 0; s < network.springs.size(); ++s) {
    const analysis::Spring& spring = network.springs[s];
    const std::string where = "springs[" + std::to_string(s) + "]";
    const int count = static_cast<int>(n);
    if (spring.i < 0 || spring.i >= count)
      return where + ".i: particle index " + std::to_string(spring.i) + " out of range [0, " +
             std::to_string(count) + ")";
    if (spring.j < 0 || spring.j >= count)
      return where + ".j: particle index " + std::to_string(spring.j) + " out of range [0, " +
             std::to_string(count) + ")";
    if (spring.i == spring.j) return where + ".j: a spring must connect two different particles";
    if (!std::isfinite(spring.stiffness) || spring.stiffness < 0)
      return where + ".k: must be finite and >= 0 (got " + describe(spring.stiffness) + ")";
    if (!std::isfinite(spring.damping) || spring.damping < 0)
      return where + ".c: must be finite and >= 0 (got " + describe(spring.damping) + ")";
    if (!std::isfinite(spring.rest_length) || spring.rest_length <= 0)
      return where + ".L0: must be finite and > 0 (got " + describe(spring.rest_length) + ")";
    if (spring.group < -1) return where + ".group: must be >= -1 (-1 means no group)";
  }
  const int corners = network.dimension == 2 ? 4 : 8;
  for (size_t v = 0; v < network.volumes.size(); ++v) {
    const analysis::VolumeTerm& term = network.volumes[v];
    const std::string where = "volumes[" + std::to_string(v) + "]";
    // A strain point (spring_strain_point.hpp) lists its own points; a cell its corners.
    if (term.points.size() != term.gradients.size())
      return where + ".gradients: one gradient per point expected";
    const std::vector<int> indices =
        term.points.empty()
            ? std::vector<int>(term.particles.begin(), term.particles.begin() + corners)
            : term.points;
    for (int q : indices)
      if (q < 0 || q >= static_cast<int>(n))
        return where + (term.points.empty() ? ".particles" : ".points") + ": particle index " +
               std::to_string(q) + " out of range [0, " + std::to_string(n) + ")";
    for (const Eigen::Vector3d& g : term.gradients)
      if (!g.allFinite()) return where + ".gradients: must be finite";
    if (!std::isfinite(term.modulus) || term.modulus < 0)
      return where + (term.kind == analysis::CellEnergy::kShear ? ".mu" : ".kappa") +
             ": must be finite and >= 0 (got " + describe(term.modulus) + ")";
    if (!std::isfinite(term.rest_volume) || term.rest_volume == 0)
      return where + ".V0: must be finite and non-zero (got " + describe(term.rest_volume) + ")";
    if (term.group < -1) return where + ".group: must be >= -1 (-1 means no group)";
  }
  return {};
}

json model_to_json(const analysis::SpringNetwork& network, const json& provenance,
                   const json& units) {
  json particles = json::array();
  for (size_t p = 0; p < network.positions.size(); ++p) {
    const Eigen::Vector3d& x = network.positions[p];
    particles.push_back(json{{"x", {x.x(), x.y(), x.z()}},
                             {"mass", network.masses[p]},
                             {"fixed", static_cast<bool>(network.fixed[p])}});
  }
  json springs = json::array();
  for (const analysis::Spring& s : network.springs)
    springs.push_back(json{{"i", s.i},
                           {"j", s.j},
                           {"k", s.stiffness},
                           {"c", s.damping},
                           {"L0", s.rest_length},
                           {"group", s.group}});
  json document{{"format", kFormat},
                {"version", kVersion},
                {"units", units},
                {"dimension", network.dimension},
                {"particles", std::move(particles)},
                {"springs", std::move(springs)},
                {"provenance", provenance.is_null() ? json::object() : provenance}};
  // Written only when present, so a plain spring model's file is unchanged.
  if (!network.volumes.empty()) {
    json volumes = json::array();
    const size_t corners = network.dimension == 2 ? 4 : 8;
    for (const analysis::VolumeTerm& v : network.volumes) {
      json item{{v.kind == analysis::CellEnergy::kShear ? "mu" : "kappa", v.modulus},
                {"V0", v.rest_volume},
                {"group", v.group}};
      if (v.points.empty()) {
        item["particles"] = std::vector<int>(v.particles.begin(), v.particles.begin() + corners);
      } else {
        // A strain point: F = sum_a x_{points[a]} gradients[a]^T (dR_a/dX at the point).
        item["points"] = v.points;
        json gradients = json::array();
        for (const Eigen::Vector3d& g : v.gradients) {
          json row = json::array();
          for (int c = 0; c < network.dimension; ++c) row.push_back(g[c]);
          gradients.push_back(std::move(row));
        }
        item["gradients"] = std::move(gradients);
      }
      volumes.push_back(std::move(item));
    }
    document["volumes"] = std::move(volumes);
  }
  return document;
}

SpringModel model_from_json(const json& document, const std::string& source) {
  const FieldReader reader(source);
  check_document(reader, document);

  SpringModel model;
  analysis::SpringNetwork& network = model.network;
  network.dimension =
      document.contains("dimension") ? reader.integer(document["dimension"], "dimension") : 3;
  if (network.dimension != 2 && network.dimension != 3) reader.fail("dimension", "must be 2 or 3");
  model.units = document.value("units", default_model_units());
  if (!model.units.is_object()) reader.fail("units", "must be an object");
  model.provenance = document.value("provenance", json::object());
  if (!model.provenance.is_object()) reader.fail("provenance", "must be an object");

  read_particles(reader, document, network);
  read_springs(reader, document, network);
  read_volumes(reader, document, network);
  // The remaining range checks are shared with the writer.
  if (const std::string problem = check_spring_network(network); !problem.empty())
    throw InputError(source + ": " + problem);

  if (document.contains("gravity"))
    model.gravity = reader.vector(document["gravity"], "gravity", network.dimension);
  read_load_cases(reader, document, model);
  return model;
}

void write_model_json(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                      const json& provenance, const json& units) {
  if (const std::string problem = check_spring_network(network); !problem.empty())
    throw InputError("cannot write '" + path.string() +
                     "': the spring model is invalid: " + problem);
  if (!provenance.is_null() && !provenance.is_object())
    throw InputError("cannot write '" + path.string() + "': provenance must be a JSON object");
  write_file_atomically(path, model_to_json(network, provenance, units).dump(2) + "\n");
}

json spring_model_to_json(const SpringModel& model) {
  json document = model_to_json(model.network, model.provenance,
                                model.units.is_null() ? default_model_units() : model.units);
  const int dim = model.network.dimension;
  if (!model.gravity.isZero()) {
    json g = json::array();
    for (int c = 0; c < dim; ++c) g.push_back(model.gravity[c]);
    document["gravity"] = g;
  }
  if (!model.load_cases.empty()) {
    json cases = json::array();
    for (const ModelLoadCase& load : model.load_cases) {
      json forces = json::array();
      for (const auto& [particle, force] : load.forces) {
        json row = json::array({particle});
        for (int c = 0; c < dim; ++c) row.push_back(force[c]);
        forces.push_back(row);
      }
      cases.push_back(json{{"id", load.id}, {"forces", forces}});
    }
    document["load_cases"] = cases;
  }
  return document;
}

void write_spring_model_json(const std::filesystem::path& path, const SpringModel& model) {
  if (const std::string problem = check_spring_network(model.network); !problem.empty())
    throw InputError("cannot write '" + path.string() +
                     "': the spring model is invalid: " + problem);
  const auto n = static_cast<int>(model.network.positions.size());
  if (!model.gravity.allFinite())
    throw InputError("cannot write '" + path.string() + "': gravity must be finite");
  for (const ModelLoadCase& load : model.load_cases)
    for (const auto& [particle, force] : load.forces)
      if (particle < 0 || particle >= n || !force.allFinite())
        throw InputError("cannot write '" + path.string() + "': load case " + load.id +
                         " has a bad force (particle " + std::to_string(particle) + ")");
  if (!model.provenance.is_null() && !model.provenance.is_object())
    throw InputError("cannot write '" + path.string() + "': provenance must be a JSON object");
  write_file_atomically(path, spring_model_to_json(model).dump(2) + "\n");
}

ModelLoadCase model_load_case(std::string id, const Eigen::VectorXd& flat, int dimension) {
  ModelLoadCase load;
  load.id = std::move(id);
  for (Eigen::Index p = 0; p < flat.size() / dimension; ++p)
    if (!flat.segment(p * dimension, dimension).isZero(0.0)) {
      Eigen::Vector3d force = Eigen::Vector3d::Zero();
      force.head(dimension) = flat.segment(p * dimension, dimension);
      load.forces.emplace_back(static_cast<int>(p), force);
    }
  return load;
}

Eigen::VectorXd model_gravity_vector(const SpringModel& model) {
  const analysis::SpringNetwork& network = model.network;
  const int dim = network.dimension;
  Eigen::VectorXd f(static_cast<Eigen::Index>(network.positions.size()) * dim);
  for (size_t p = 0; p < network.positions.size(); ++p)
    f.segment(static_cast<Eigen::Index>(p) * dim, dim) =
        network.masses[p] * model.gravity.head(dim);
  return f;
}

Eigen::VectorXd model_force_vector(const SpringModel& model, size_t index, bool with_gravity) {
  const analysis::SpringNetwork& network = model.network;
  const int dim = network.dimension;
  Eigen::VectorXd f =
      with_gravity
          ? model_gravity_vector(model)
          : Eigen::VectorXd::Zero(static_cast<Eigen::Index>(network.positions.size()) * dim);
  for (const auto& [particle, force] : model.load_cases.at(index).forces)
    f.segment(static_cast<Eigen::Index>(particle) * dim, dim) += force.head(dim);
  return f;
}

SpringModel read_model_json(const std::filesystem::path& path) {
  const std::string text = read_text_file(path, "model file");
  const std::string source = path.filename().string();
  return model_from_json(parse_json_text(text, source, "model file"), source);
}

}  // namespace isospring::io
