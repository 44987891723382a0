#include "identify_suite_datasets.hpp"

#include <cmath>
#include <tuple>

namespace isospring::identify_suite {

namespace {

using nlohmann::json;

json traction(const json& side, const std::vector<double>& value) {
  json t = side;
  t["value"] = value;
  return t;
}

// 100 x 20 x 20 mm cantilever clamped at x = 0, loads on x = 100 mm (the specimen).
// Declared: degree 2 on 10 x 2 x 2 elements, too coarse for 0.2 % noise on purpose (identify's
// discretisation check must refine it). Markers: ccx nodes of the top face and the y = 0 face,
// x > 5 mm, every 7th.
Specimen cantilever(const Hidden& h) {
  Specimen s;
  s.true_modulus = 1e7;
  const double f = h.load_factor;
  const json end = {{"side", "u1"}};
  s.declared = {{"schema_version", 1},
                {"units", "SI"},
                {"geometry", {{"type", "box"}, {"size", {0.1, 0.02, 0.02}}}},
                {"discretization", {{"degree", 2}, {"elements", {10, 2, 2}}}},
                {"material", {{"E", 0.75 * s.true_modulus}, {"nu", 0.3}, {"density", 1000.0}}},
                {"boundary", {{{"side", "u0"}, {"fix", {"x", "y", "z"}}}}},
                {"load_cases",
                 {{{"id", "tip_down"}, {"tractions", {traction(end, {0.0, 0.0, -2000.0 * f})}}},
                  {{"id", "tip_side"}, {"tractions", {traction(end, {0.0, 1500.0 * f, 0.0})}}},
                  {{"id", "pull"}, {"tractions", {traction(end, {20000.0 * f, 0.0, 0.0})}}}}}};
  s.truth_elements = {30, 6, 6};
  s.slab = 0.1 / 30;
  s.gravity = Eigen::Vector3d(0, 0, -9.81);
  s.is_marker = [](const Eigen::Vector3d& x) {
    return x.x() > 0.005 && (std::abs(x.z() - 0.02) < 1e-9 || std::abs(x.y()) < 1e-9);
  };
  s.stride = 7;
  return s;
}

// 100 x 40 mm plate, 1 mm thick, central hole of radius 8 mm, plane stress, clamped at x = 0
// (side v1 of patch 0), loads on x = 100 mm (side v1 of patch 5). Declared: degree 2 on 2 x 2
// elements per patch (6 patches). Markers: every 5th ccx node.
Specimen plate_with_hole(const Hidden& h) {
  Specimen s;
  s.true_modulus = 2e9;
  const double f = h.load_factor;
  const json end = {{"patch", 5}, {"side", "v1"}};
  s.declared = {
      {"schema_version", 1},
      {"units", "SI"},
      {"geometry",
       {{"type", "plate_with_central_hole"}, {"size", {0.1, 0.04}}, {"hole_radius", 0.008}}},
      {"discretization", {{"degree", 2}, {"elements", {2, 2}}}},
      {"analysis", {{"type", "plane_stress"}, {"thickness", 0.001}}},
      {"material", {{"E", 0.8 * s.true_modulus}, {"nu", 0.35}, {"density", 1200.0}}},
      {"boundary", {{{"patch", 0}, {"side", "v1"}, {"fix", {"x", "y"}}}}},
      {"load_cases",
       {{{"id", "pull"}, {"tractions", {traction(end, {2e6 * f, 0.0})}}},
        {{"id", "shear"}, {"tractions", {traction(end, {0.0, 2e5 * f})}}},
        {{"id", "pull_shear"}, {"tractions", {traction(end, {1e6 * f, 1e5 * f})}}}}}};
  s.truth_elements = {12, 12};
  s.gradient_axis = 0;
  s.is_marker = [](const Eigen::Vector3d&) { return true; };
  s.stride = 5;
  return s;
}

// Quarter tube, radii 20 and 26 mm, 120 mm long along z, clamped at z = 0 (side w0), loads on
// z = 120 mm (side w1): axial pull, shear along x, shear along y. Declared: degree 2 on
// 1 x 3 x 8 elements. Markers: ccx nodes of the outer surface, every 3rd.
Specimen tube(const Hidden& h) {
  Specimen s;
  s.true_modulus = 2e7;
  const double f = h.load_factor;
  const json end = {{"side", "w1"}};
  s.declared = {
      {"schema_version", 1},
      {"units", "SI"},
      {"geometry",
       {{"type", "tube"}, {"inner_radius", 0.02}, {"outer_radius", 0.026}, {"length", 0.12}}},
      {"discretization", {{"degree", 2}, {"elements", {1, 3, 8}}}},
      {"material", {{"E", 0.8 * s.true_modulus}, {"nu", 0.3}, {"density", 1000.0}}},
      {"boundary", {{{"side", "w0"}, {"fix", {"x", "y", "z"}}}}},
      {"load_cases",
       {{{"id", "axial"}, {"tractions", {traction(end, {0.0, 0.0, 40000.0 * f})}}},
        {{"id", "shear_x"}, {"tractions", {traction(end, {1000.0 * f, 0.0, 0.0})}}},
        {{"id", "shear_y"}, {"tractions", {traction(end, {0.0, -1000.0 * f, 0.0})}}}}}};
  s.truth_elements = {2, 8, 24};
  s.gradient_axis = 2;
  s.slab = 0.12 / 24;
  s.gravity = Eigen::Vector3d(0, -9.81, 0);
  s.is_marker = [](const Eigen::Vector3d& x) {
    return std::abs(std::hypot(x.x(), x.y()) - 0.026) < 1e-9 && x.z() > 0.005;
  };
  s.stride = 3;
  return s;
}

}  // namespace

Specimen specimen(const std::string& name, const Hidden& hidden) {
  if (name == "cantilever") return cantilever(hidden);
  if (name == "plate_with_hole") return plate_with_hole(hidden);
  return tube(hidden);
}

Specimen specimen(const Dataset& dataset) {
  Specimen s = specimen(dataset.specimen, dataset.hidden);
  if (dataset.poisson_ratio > 0.0) s.declared["material"]["nu"] = dataset.poisson_ratio;
  return s;
}

std::vector<Dataset> datasets() {
  std::vector<Dataset> all;
  auto add = [&](std::string name, std::string specimen_name, std::vector<std::string> effects,
                 double noise, unsigned seed, Hidden hidden, std::string note) {
    all.push_back({std::move(name),
                   std::move(specimen_name),
                   std::move(effects),
                   noise,
                   seed,
                   hidden,
                   std::move(note),
                   0.0,
                   {}});
  };
  const Hidden none;
  Hidden gravity;
  gravity.gravity = true;
  Hidden soft_clamp;
  soft_clamp.soft_layer = 0.25;
  Hidden graded;
  graded.gradient = 0.4;
  Hidden scaled;
  scaled.load_scale = 1.15;
  Hidden frame;
  frame.frame_translation = Eigen::Vector3d(2e-5, -1e-5, 1.5e-5);
  frame.frame_rotation = Eigen::Vector3d(0.0, 1e-4, 2e-4);
  Hidden large;
  large.nonlinear = true;
  large.load_factor = 6.0;
  Hidden frame_2d;
  frame_2d.frame_translation = Eigen::Vector3d(3e-6, -2e-6, 0.0);
  frame_2d.frame_rotation = Eigen::Vector3d(0.0, 0.0, 5e-5);

  add("cantilever_clean", "cantilever", {}, 2e-3, 11, none, "nothing hidden, noise 0.2 %");
  add("cantilever_clean_noisy", "cantilever", {}, 1e-2, 12, none, "nothing hidden, noise 1 %");
  add("cantilever_gravity", "cantilever", {"gravity"}, 2e-3, 13, gravity, "self-weight");
  add("cantilever_soft_clamp", "cantilever", {"support_compliance"}, 2e-3, 14, soft_clamp,
      "3.3 mm slab at the clamp 4x softer");
  add("cantilever_frame", "cantilever", {"rigid_offset"}, 2e-3, 15, frame,
      "measuring frame moved 27 um, rotated 0.2 mrad");
  add("cantilever_load_scale", "cantilever", {"load_scale"}, 2e-3, 16, scaled,
      "tip_side's load 15 % above nominal");
  add("cantilever_large_deformation", "cantilever", {"geometric_nonlinearity"}, 2e-3, 17, large,
      "loads x6: tip deflection 12 % of the length (ccx NLGEOM)");
  add("plate_clean", "plate_with_hole", {}, 2e-3, 21, none, "nothing hidden, noise 0.2 %");
  add("plate_clean_noisy", "plate_with_hole", {}, 1e-2, 22, none, "nothing hidden, noise 1 %");
  add("plate_graded", "plate_with_hole", {"stiffness_gradient"}, 2e-3, 23, graded,
      "E rises 40 % per plate length along x");
  add("plate_frame", "plate_with_hole", {"rigid_offset"}, 2e-3, 24, frame_2d,
      "measuring frame moved 3.6 um, rotated 0.05 mrad");
  add("tube_clean", "tube", {}, 2e-3, 31, none, "nothing hidden, noise 0.2 %");
  add("tube_gravity", "tube", {"gravity"}, 2e-3, 32, gravity, "self-weight");
  add("tube_graded", "tube", {"stiffness_gradient"}, 2e-3, 33, graded,
      "E rises 40 % per tube length along z");

  // Tissue-like: the cantilever at nu = 0.45 and 0.49 with every hidden effect of the suite (the
  // graded modulus along its length too) and two pairs of effects, noise 0.2 %.
  Hidden gravity_soft_clamp = soft_clamp;
  gravity_soft_clamp.gravity = true;
  Hidden frame_gravity = frame;
  frame_gravity.gravity = true;
  const std::vector<std::tuple<std::string, std::vector<std::string>, Hidden, std::string>> tissue =
      {{"clean", {}, none, "nothing hidden"},
       {"gravity", {"gravity"}, gravity, "self-weight"},
       {"soft_clamp", {"support_compliance"}, soft_clamp, "3.3 mm slab at the clamp 4x softer"},
       {"frame", {"rigid_offset"}, frame, "measuring frame moved 27 um, rotated 0.2 mrad"},
       {"load_scale", {"load_scale"}, scaled, "tip_side's load 15 % above nominal"},
       {"large_deformation",
        {"geometric_nonlinearity"},
        large,
        "loads x6, large deformation (ccx NLGEOM)"},
       {"graded", {"stiffness_gradient"}, graded, "E rises 40 % per length along x"},
       {"gravity_soft_clamp",
        {"gravity", "support_compliance"},
        gravity_soft_clamp,
        "self-weight and a 3.3 mm slab at the clamp 4x softer"},
       {"frame_gravity",
        {"gravity", "rigid_offset"},
        frame_gravity,
        "self-weight, measuring frame moved 27 um, rotated 0.2 mrad"}};
  for (const auto& [nu, suffix, first_seed] :
       {std::tuple{0.45, "_nu045", 41u}, std::tuple{0.49, "_nu049", 61u}}) {
    unsigned seed = first_seed;
    for (const auto& [effect, effects, hidden, note] : tissue) {
      add("cantilever_" + effect + suffix, "cantilever", effects, 2e-3, seed++, hidden,
          note + ", nu = " + (nu == 0.45 ? "0.45" : "0.49") + ", noise 0.2 %");
      all.back().poisson_ratio = nu;
      // A soft slab at the clamp of a nearly incompressible body: the uniform 60 x 12 x 12
      // reference is not converged there (its mesh check fails); graded towards the clamp, the
      // slab and the faces it meets.
      if (nu == 0.49 && hidden.soft_layer > 0.0) all.back().grading = {1, 4, 2};
    }
  }
  return all;
}

}  // namespace isospring::identify_suite
