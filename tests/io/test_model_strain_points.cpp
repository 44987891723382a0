// Strain-point terms (analysis/spring_strain_point.hpp) in model.json: the points and
// their basis gradients round-trip exactly (same stiffness, same nonlinear forces), bad entries
// are named, and the SOFA / MuJoCo exports refuse them like the cell terms.
#include <gtest/gtest.h>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/export_sofa.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using nlohmann::json;

// Three particles of a triangle carrying one strain point: F = sum_a x_a g_a^T is exact for
// affine motions when sum_a g_a = 0 and sum_a X_a g_a^T = I (linear triangle gradients).
analysis::SpringNetwork triangle() {
  analysis::SpringNetwork n;
  n.dimension = 2;
  n.positions = {{0.0, 0.0, 0.0}, {0.2, 0.0, 0.0}, {0.0, 0.1, 0.0}};
  n.masses.assign(3, 0.5);
  n.fixed = {true, false, false};
  n.springs.push_back({1, 2, 700.0, 0.0, std::sqrt(0.05), 0});
  analysis::VolumeTerm term;
  term.points = {0, 1, 2};
  term.gradients = {{-5.0, -10.0, 0.0}, {5.0, 0.0, 0.0}, {0.0, 10.0, 0.0}};
  term.rest_volume = 0.01;
  term.modulus = 1234.567890123;
  term.group = 2;
  n.volumes.push_back(term);
  term.kind = analysis::CellEnergy::kShear;
  term.modulus = 345.6789;
  n.volumes.push_back(term);
  return n;
}

TEST(ModelStrainPoints, RoundTripIsExact) {
  const analysis::SpringNetwork n = triangle();
  const json document = model_to_json(n);
  ASSERT_TRUE(document["volumes"][0].contains("points"));
  EXPECT_FALSE(document["volumes"][0].contains("particles"));
  const SpringModel m = model_from_json(json::parse(document.dump()), "model.json");
  ASSERT_EQ(m.network.volumes.size(), 2u);
  for (size_t v = 0; v < 2; ++v) {
    EXPECT_EQ(m.network.volumes[v].points, n.volumes[v].points);
    EXPECT_EQ(m.network.volumes[v].gradients, n.volumes[v].gradients);
    EXPECT_EQ(m.network.volumes[v].kind, n.volumes[v].kind);
    EXPECT_EQ(m.network.volumes[v].modulus, n.volumes[v].modulus);
  }
  EXPECT_EQ((Eigen::MatrixXd(analysis::rest_stiffness(n)) -
             Eigen::MatrixXd(analysis::rest_stiffness(m.network)))
                .norm(),
            0.0);
  Eigen::VectorXd x = analysis::flat_positions(n);
  x[2] += 0.03;
  x[5] -= 0.02;
  const Eigen::VectorXd f = analysis::spring_forces(n, x);
  EXPECT_GT(f.norm(), 1.0);
  EXPECT_EQ((f - analysis::spring_forces(m.network, x)).norm(), 0.0);
}

TEST(ModelStrainPoints, BadEntriesAreNamedAndEnginesRefuseThem) {
  const json good = model_to_json(triangle());
  auto expect_error = [](const json& document, const std::string& fragment) {
    try {
      model_from_json(document, "model.json");
      FAIL() << "no InputError for " << fragment;
    } catch (const nurbs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  json bad = good;
  bad["volumes"][0]["points"][1] = 7;
  expect_error(bad, "volumes[0].points: particle index 7");
  bad = good;
  bad["volumes"][1]["gradients"].erase(2);
  expect_error(bad, "volumes[1].points");
  bad = good;
  bad["volumes"][0]["gradients"][0] = {1.0, 2.0, 3.0};
  expect_error(bad, "volumes[0].gradients[0]");
  EXPECT_THROW(sofa_scene(triangle(), {}), nurbs::InputError);
  EXPECT_THROW(mjcf_document(triangle(), {}), nurbs::InputError);
  try {
    sofa_scene(triangle(), {});
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 strain points"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isospring::io
