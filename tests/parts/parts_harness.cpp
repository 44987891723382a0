// The parts harness (parts_harness.hpp).
#include "parts_harness.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <vector>

namespace isospring::parts_harness {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kParts = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts";

json read_json(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

Eigen::Matrix3d placement(const json& part) {
  if (!part.contains("placement")) return Eigen::Matrix3d::Identity();
  const auto axis = part.at("placement").at("axis").get<std::vector<double>>();
  const double angle = part.at("placement").at("angle_deg").get<double>() * M_PI / 180.0;
  return Eigen::AngleAxisd(angle, Eigen::Vector3d(axis[0], axis[1], axis[2]).normalized())
      .toRotationMatrix();
}

geometry::CadSolid read_placed_solid(const json& part) {
  const geometry::CadSolid read =
      geometry::read_cad_solid(kParts / part.at("file").get<std::string>());
  return part.contains("placement") ? geometry::transform_solid(read, placement(part)) : read;
}

geometry::ImmersionOptions immersion_options(const json& part, const json& grid, int degree,
                                             const geometry::CadSolid& solid) {
  geometry::ImmersionOptions immersion;
  if (grid.value("frame", std::string()) == "placement") immersion.frame = placement(part);
  if (grid.value("frame", std::string()) == "principal")
    immersion.frame = geometry::principal_frame(solid).axes;
  immersion.degree = degree;
  immersion.cell_size = grid.at("cell_size").get<double>();
  immersion.margin = grid.value("margin", 0.0);
  immersion.tolerance = grid.value("tolerance", 1e-7);
  immersion.max_depth = grid.value("max_depth", 4);
  if (grid.contains("grading")) {
    // Cells graded towards the clamped face's outline, where the stresses are singular.
    const json& g = grid.at("grading");
    immersion.grading =
        geometry::grading_towards_face(solid, part.at("clamp_face").get<int>(),
                                       g.at("smallest").get<double>(), g.at("ratio").get<double>());
  }
  if (grid.contains("grading_planes")) {
    // Cells graded towards planes through the part's re-entrant edges (where the stresses are
    // singular too), as a case file's "grading": [{"plane": {"axis", "at"}, ...}] gives them.
    for (const json& g : grid.at("grading_planes")) {
      const int axis = std::string("xyz").find(g.at("axis").get<std::string>());
      EXPECT_TRUE(axis >= 0 && axis <= 2) << "grading_planes: axis must be \"x\", \"y\" or \"z\"";
      immersion.grading.push_back(
          {axis, g.at("at").get<double>(), g.at("smallest").get<double>(), g.value("ratio", 1.5)});
    }
  }
  return immersion;
}

analysis::ImmersedOptions analysis_options(const json& part, const json& grid) {
  analysis::ImmersedOptions options;
  options.material.youngs_modulus = part.at("material").at("E").get<double>();
  options.material.poisson_ratio = part.at("material").at("nu").get<double>();
  options.material.density = part.at("material").at("density").get<double>();
  // "volumetric": "bbar" for nearly incompressible parts (mean-dilatation B-bar).
  if (grid.value("volumetric", std::string()) == "bbar")
    options.volumetric = analysis::Volumetric::kBbar;
  // The ghost penalty's strength and the cut fraction below which it acts (ImmersedOptions).
  options.ghost_penalty = grid.value("ghost_penalty", options.ghost_penalty);
  options.ghost_fraction = grid.value("ghost_fraction", options.ghost_fraction);
  analysis::ImmersedSupport clamp;
  clamp.face = part.at("clamp_face").get<int>();
  clamp.fixed = {true, true, true};
  options.supports = {clamp};
  const auto g = part.at("gravity").get<std::vector<double>>();
  options.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
  return options;
}

json find_part(const std::string& name) {
  const json parts = read_json(kParts / "parts.json");
  for (const auto& p : parts.at("parts"))
    if (p.at("name") == name) return p;
  return json();
}

}  // namespace isospring::parts_harness
