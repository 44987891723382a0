// SOFA scene export: the scene is parsed back with a minimal XML reader (tags balanced, one
// attribute map per element) and every number is compared with the model (17 significant
// digits read back to the same doubles).
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>

#include "isospring/io/export_sofa.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using Element = std::map<std::string, std::string>;

/// Elements by tag name (attributes only); fails the test when tags do not balance.
std::multimap<std::string, Element> parse_elements(const std::string& xml) {
  std::string text = std::regex_replace(xml, std::regex("<!--[\\s\\S]*?-->|<\\?[^>]*\\?>"), "");
  const std::regex tag("<(/?)([A-Za-z]+)((?:\\s+[A-Za-z]+=\"[^\"]*\")*)\\s*(/?)>");
  const std::regex attribute("([A-Za-z]+)=\"([^\"]*)\"");
  std::multimap<std::string, Element> elements;
  std::vector<std::string> open;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator();
       ++it) {
    const std::string name = (*it)[2];
    if ((*it)[1] == "/") {
      EXPECT_FALSE(open.empty());
      if (open.empty()) break;
      EXPECT_EQ(open.back(), name);
      open.pop_back();
      continue;
    }
    Element e;
    const std::string attrs = (*it)[3];
    for (auto a = std::sregex_iterator(attrs.begin(), attrs.end(), attribute);
         a != std::sregex_iterator(); ++a)
      e[(*a)[1]] = (*a)[2];
    elements.emplace(name, e);
    if ((*it)[4] != "/") open.push_back(name);
  }
  EXPECT_TRUE(open.empty());
  return elements;
}

std::vector<double> numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> out;
  double x;
  while (in >> x) out.push_back(x);
  return out;
}

analysis::SpringNetwork network(bool equal_masses, int dimension) {
  analysis::SpringNetwork n;
  n.dimension = dimension;
  n.positions = {{0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1 / 3.0, 0}, {0, 0.1, 0}};
  n.masses = {0.5, 0.25, equal_masses ? 0.25 : 1.0 / 3.0, 0.25};
  n.fixed = {true, false, false, false};
  n.springs = {{0, 1, 1000.0 / 3.0, 0.5, 0.1, 0},
               {1, 2, 2e3, 0.0, 0.1 / 3.0, 1},
               {2, 3, 1.5e3, 0.25, 0.10540925533894598, -1},
               {0, 2, 7e2, 0.1, 0.10540925533894598, -1}};
  return n;
}

TEST(ExportSofa, SceneCarriesEveryValueExactly) {
  const analysis::SpringNetwork n = network(false, 3);
  SofaOptions options;
  options.gravity = Eigen::Vector3d(0, -9.81, 0);
  options.timestep = 1e-3;
  options.comment = "case cantilever -- calibrated";
  const std::string scene = sofa_scene(n, options);
  EXPECT_NE(scene.find("v22.12"), std::string::npos);
  const auto elements = parse_elements(scene);

  ASSERT_EQ(elements.count("MechanicalObject"), 1u);
  const Element& mo = elements.find("MechanicalObject")->second;
  EXPECT_EQ(mo.at("template"), "Vec3d");
  const std::vector<double> x = numbers(mo.at("position"));
  ASSERT_EQ(x.size(), 12u);
  for (size_t p = 0; p < 4; ++p)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(x[3 * p + static_cast<size_t>(c)], n.positions[p](c));

  ASSERT_EQ(elements.count("DiagonalMass"), 1u);
  EXPECT_EQ(elements.count("UniformMass"), 0u);
  EXPECT_EQ(numbers(elements.find("DiagonalMass")->second.at("vertexMass")), n.masses);

  const std::vector<double> springs =
      numbers(elements.find("StiffSpringForceField")->second.at("spring"));
  ASSERT_EQ(springs.size(), 5 * n.springs.size());
  for (size_t s = 0; s < n.springs.size(); ++s) {
    EXPECT_EQ(springs[5 * s], n.springs[s].i);
    EXPECT_EQ(springs[5 * s + 1], n.springs[s].j);
    EXPECT_EQ(springs[5 * s + 2], n.springs[s].stiffness);
    EXPECT_EQ(springs[5 * s + 3], n.springs[s].damping);
    EXPECT_EQ(springs[5 * s + 4], n.springs[s].rest_length);
  }
  EXPECT_EQ(numbers(elements.find("MeshTopology")->second.at("edges")).size(), 8u);
  EXPECT_EQ(elements.find("FixedConstraint")->second.at("indices"), "0");
  const Element& root = elements.find("Node")->second;
  EXPECT_EQ(root.at("name"), "root");
  EXPECT_EQ(numbers(root.at("gravity")), (std::vector<double>{0, -9.81, 0}));
  EXPECT_EQ(numbers(root.at("dt")), std::vector<double>{1e-3});
  EXPECT_EQ(elements.count("EulerImplicitSolver"), 1u);
}

TEST(ExportSofa, EqualMassesUseUniformMassAndPlanarModelsVec2d) {
  // A flat model's Vec2d particles cannot follow a z gravity (the default): refused, with the
  // in-plane gravity that `isospring export` gives such models by default.
  EXPECT_THROW((void)sofa_scene(network(true, 2)), nurbs::InputError);
  SofaOptions in_plane;
  in_plane.gravity = Eigen::Vector3d(0.0, -9.81, 0.0);
  const auto elements = parse_elements(sofa_scene(network(true, 2), in_plane));
  ASSERT_EQ(elements.count("UniformMass"), 1u);
  EXPECT_EQ(elements.count("DiagonalMass"), 0u);
  EXPECT_EQ(numbers(elements.find("UniformMass")->second.at("vertexMass")),
            std::vector<double>{0.25});
  const Element& mo = elements.find("MechanicalObject")->second;
  EXPECT_EQ(mo.at("template"), "Vec2d");
  EXPECT_EQ(numbers(mo.at("position")).size(), 8u);
}

TEST(ExportSofa, InvalidModelIsRefused) {
  analysis::SpringNetwork n = network(true, 3);
  n.springs[0].rest_length = -1;
  EXPECT_THROW(sofa_scene(n), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::io
