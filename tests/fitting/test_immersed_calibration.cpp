// The spring model of an immersed part (fitting/immersed_calibration.hpp) checked against what it
// must reproduce: on a block whose faces lie on the background grid's boundary (no cut cell) the
// body-fitted calibration of the same block and grid (particles, springs, masses, loads, and the
// fitted stiffnesses given the same reference); on a cut cylinder the part's mass and the
// applied loads from OpenCascade's volume and area, and the held layer of the net.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/analysis/immersed_particles.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/immersed_calibration.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {
namespace {

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";

analysis::Material steel() {
  analysis::Material m;
  m.youngs_modulus = 2.1e11;
  m.poisson_ratio = 0.3;
  m.density = 7850.0;
  return m;
}

// The face whose boundary points all lie on the plane x[axis] = at.
int face_on_plane(const geometry::ImmersedDomain& domain, int axis, double at) {
  for (int f = 0; f < domain.face_count; ++f) {
    bool all = true, any = false;
    for (const auto& b : domain.boundary)
      if (b.face == f) {
        any = true;
        all = all && std::abs(b.point[axis] - at) < 1e-12;
      }
    if (any && all) return f;
  }
  return -1;
}

double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

// block.step: 0.1 x 0.02 x 0.02 m from the origin. With margin 0 the background box is the block,
// so every cell is inside and the background patch is a body-fitted model of the same block.
struct AlignedBlock {
  geometry::ImmersedDomain domain;
  int clamp = -1, end = -1;
  std::vector<ImmersedCalibrationCase> cases;
  analysis::Problem problem;  // the same block, grid, supports and loads, body-fitted
};

AlignedBlock aligned_block() {
  AlignedBlock b;
  geometry::ImmersionOptions o;
  o.degree = 2;
  o.cells = Eigen::Vector3i(4, 2, 2);
  b.domain = geometry::immerse_solid(geometry::read_cad_solid(kExamples + "cad/block.step"), o);
  b.clamp = face_on_plane(b.domain, 0, b.domain.origin.x());
  b.end = face_on_plane(b.domain, 0, b.domain.origin.x() + b.domain.extent.x());
  b.problem.patches = {b.domain.background};
  b.problem.material = steel();
  analysis::Support clamp;
  clamp.side = analysis::parse_side("u0");
  clamp.fixed = {true, true, true};
  b.problem.supports = {clamp};
  const std::vector<std::pair<std::string, Eigen::Vector3d>> tractions = {
      {"pull", {2e6, 0, 0}}, {"bend_z", {0, 0, -4e5}}, {"bend_y", {0, 3e5, 0}}};
  for (const auto& [id, t] : tractions) {
    ImmersedCalibrationCase c;
    c.id = id;
    c.options.material = steel();
    c.options.supports = {{b.clamp, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
    c.options.tractions = {{b.end, t, nullptr}};
    b.cases.push_back(c);
    analysis::LoadCase lc;
    lc.id = id;
    lc.tractions = {{analysis::parse_side("u1"), t, nullptr}};
    b.problem.load_cases.push_back(lc);
  }
  const std::vector<std::pair<std::string, Eigen::Vector3d>> body = {
      {"weight", {0, 0, -9.81 * 7850.0}}, {"body_x", {4e5, 0, 0}}, {"body_y", {0, -2e5, 3e4}}};
  for (const auto& [id, force] : body) {
    ImmersedCalibrationCase c = b.cases.front();
    c.id = id;
    c.options.tractions.clear();
    analysis::LoadCase lc;
    lc.id = id;
    if (id == "weight") {
      c.options.gravity = lc.gravity = force / 7850.0;
    } else {
      c.options.body_force = lc.body_force = force;
    }
    b.cases.push_back(c);
    b.problem.load_cases.push_back(lc);
  }
  return b;
}

// Fitted: loads integrated over the cells (exact Gauss rules on both paths); held out: tractions
// (integrated on the part's faces to the face quadrature's 1e-9).
CalibrationSettings block_settings() {
  CalibrationSettings s;
  s.fit_cases = {"weight", "body_x", "body_y"};
  s.holdout_cases = {"bend_y"};
  s.gamma = 0.01;
  return s;
}

TEST(ImmersedCalibration, AlignedBlockIsTheBodyFittedCalibration) {
  const AlignedBlock b = aligned_block();
  for (const auto& cell : b.domain.cells) ASSERT_EQ(cell.kind, geometry::CellKind::kInside);
  ASSERT_GE(b.clamp, 0);
  ASSERT_GE(b.end, 0);
  const ImmersedCalibrationResult immersed =
      calibrate_immersed(b.domain, b.cases, block_settings());
  // The body-fitted calibration of the same grid, fitted to the immersed reference: everything
  // but the reference is built by the body-fitted path.
  CalibrationSettings settings = block_settings();
  for (const auto& r : immersed.reference) {
    Eigen::VectorXd u(3 * static_cast<Eigen::Index>(r.control_displacements.size()));
    for (size_t a = 0; a < r.control_displacements.size(); ++a)
      u.segment<3>(3 * static_cast<Eigen::Index>(a)) = r.control_displacements[a];
    settings.reference_displacements.push_back(u);
  }
  const CalibrationResult fitted = calibrate(b.problem, settings);
  // The reference is the immersed solution analysis::solve_immersed gives.
  for (size_t c : {size_t{0}, size_t{3}}) {
    const analysis::ImmersedResult solved = analysis::solve_immersed(b.domain, b.cases[c].options);
    double worst = 0.0, largest = 0.0;
    for (size_t a = 0; a < solved.control_displacements.size(); ++a) {
      worst = std::max(
          worst, (solved.control_displacements[a] - immersed.reference[c].control_displacements[a])
                     .norm());
      largest = std::max(largest, solved.control_displacements[a].norm());
    }
    EXPECT_LT(worst, 1e-12 * largest) << b.cases[c].id;
  }
  const analysis::SpringNetwork& a = immersed.calibration.mesh.network;
  const analysis::SpringNetwork& f = fitted.mesh.network;

  // Particles: every control point is active, in the same order, at the same place.
  ASSERT_EQ(a.positions.size(), f.positions.size());
  ASSERT_EQ(a.positions.size(), static_cast<size_t>(b.domain.background.num_points()));
  for (size_t q = 0; q < a.positions.size(); ++q) {
    EXPECT_LT((a.positions[q] - f.positions[q]).norm(), 1e-15);
    EXPECT_NEAR(a.masses[q], f.masses[q], 1e-12 * f.masses[q]) << q;
    EXPECT_EQ(a.fixed[q], f.fixed[q]) << q;
  }
  // Springs: the same pairs in the same order (the closed-form count of the net).
  ASSERT_EQ(a.springs.size(), f.springs.size());
  EXPECT_EQ(static_cast<long>(a.springs.size()), expected_spring_count(6, 4, 4));
  for (size_t s = 0; s < a.springs.size(); ++s) {
    EXPECT_EQ(a.springs[s].i, f.springs[s].i);
    EXPECT_EQ(a.springs[s].j, f.springs[s].j);
  }
  // Loads: body forces over the cells (the same Gauss rules: round-off), tractions on the part's
  // faces (Gauss pieces that need not break at the knots, doubled until area and moments repeat
  // to 1e-9) vs the patch's sides.
  for (size_t c = 0; c < b.cases.size(); ++c) {
    const bool traction = !b.cases[c].options.tractions.empty();
    EXPECT_LT(relative_difference(immersed.calibration.particle_loads[c], fitted.particle_loads[c]),
              traction ? 1e-8 : 1e-12)
        << b.cases[c].id;
  }
  // The fit: the same data give the same stiffnesses and errors.
  ASSERT_EQ(immersed.calibration.fit_result.group_stiffness.size(),
            fitted.fit_result.group_stiffness.size());
  // Stiffnesses: Levenberg-Marquardt stops where the cost's relative decrease falls below its
  // tolerance, and along the cost's flat directions (groups that barely change the fitted
  // displacements) a 1e-12 change of the loads moves that point: by 1.6e-7 with two threads and
  // 1.2e-6 with one (the loads' round-off follows the assembly's summation order), and by
  // 1.1e-5 once the fit summed its stiffness per group in another order, in the measurements.
  // 1e-4 still fails for any wrong particle, spring, mass or support (an O(1) change). The
  // errors below, the well-determined outcome, agree to 1e-10.
  for (size_t g = 0; g < fitted.fit_result.group_stiffness.size(); ++g)
    EXPECT_NEAR(
        immersed.calibration.fit_result.group_stiffness[g] / fitted.fit_result.group_stiffness[g],
        1.0, 1e-4);
  // The held-out traction case: its load agrees to the face quadrature's 1e-9.
  ASSERT_EQ(immersed.calibration.holdout.size(), 1u);
  EXPECT_NEAR(immersed.calibration.holdout[0].control.percent_e_rms /
                  fitted.holdout[0].control.percent_e_rms,
              1.0, 1e-8);
  for (size_t c = 0; c < immersed.calibration.fit.size(); ++c)
    EXPECT_NEAR(
        immersed.calibration.fit[c].control.percent_e_rms / fitted.fit[c].control.percent_e_rms,
        1.0, 1e-10);
}

// The reference holds the clamp weakly (Nitsche), the body-fitted solve strongly: both solve the
// same problem, so their coefficients approach each other as the Nitsche penalty grows (the
// difference is the weak imposition's, O(1 / penalty) at a fixed grid).
TEST(ImmersedCalibration, ReferenceApproachesTheStronglyClampedSolution) {
  AlignedBlock b = aligned_block();
  const analysis::StaticResult strong = analysis::solve_static(b.problem);
  std::vector<double> differences;
  for (double factor : {4.0, 40.0, 400.0}) {
    analysis::ImmersedOptions o = b.cases[1].options;
    o.nitsche_factor = factor;
    const analysis::ImmersedResult weak = analysis::solve_immersed(b.domain, o);
    const auto& u = strong.load_cases[1].control_displacements[0];
    double worst = 0.0, largest = 0.0;
    for (size_t a = 0; a < u.size(); ++a) {
      worst = std::max(worst, (weak.control_displacements[a] - u[a]).norm());
      largest = std::max(largest, u[a].norm());
    }
    differences.push_back(worst / largest);
  }
  std::printf(
      "Nitsche factor 4, 40, 400: largest coefficient difference %.3g, %.3g, %.3g of the "
      "largest displacement\n",
      differences[0], differences[1], differences[2]);
  EXPECT_LT(differences[0], 0.05);
  EXPECT_LT(differences[1], 0.5 * differences[0]);
  EXPECT_LT(differences[2], 0.5 * differences[1]);
}

TEST(ImmersedCalibration, CutCylinderMassesLoadsAndHeldLayer) {
  const geometry::CadSolid solid =
      geometry::read_cad_solid(kExamples + "immersed/cube_cylinder.step", 0);
  geometry::ImmersionOptions o;
  o.degree = 2;
  o.cells = Eigen::Vector3i(4, 4, 4);
  const geometry::ImmersedDomain domain = geometry::immerse_solid(solid, o);
  const geometry::SolidMeasures occ = geometry::measure_solid(solid);
  // The end disks: the two faces flat in one coordinate (OpenCascade's box, and so the grid, is
  // the part's enlarged by the edges' tolerance, 1e-7 m: the disks lie that far inside it).
  int axis = -1, clamp = -1, end = -1;
  for (int f = 0; f < domain.face_count; ++f)
    for (int d = 0; d < 3; ++d) {
      double lo = 1e300, hi = -1e300;
      for (const auto& b : domain.boundary)
        if (b.face == f) lo = std::min(lo, b.point[d]), hi = std::max(hi, b.point[d]);
      if (!(hi >= lo) || hi - lo > 1e-12) continue;  // no point (the cube's faces) or not flat
      axis = d;
      (lo < domain.origin[d] + 0.5 * domain.extent[d] ? clamp : end) = f;
    }
  ASSERT_GE(axis, 0);
  ASSERT_GE(clamp, 0);
  ASSERT_GE(end, 0);
  ImmersedCalibrationCase weight;
  weight.id = "weight";
  weight.options.material = steel();
  weight.options.supports = {{clamp, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
  weight.options.gravity[(axis + 1) % 3] = -9.81;
  ImmersedCalibrationCase push = weight;
  push.id = "push";
  push.options.gravity.setZero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  t[(axis + 2) % 3] = 1e5;
  push.options.tractions = {{end, t, nullptr}};
  ImmersedCalibrationCase pull = push;
  pull.id = "pull";
  pull.options.tractions[0].value = Eigen::Vector3d::Zero();
  pull.options.tractions[0].value[axis] = 2e5;
  CalibrationSettings settings;
  settings.fit_cases = {"weight", "pull"};
  settings.holdout_cases = {"push"};
  const auto start = std::chrono::steady_clock::now();
  const ImmersedCalibrationResult r = calibrate_immersed(domain, {weight, push, pull}, settings);
  std::printf("calibrate_immersed %.2f s (assembly %.2f, reference %.2f, fit %.2f)\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              r.assembly_seconds, r.calibration.reference_seconds, r.calibration.fit_seconds);
  const analysis::SpringNetwork& net = r.calibration.mesh.network;

  // The references (one assembly, then each further case's loads alone) are solve_immersed's
  // solutions, which assemble every case whole: the same coefficients to round-off.
  const std::vector<const ImmersedCalibrationCase*> all{&weight, &push, &pull};
  ASSERT_EQ(r.reference.size(), all.size());
  for (size_t c = 0; c < all.size(); ++c) {
    const analysis::ImmersedResult whole = analysis::solve_immersed(domain, all[c]->options);
    double largest = 0.0, difference = 0.0;
    for (size_t cp = 0; cp < whole.control_displacements.size(); ++cp) {
      largest = std::max(largest, whole.control_displacements[cp].cwiseAbs().maxCoeff());
      difference = std::max(
          difference, (r.reference[c].control_displacements[cp] - whole.control_displacements[cp])
                          .cwiseAbs()
                          .maxCoeff());
    }
    std::printf("reference %s: max difference %.2e of max |u| %.3e\n", all[c]->id.c_str(),
                difference, largest);
    EXPECT_GT(largest, 0.0);
    EXPECT_LE(difference, 1e-13 * largest) << all[c]->id;
  }

  // The disks' distance from their boundary points (the grid's box is larger by OpenCascade's
  // tolerance): the radius from OpenCascade's volume.
  double at[2] = {0.0, 0.0};
  for (const auto& b : domain.boundary)
    if (b.face == clamp || b.face == end) at[b.face == end] = b.point[axis];
  const double height = std::abs(at[1] - at[0]);
  const double radius = std::sqrt(occ.volume / (M_PI * height));
  // Mass: rho times the part's volume (OpenCascade's; the quadrature's agrees to 1e-6).
  double mass = 0.0;
  for (double m : net.masses) {
    EXPECT_GT(m, 0.0);
    mass += m;
  }
  EXPECT_NEAR(mass / (steel().density * occ.volume), 1.0, 1e-6);
  // Loads: the particle forces sum to the applied totals (the splines sum to one).
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (size_t q = 0; q < net.positions.size(); ++q)
    total += r.calibration.particle_loads[0].segment<3>(3 * static_cast<Eigen::Index>(q));
  EXPECT_LT((total - mass * weight.options.gravity).norm(), 1e-9 * mass * 9.81);
  total.setZero();
  for (size_t q = 0; q < net.positions.size(); ++q)
    total += r.calibration.particle_loads[1].segment<3>(3 * static_cast<Eigen::Index>(q));
  EXPECT_NEAR(total[(axis + 2) % 3] / (1e5 * M_PI * radius * radius), 1.0, 1e-6);
  // Held: the active control points of the net's first layer along the axis (open knots: only
  // those functions reach the plane of the clamped disk), every component.
  // A first-layer function whose control point (its Greville point) lies within the disk's
  // radius is positive on part of the disk, so it is held; one beyond the rim may or may not be.
  const Eigen::Vector3d centre = domain.origin + 0.5 * domain.extent;
  for (size_t q = 0; q < net.positions.size(); ++q) {
    const auto ijk = domain.background.net_position(r.control_point_of_particle[q]);
    const bool on_layer = ijk[static_cast<size_t>(axis)] == 0;
    Eigen::Vector3d off_axis = net.positions[q] - centre;
    off_axis[axis] = 0.0;
    if (!on_layer) {
      EXPECT_FALSE(net.fixed[q]) << q;
    }
    if (on_layer && off_axis.norm() < radius) {
      EXPECT_TRUE(net.fixed[q]) << q;
    }
  }
  EXPECT_GT(r.held_particles, 0);
  // Every particle is in a spring.
  std::vector<int> springs(net.positions.size(), 0);
  for (const auto& s : net.springs) ++springs[s.i], ++springs[s.j];
  for (int n : springs) EXPECT_GT(n, 0);
  // The fitted cases and the held-out one are measured; errors are finite and below 100 %.
  ASSERT_EQ(r.calibration.holdout.size(), 1u);
  EXPECT_EQ(r.calibration.holdout[0].id, "push");
  EXPECT_LT(r.calibration.holdout[0].control.percent_e_rms, 100.0);
  EXPECT_GT(r.calibration.holdout[0].field.points, 0);
  std::printf(
      "cylinder: %zu particles, %zu springs, %d held; held-out %%e_rms %.3g (field %.3g, "
      "surface %.3g), fitted %.3g %.3g\n",
      net.positions.size(), net.springs.size(), r.held_particles,
      r.calibration.holdout[0].control.percent_e_rms, r.calibration.holdout[0].field.percent_e_rms,
      r.calibration.holdout[0].surface.percent_e_rms, r.calibration.fit[0].control.percent_e_rms,
      r.calibration.fit[1].control.percent_e_rms);
}

TEST(ImmersedCalibration, SettingsWithoutAnImmersedFormAreRefused) {
  const AlignedBlock b = aligned_block();
  CalibrationSettings s = block_settings();
  s.matrix_approach = true;
  EXPECT_THROW(calibrate_immersed(b.domain, b.cases, s), nurbs::InputError);
  s = block_settings();
  s.fit_cases = {"nope"};
  EXPECT_THROW(calibrate_immersed(b.domain, b.cases, s), nurbs::InputError);
  std::vector<ImmersedCalibrationCase> moved = b.cases;
  moved[0].options.supports[0].value = Eigen::Vector3d(1e-3, 0, 0);
  EXPECT_THROW(calibrate_immersed(b.domain, moved, block_settings()), nurbs::InputError);
  moved = b.cases;
  moved[1].options.supports[0].fixed = {true, false, false};
  EXPECT_THROW(calibrate_immersed(b.domain, moved, block_settings()), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::fitting
