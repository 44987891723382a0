// The measured-data loop on an immersed part (identify_immersed.hpp). Its forward model against
// the immersed solver itself (analysis::solve_immersed evaluated at the markers), and the loop
// on synthetic data of that model: a hidden effect is named and nothing else, its parameters
// within 3 standard errors of the truth, the residual at the noise level; clean data add nothing.
// The check against data the immersed code did not produce (CalculiX on a gmsh mesh of a CAD
// part) is tests/workflows/test_identify_immersed_calculix.cpp.
#include "isospring/fitting/identify_immersed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";
using Effects = std::vector<std::pair<std::string, Eigen::VectorXd>>;
constexpr double kTrueScale = 1.1;  // E_true / E_prior

// CadQuery's cylinder (r 5 mm, h 10 mm along z) in a 4 x 4 x 4 quadratic grid, clamped on its
// end disk (face 0), three tractions on the other end disk (face 1).
struct Cylinder {
  geometry::ImmersedDomain domain;
  std::vector<ImmersedCalibrationCase> cases;
  std::vector<Marker> markers;
};

analysis::Material soft(double scale = 1.0) {
  analysis::Material m;
  m.youngs_modulus = 1e6 * scale;
  m.poisson_ratio = 0.3;
  m.density = 1100.0;
  return m;
}

// Immersed once for all tests (the cut cells' quadrature is most of a test's CPU).
const geometry::ImmersedDomain& cylinder_domain() {
  static const geometry::ImmersedDomain domain = [] {
    geometry::ImmersionOptions o;
    o.degree = 2;
    o.cells = Eigen::Vector3i(4, 4, 4);
    return geometry::immerse_solid(
        geometry::read_cad_solid(kExamples + "immersed/cube_cylinder.step", 0), o);
  }();
  return domain;
}

Cylinder cylinder(double e_scale = 1.0) {
  Cylinder c;
  c.domain = cylinder_domain();
  const std::vector<std::pair<std::string, Eigen::Vector3d>> tractions = {
      {"shear_x", {200, 0, 0}}, {"axial", {0, 0, 500}}, {"shear_y", {0, 200, 0}}};
  for (const auto& [id, t] : tractions) {
    ImmersedCalibrationCase lc;
    lc.id = id;
    lc.options.material = soft(e_scale);
    lc.options.supports = {{0, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
    lc.options.tractions = {{1, t, nullptr}};
    c.cases.push_back(lc);
  }
  // Markers on the free end disk and the mantle (every 7th boundary quadrature point).
  int k = 0;
  for (const auto& b : c.domain.boundary) {
    if (b.face == 0 || k++ % 7 != 0) continue;
    for (const auto& lc : c.cases) {
      Marker m;
      m.load_case = lc.id;
      m.position = b.point;
      m.row = static_cast<int>(c.markers.size()) + 2;
      c.markers.push_back(m);
    }
  }
  return c;
}

// Data of the immersed model with E_true = kTrueScale E_prior and the hidden effects, plus
// Gaussian noise of `sigma` per component; returns sigma.
double add_data(Cylinder& c, const Effects& hidden, double noise_fraction, unsigned seed) {
  const Cylinder truth = cylinder(kTrueScale);
  const std::vector<Eigen::Vector3d> u =
      simulate_immersed_markers(truth.domain, truth.cases, c.markers, hidden);
  double largest = 0.0;
  for (const auto& v : u) largest = std::max(largest, v.norm());
  const double sigma = noise_fraction * largest;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (size_t m = 0; m < u.size(); ++m)
    for (int i = 0; i < 3; ++i) c.markers[m].displacement[i] = u[m][i] + noise(rng);
  return sigma;
}

TEST(IdentifyImmersed, ForwardModelIsTheImmersedSolution) {
  const Cylinder c = cylinder();
  const std::vector<Eigen::Vector3d> model =
      simulate_immersed_markers(c.domain, c.cases, c.markers, {});
  double worst = 0.0, largest = 0.0;
  for (size_t l = 0; l < c.cases.size(); ++l) {
    const analysis::ImmersedResult solved = analysis::solve_immersed(c.domain, c.cases[l].options);
    for (size_t m = 0; m < c.markers.size(); ++m) {
      if (c.markers[m].load_case != c.cases[l].id) continue;
      const Eigen::Vector3d u =
          analysis::evaluate_immersed(c.domain, solved, c.markers[m].position).displacement;
      worst = std::max(worst, (u - model[m]).norm());
      largest = std::max(largest, u.norm());
    }
  }
  ASSERT_GT(largest, 0.0);
  // Two Cholesky solves of the same system: round-off only.
  EXPECT_LT(worst, 1e-9 * largest);
}

TEST(IdentifyImmersed, GravityOfTheDeclaredDensityScalesLikeTheDeclaredLoad) {
  // simulate_immersed_markers with a gravity effect g equals the solver with gravity g declared
  // in every case (the self-weight's load vector is the immersed assembly's).
  Cylinder c = cylinder();
  const Eigen::Vector3d g(-9.81, 0.0, 4.0);
  const std::vector<Eigen::Vector3d> model =
      simulate_immersed_markers(c.domain, c.cases, c.markers, {{"gravity", g}});
  double worst = 0.0, largest = 0.0;
  for (auto& lc : c.cases) {
    lc.options.gravity = g;
    const analysis::ImmersedResult solved = analysis::solve_immersed(c.domain, lc.options);
    for (size_t m = 0; m < c.markers.size(); ++m)
      if (c.markers[m].load_case == lc.id) {
        const Eigen::Vector3d u =
            analysis::evaluate_immersed(c.domain, solved, c.markers[m].position).displacement;
        worst = std::max(worst, (u - model[m]).norm());
        largest = std::max(largest, u.norm());
      }
  }
  EXPECT_LT(worst, 1e-9 * largest);
}

void expect_identified(const Effects& hidden, unsigned seed) {
  Cylinder c = cylinder();
  const double sigma = add_data(c, hidden, 0.002, seed);
  IdentifyOptions options;
  options.holdout = false;
  const IdentifyResult r = identify_immersed(c.domain, c.cases, c.markers, options);
  std::set<std::string> expected, found(r.effects_added.begin(), r.effects_added.end());
  for (const auto& [name, values] : hidden) expected.insert(name);
  EXPECT_EQ(found, expected);
  EXPECT_LT(r.after.rms, 1.3 * sigma);
  EXPECT_NEAR(r.noise_estimate, sigma, 0.2 * sigma);
  ASSERT_FALSE(r.parameters.empty());
  EXPECT_LT(std::abs(r.parameters[0].value - kTrueScale * 1e6), 3 * r.parameters[0].standard_error);
  EXPECT_EQ(r.discretization.done, false);
  EXPECT_NE(r.discretization.note.find("immersed"), std::string::npos) << r.discretization.note;
  if (found != expected) return;
  for (const auto& [name, values] : hidden) {
    size_t k = 0;
    for (const auto& p : r.parameters)
      if (p.effect == name) {
        const double truth = values[static_cast<Eigen::Index>(k++)];
        EXPECT_LT(std::abs(p.value - truth), 3 * p.standard_error)
            << name << "." << p.name << " = " << p.value << " +- " << p.standard_error;
      }
    EXPECT_EQ(k, static_cast<size_t>(values.size()));
  }
}

TEST(IdentifyImmersed, FindsUndeclaredSelfWeight) {
  expect_identified({{"gravity", Eigen::Vector3d(-9.81, 0.0, 0.0)}}, 3);
}

TEST(IdentifyImmersed, FindsLoadScale) {
  expect_identified({{"load_scale", Eigen::Vector2d(0.05, -0.04)}}, 4);
}

TEST(IdentifyImmersed, CleanDataAddNothing) {
  expect_identified({}, 5);
}

TEST(IdentifyImmersed, EffectsWithoutAnImmersedFormAreListedWithTheReason) {
  Cylinder c = cylinder();
  add_data(c, {}, 0.002, 6);
  IdentifyOptions options;
  options.holdout = false;
  options.candidates = std::vector<std::string>{"support_compliance", "stiffness_gradient",
                                                "geometric_nonlinearity", "rigid_offset"};
  const IdentifyResult r = identify_immersed(c.domain, c.cases, c.markers, options);
  ASSERT_FALSE(r.rounds.empty());
  std::set<std::string> unavailable, tried;
  for (const auto& t : r.rounds.front().candidates) {
    if (t.note.find("not available for immersed models") != std::string::npos)
      unavailable.insert(t.effect);
    else
      tried.insert(t.effect);
  }
  EXPECT_EQ(unavailable, (std::set<std::string>{"support_compliance", "stiffness_gradient",
                                                "geometric_nonlinearity"}));
  EXPECT_EQ(tried, std::set<std::string>{"rigid_offset"});
}

TEST(IdentifyImmersed, RefusesWhatItCannotFit) {
  Cylinder c = cylinder();
  add_data(c, {}, 0.002, 7);
  IdentifyOptions poisson;
  poisson.fit_poisson = true;
  EXPECT_THROW(identify_immersed(c.domain, c.cases, c.markers, poisson), nurbs::InputError);
  // A marker far outside the part (beyond the background grid).
  Cylinder off = c;
  off.markers[3].position += Eigen::Vector3d(1.0, 0.0, 0.0);
  EXPECT_EQ(immersed_markers_outside(off.domain, off.markers), std::vector<int>{3});
  EXPECT_THROW(identify_immersed(off.domain, off.cases, off.markers), nurbs::InputError);
  // Supports that differ between load cases.
  Cylinder held = c;
  held.cases[1].options.supports[0].fixed = {true, true, false};
  EXPECT_THROW(identify_immersed(held.domain, held.cases, held.markers), nurbs::InputError);
  // A non-zero support value.
  Cylinder moved = c;
  for (auto& lc : moved.cases) lc.options.supports[0].value = Eigen::Vector3d(1e-6, 0, 0);
  EXPECT_THROW(identify_immersed(moved.domain, moved.cases, moved.markers), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
