// model.json: exact round trip and validation (every bad field is an InputError naming it).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

analysis::SpringNetwork small_network() {
  analysis::SpringNetwork n;
  n.dimension = 3;
  n.positions = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, {0.1 / 3.0, 0.2, std::sqrt(2.0)}};
  n.masses = {0.0, 0.25, 1.0 / 3.0, 1e-7};
  n.fixed = {true, false, false, false};
  n.springs = {{0, 1, 1234.5678901234567, 0.1, 0.1, 0},
               {1, 2, 1.0 / 7.0, 0.0, std::sqrt(0.02), -1},
               {2, 3, 9e9, 3.3, 0.123456789012345678, 7}};
  return n;
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("isospring_test_model_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void expect_error(const json& document, const std::string& fragment) {
  try {
    model_from_json(document, "model.json");
    FAIL() << "no InputError for " << fragment;
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("model.json: ", 0), 0u) << e.what();
  }
}

TEST(ModelFile, RoundTripIsBitExact) {
  const analysis::SpringNetwork n = small_network();
  const fs::path path = temp_dir("roundtrip") / "model.json";
  const json provenance{
      {"case", "cantilever"}, {"isospring_version", "0.1.0"}, {"fit", {{"rms", 1.25e-6}}}};
  write_model_json(path, n, provenance);
  const SpringModel m = read_model_json(path);
  ASSERT_EQ(m.network.positions.size(), n.positions.size());
  for (size_t p = 0; p < n.positions.size(); ++p) {
    EXPECT_EQ(m.network.positions[p], n.positions[p]);  // shortest round-trip doubles: exact
    EXPECT_EQ(m.network.masses[p], n.masses[p]);
    EXPECT_EQ(m.network.fixed[p], n.fixed[p]);
  }
  ASSERT_EQ(m.network.springs.size(), n.springs.size());
  for (size_t s = 0; s < n.springs.size(); ++s) {
    EXPECT_EQ(m.network.springs[s].i, n.springs[s].i);
    EXPECT_EQ(m.network.springs[s].j, n.springs[s].j);
    EXPECT_EQ(m.network.springs[s].stiffness, n.springs[s].stiffness);
    EXPECT_EQ(m.network.springs[s].damping, n.springs[s].damping);
    EXPECT_EQ(m.network.springs[s].rest_length, n.springs[s].rest_length);
    EXPECT_EQ(m.network.springs[s].group, n.springs[s].group);
  }
  EXPECT_EQ(m.network.dimension, 3);
  EXPECT_EQ(m.provenance, provenance);
  EXPECT_EQ(m.units["length"], "m");
  // The documented schema's top-level keys are what is on disk.
  const json on_disk = json::parse(std::ifstream(path));
  EXPECT_EQ(on_disk["format"], "isospring-spring-model");
  EXPECT_EQ(on_disk["version"], 1);
  EXPECT_EQ(on_disk["springs"][0]["L0"], 0.1);
}

TEST(ModelFile, OptionalFieldsTakeTheirDefaults) {
  const json doc{
      {"format", "isospring-spring-model"},
      {"version", 1},
      {"particles", {{{"x", {0, 0, 0}}, {"mass", 1.0}}, {{"x", {1, 0, 0}}, {"mass", 2.0}}}},
      {"springs", {{{"i", 0}, {"j", 1}, {"k", 5.0}, {"L0", 1.0}}}}};
  const SpringModel m = model_from_json(doc, "model.json");
  EXPECT_EQ(m.network.dimension, 3);
  EXPECT_FALSE(m.network.fixed[0]);
  EXPECT_EQ(m.network.springs[0].damping, 0.0);
  EXPECT_EQ(m.network.springs[0].group, -1);
  EXPECT_TRUE(m.provenance.is_object());
}

TEST(ModelFile, BadFieldsAreNamed) {
  const json good = model_to_json(small_network());
  auto with = [&](const std::string& pointer, const json& value) {
    json doc = good;
    doc[json::json_pointer(pointer)] = value;
    return doc;
  };
  expect_error(with("/springs/1/k", -3.0), "springs[1].k");
  expect_error(with("/springs/0/j", 4), "springs[0].j: particle index 4 out of range");
  expect_error(with("/springs/0/i", -1), "springs[0].i");
  expect_error(with("/springs/2/j", 2), "springs[2].j");
  expect_error(with("/springs/2/L0", 0.0), "springs[2].L0");
  expect_error(with("/springs/2/c", -1.0), "springs[2].c");
  expect_error(with("/springs/2/k", nullptr), "springs[2].k must be a number");  // NaN in JSON
  expect_error(with("/springs/2/k", "12"), "springs[2].k must be a number, got string");
  expect_error(with("/springs/0/i", 0.5), "springs[0].i must be an integer, got number");
  expect_error(with("/particles/1/mass", 0.0), "particles[1].mass");
  expect_error(with("/particles/2/x", json::array({0, 1})), "particles[2].x");
  expect_error(with("/particles/2/fixed", "yes"), "particles[2].fixed");
  expect_error(with("/format", "something-else"), "format");
  expect_error(with("/version", 2), "version");
  expect_error(with("/dimension", 4), "dimension");
  expect_error(with("/springs/0/stiffness", 1.0), "springs[0].stiffness: unknown field");
  json missing = good;
  missing["springs"][1].erase("L0");
  expect_error(missing, "springs[1].L0: missing");
  json empty = good;
  empty["particles"] = json::array();
  expect_error(empty, "particles");
}

TEST(ModelFile, LoadsRoundTripAndAddUp) {
  SpringModel model;
  model.network = small_network();
  model.units = default_model_units();
  model.gravity = Eigen::Vector3d(0.0, -9.81, 0.1 / 3.0);
  model.load_cases = {{"L1", {{1, Eigen::Vector3d(1.0 / 3.0, 2.0, -1e-9)}, {3, {0, 0, 5}}}},
                      {"L2", {}}};
  const fs::path dir = temp_dir("loads");
  write_spring_model_json(dir / "model.json", model);
  const SpringModel back = read_model_json(dir / "model.json");
  EXPECT_EQ(back.gravity, model.gravity);  // full precision: bit exact
  ASSERT_EQ(back.load_cases.size(), 2u);
  EXPECT_EQ(back.load_cases[0].id, "L1");
  ASSERT_EQ(back.load_cases[0].forces.size(), 2u);
  EXPECT_EQ(back.load_cases[0].forces[0].second, model.load_cases[0].forces[0].second);
  EXPECT_TRUE(back.load_cases[1].forces.empty());
  // Force vector: the listed forces plus m_i g on every particle.
  const Eigen::VectorXd f = model_force_vector(back, 0, true);
  ASSERT_EQ(f.size(), 12);
  EXPECT_EQ(f.segment(3, 3), Eigen::Vector3d(1.0 / 3.0, 2.0, -1e-9) + 0.25 * model.gravity);
  EXPECT_EQ(f.segment(9, 3), Eigen::Vector3d(0, 0, 5) + 1e-7 * model.gravity);
  EXPECT_EQ(f.segment(0, 3), Eigen::Vector3d::Zero());  // mass 0
  EXPECT_EQ(model_force_vector(back, 0, false).segment(3, 3),
            Eigen::Vector3d(1.0 / 3.0, 2.0, -1e-9));
  // Files without loads read as before: zero gravity, no load cases.
  const SpringModel plain = model_from_json(model_to_json(small_network()), "model.json");
  EXPECT_TRUE(plain.gravity.isZero());
  EXPECT_TRUE(plain.load_cases.empty());
  // Bad loads are named.
  const json good = spring_model_to_json(model);
  auto with = [&](const std::string& pointer, const json& value) {
    json doc = good;
    doc[json::json_pointer(pointer)] = value;
    return doc;
  };
  expect_error(with("/load_cases/0/forces/1/0", 4),
               "load_cases[0].forces[1][0]: particle index 4 out of range");
  expect_error(with("/load_cases/0/forces/0", json::array({1, 2.0})),
               "load_cases[0].forces[0]: must be [particle, fx, fy, fz]");
  expect_error(with("/load_cases/1/id", 3), "load_cases[1].id: must be a string");
  expect_error(with("/gravity", json::array({0, "g", 0})), "gravity[1] must be a number");
  fs::remove_all(dir);
}

TEST(ModelFile, WriterRefusesAnInvalidNetworkAndKeepsTheOldFile) {
  const fs::path path = temp_dir("writer") / "model.json";
  write_model_json(path, small_network());
  analysis::SpringNetwork bad = small_network();
  bad.springs[1].stiffness = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_model_json(path, bad), nurbs::InputError);
  bad = small_network();
  bad.springs[0].j = 17;
  EXPECT_THROW(write_model_json(path, bad), nurbs::InputError);
  bad = small_network();
  bad.masses.pop_back();
  EXPECT_THROW(write_model_json(path, bad), nurbs::InputError);
  EXPECT_NO_THROW(read_model_json(path));  // the earlier good file is untouched
}

TEST(ModelFile, UnreadableFilesAreInputErrors) {
  const fs::path dir = temp_dir("unreadable");
  EXPECT_THROW(read_model_json(dir / "missing.json"), nurbs::InputError);
  std::ofstream(dir / "broken.json") << "{\"format\": ";
  try {
    read_model_json(dir / "broken.json");
    FAIL();
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace isospring::io
