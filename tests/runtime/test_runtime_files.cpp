// The runtime's loader: bad files are refused with a sentence naming the file and the field, and
// a reduced model written by io::export_reduced_model steps exactly as
// analysis::ReducedSpringModel does.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/fitting/spring_mesh.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/export_reduced.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/runtime/runtime.h"
#include "runtime_test_support.hpp"

namespace isospring::runtime {
namespace {

using nlohmann::json;

// A small valid model: two cells of a 2D net with springs, a cell area and a strain point.
json small_model() {
  json d = {{"format", "isospring-spring-model"}, {"version", 1}, {"dimension", 2}};
  d["particles"] = json::array();
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i)
      d["particles"].push_back({{"x", {0.1 * i, 0.1 * j, 0.0}}, {"mass", 0.01}, {"fixed", i == 0}});
  d["springs"] = json::array({{{"i", 0}, {"j", 1}, {"k", 100.0}, {"c", 0.1}, {"L0", 0.1}},
                              {{"i", 1}, {"j", 4}, {"k", 100.0}, {"L0", 0.1}}});
  d["volumes"] = json::array({{{"particles", {0, 1, 3, 4}}, {"kappa", 10.0}, {"V0", 0.01}},
                              {{"points", {1, 2, 5}},
                               {"gradients", {{-10.0, 0.0}, {10.0, -10.0}, {0.0, 10.0}}},
                               {"mu", 5.0},
                               {"V0", 0.005}}});
  return d;
}

std::string error_after(void (*change)(json&)) {
  json d = small_model();
  change(d);
  return load_error(d.dump());
}

TEST(RuntimeFiles, AValidModelLoadsWithItsCounts) {
  const std::string text = small_model().dump();
  char error[200] = "unchanged";
  isospring_model* m = isospring_model_parse(text.data(), text.size(), "m.json", error, 200);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_STREQ(error, "");
  EXPECT_EQ(isospring_model_kind(m), ISOSPRING_MODEL_NETWORK);
  EXPECT_EQ(isospring_model_particle_count(m), 6u);
  EXPECT_EQ(isospring_model_state_size(m), 12u);
  EXPECT_EQ(isospring_model_term_count(m, ISOSPRING_TERM_SPRINGS), 2u);
  EXPECT_EQ(isospring_model_term_count(m, ISOSPRING_TERM_CELL_VOLUME), 1u);
  EXPECT_EQ(isospring_model_term_count(m, ISOSPRING_TERM_POINT_SHEAR), 1u);
  EXPECT_EQ(isospring_model_particle_fixed(m, 3), 1);
  EXPECT_EQ(isospring_model_particle_fixed(m, 4), 0);
  EXPECT_EQ(isospring_model_rest_positions(m)[2 * 4 + 1], 0.1);
  EXPECT_EQ(isospring_model_masses(m)[5], 0.01);
  isospring_model_free(m);
}

TEST(RuntimeFiles, BadFilesNameTheFileAndTheField) {
  struct Case {
    void (*change)(json&);
    const char* expected;
  };
  const Case cases[] = {
      {[](json& d) { d["format"] = "something-else"; }, "model.json: format: must be"},
      {[](json& d) { d["version"] = 2; }, "model.json: version: unsupported version"},
      {[](json& d) { d["dimension"] = 4; }, "model.json: dimension: must be 2 or 3"},
      {[](json& d) { d.erase("particles"); }, "model.json: particles: missing"},
      {[](json& d) { d["particles"][2]["mass"] = -1.0; }, "particles[2].mass: must be > 0"},
      {[](json& d) { d["particles"][1]["x"] = "here"; }, "particles[1].x: must be an array"},
      {[](json& d) { d["springs"][1]["k"] = -3.0; }, "springs[1].k: must be finite and >= 0"},
      {[](json& d) { d["springs"][0]["j"] = 6; }, "springs[0].j: particle index 6 out of range"},
      {[](json& d) { d["springs"][0]["j"] = 0; }, "springs[0].j: a spring must connect two"},
      {[](json& d) { d["springs"][0]["L0"] = 0.0; }, "springs[0].L0: must be finite and > 0"},
      {[](json& d) { d["springs"][0].erase("L0"); }, "springs[0].L0: missing"},
      {[](json& d) { d["volumes"][0]["mu"] = 1.0; }, "volumes[0]: give either \"kappa\""},
      {[](json& d) {
         d["volumes"][0]["particles"] = {0, 1, 3};
       },
       "volumes[0].particles: must list the 4 corners"},
      {[](json& d) { d["volumes"][0]["V0"] = 0.0; }, "volumes[0].V0: must be finite and non-zero"},
      {[](json& d) { d["volumes"][1]["gradients"][2] = {1.0}; },
       "volumes[1].gradients[2]: must be an array of 2 entries"},
      {[](json& d) {
         d["volumes"][1]["points"] = {1, 2};
       },
       "volumes[1].points: must list one particle per row"},
      {[](json& d) { d["volumes"][1]["gradients"][0][1] = "x"; },
       "volumes[1].gradients[0][1]: must be a number"},
  };
  for (const Case& c : cases) {
    const std::string message = error_after(c.change);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << message;
  }
  EXPECT_NE(load_error("{\"format\": ").find("model.json: not valid JSON"), std::string::npos);
  char error[300];
  EXPECT_EQ(isospring_model_load("/nonexistent/model.json", error, sizeof(error)), nullptr);
  EXPECT_NE(std::string(error).find("/nonexistent/model.json: cannot open the model file"),
            std::string::npos)
      << error;
  // A short buffer is truncated and terminated, never overrun.
  char tiny[8];
  const std::string text = "[1]";
  EXPECT_EQ(isospring_model_parse(text.data(), text.size(), "model.json", tiny, sizeof(tiny)),
            nullptr);
  EXPECT_STREQ(tiny, "model.j");
}

// The same model built from arrays evaluates to the same forces (bit for bit: the same terms in
// the same order), and a refused add leaves the model as it was.
TEST(RuntimeFiles, BuilderMakesTheSameModelAsTheFile) {
  const std::string text = small_model().dump();
  ModelHandle parsed(isospring_model_parse(text.data(), text.size(), "m.json", nullptr, 0),
                     ModelDeleter());
  ASSERT_NE(parsed, nullptr);
  const double rest[] = {0, 0, 0.1, 0, 0.2, 0, 0, 0.1, 0.1, 0.1, 0.2, 0.1};
  const double masses[] = {0.01, 0.01, 0.01, 0.01, 0.01, 0.01};
  const unsigned char fixed[] = {1, 0, 0, 1, 0, 0};
  char error[300] = "";
  ModelHandle built(isospring_model_create(2, 6, rest, masses, fixed, error, 300), ModelDeleter());
  ASSERT_NE(built, nullptr) << error;
  const int ends[] = {0, 1, 1, 4};
  const double k[] = {100, 100}, c[] = {0.1, 0}, l0[] = {0.1, 0.1};
  ASSERT_EQ(isospring_model_add_springs(built.get(), 2, ends, k, c, l0, error, 300), 1) << error;
  const int corners[] = {0, 1, 3, 4};
  const double kappa[] = {10.0}, v0[] = {0.01};
  ASSERT_EQ(isospring_model_add_cells(built.get(), ISOSPRING_TERM_CELL_VOLUME, 1, corners, kappa,
                                      v0, error, 300),
            1)
      << error;
  const size_t offsets[] = {0, 3};
  const int points[] = {1, 2, 5};
  const double gradients[] = {-10, 0, 10, -10, 0, 10}, mu[] = {5.0}, point_v0[] = {0.005};
  ASSERT_EQ(isospring_model_add_points(built.get(), ISOSPRING_TERM_POINT_SHEAR, 1, offsets, points,
                                       gradients, mu, point_v0, error, 300),
            1)
      << error;
  // A bad second spring: refused with its entry named, and the first one not kept either.
  const int bad_ends[] = {0, 2, 3, 9};
  EXPECT_EQ(isospring_model_add_springs(built.get(), 2, bad_ends, k, c, l0, error, 300), 0);
  EXPECT_NE(std::string(error).find("isospring_model_add_springs: springs[1].j: particle index 9"),
            std::string::npos)
      << error;
  EXPECT_EQ(isospring_model_term_count(built.get(), ISOSPRING_TERM_SPRINGS), 2u);

  double x[12], v[12], f_parsed[12], f_built[12];
  for (int e = 0; e < 12; ++e) {
    x[e] = rest[e] + 0.01 * ((e * 7) % 5 - 2);
    v[e] = 0.1 * ((e * 3) % 4 - 1.5);
  }
  const double e_parsed = isospring_model_forces(parsed.get(), x, v, f_parsed);
  EXPECT_EQ(isospring_model_forces(built.get(), x, v, f_built), e_parsed);
  for (int e = 0; e < 12; ++e) EXPECT_EQ(f_built[e], f_parsed[e]) << e;
  EXPECT_EQ(isospring_model_create(4, 6, rest, masses, fixed, error, 300), nullptr);
  EXPECT_NE(std::string(error).find("isospring_model_create: dimension: must be 2 or 3"),
            std::string::npos)
      << error;
}

TEST(RuntimeFiles, ReducedModelStepsAsTheAnalysisModel) {
  // A cube net of springs (a cell term each, so the reduced K holds them too), fixed on u0.
  const fitting::ThesisObject cube = fitting::thesis_cube(3);
  fitting::SpringMeshOptions mesh_options;
  mesh_options.volume_terms = true;
  io::SpringModel model;
  model.network = fitting::build_spring_mesh(cube.problem, mesh_options).network;
  analysis::SpringNetwork& n = model.network;
  n.masses.assign(n.positions.size(), 0.05);
  n.fixed.assign(n.positions.size(), false);
  for (size_t p = 0; p < n.positions.size(); ++p) n.fixed[p] = n.positions[p].x() < 1e-9;
  for (size_t s = 0; s < n.springs.size(); ++s) {
    n.springs[s].stiffness = 1e3 * (1.0 + 0.1 * static_cast<double>(s % 7));
    n.springs[s].damping = 0.5;
  }
  for (analysis::VolumeTerm& t : n.volumes) t.modulus = 2e3;
  io::ReducedExportOptions options;
  options.modes = 12;
  options.load_shapes = false;
  options.error_steps = 1;
  const io::ReducedExport exported = io::export_reduced_model(model, options);
  const std::string text = exported.document.dump();
  char error[500] = "";
  ModelHandle m(isospring_model_parse(text.data(), text.size(), "reduced.json", error, 500),
                ModelDeleter());
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(isospring_model_kind(m.get()), ISOSPRING_MODEL_REDUCED);
  EXPECT_EQ(isospring_model_timestep(m.get()), options.timestep);

  analysis::ReducedModelOptions reduction;
  reduction.modes = options.modes;
  analysis::ReducedSpringModel reference(n, options.timestep, reduction);
  const auto r = static_cast<size_t>(reference.size());
  ASSERT_EQ(isospring_model_state_size(m.get()), r);

  Eigen::VectorXd force = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * n.positions.size()));
  for (size_t p = 0; p < n.positions.size(); ++p)
    if (n.positions[p].x() > 2.0 - 1e-9)
      force.segment<3>(3 * static_cast<Eigen::Index>(p)) << 1, -2, 3;
  Eigen::VectorXd g(static_cast<Eigen::Index>(r)), q = Eigen::VectorXd::Zero(g.size()), qdot = q;
  isospring_model_reduce_force(m.get(), force.data(), g.data());
  const Eigen::VectorXd g_reference = reference.reduce_force(force);
  EXPECT_LE((g - g_reference).norm(), 1e-12 * g_reference.norm());
  for (int step = 0; step < 50; ++step) {
    isospring_model_reduced_step(m.get(), g.data(), q.data(), qdot.data());
    reference.step(g_reference);
  }
  EXPECT_LE((q - reference.coordinates()).norm(), 1e-12 * reference.coordinates().norm());
  EXPECT_LE((qdot - reference.velocities()).norm(), 1e-12 * reference.velocities().norm());
  Eigen::VectorXd u(force.size());
  isospring_model_expand(m.get(), q.data(), u.data());
  EXPECT_LE((u - reference.displacement()).norm(), 1e-12 * reference.displacement().norm());
  // Forces -Lambda q - C_r qdot and their (constant) Jacobian.
  Eigen::VectorXd f(g.size()), df(g.size());
  isospring_model_forces(m.get(), q.data(), qdot.data(), f.data());
  const Eigen::VectorXd expected =
      -(reference.eigenvalues().cwiseProduct(q)) - reference.damping() * qdot;
  EXPECT_LE((f - expected).norm(), 1e-12 * expected.norm());
  isospring_model_force_jvp(m.get(), q.data(), qdot.data(), q.data(), qdot.data(), df.data());
  EXPECT_LE((df - expected).norm(), 1e-12 * expected.norm());  // linear: J (q, qdot) = f
}

}  // namespace
}  // namespace isospring::runtime
