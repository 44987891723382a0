// The neo-Hookean IGA reference against CalculiX's *HYPERELASTIC, NEO HOOKE with NLGEOM on the same
// parts at about 30 % strain: C3D20 hexahedra (full integration) on a mesh of their own, shown
// converged by a finer one, against the IGA solution (analysis::solve_static_nonlinear). Both
// solve the same problem: prescribed displacements, or dead loads (the deck's consistent nodal
// *CLOAD forces keep their direction, as isospring's tractions act on the reference
// configuration). Skipped when ccx (Debian package calculix-ccx) is not on PATH.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>

#include "isospring/analysis/neo_hookean.hpp"
#include "isospring/analysis/nonlinear_elasticity.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using Eigen::Vector3d;

constexpr double kE = 1000.0, kNu = 0.3;

bool ccx_available() {
  return std::system("command -v ccx > /dev/null 2>&1") == 0;
}

// The box [0, size] of the given degree with elements[d] equal spans in direction d.
nurbs::Patch box(const Vector3d& size, int degree, const std::array<int, 3>& elements) {
  std::vector<Vector3d> corners;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) corners.emplace_back(i * size.x(), j * size.y(), k * size.z());
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  nurbs::Patch patch =
      nurbs::elevate_degree(nurbs::Patch({linear, linear, linear}, corners), degree - 1);
  for (int d = 0; d < 3; ++d)
    patch = nurbs::refine_uniform(patch, d, elements[static_cast<size_t>(d)]);
  return patch;
}

analysis::Support symmetry(int dir) {
  analysis::Support s;
  s.side = {0, dir, 0};
  s.symmetry = true;
  return s;
}

// What both solvers report: the displacement of one point and the reaction (x) on the side
// x = size.x() (0 under a load).
struct Answer {
  Vector3d displacement = Vector3d::Constant(NAN);
  double reaction = NAN;
  double seconds = 0.0;
  int steps = 0, iterations = 0;           // isospring's Newton: load steps, iterations
  analysis::ControlDisplacements control;  // isospring's solution
};

double elapsed(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// isospring: Newton on the neo-Hookean law; the point must be a corner (interpolatory) control
// point, the reaction is the internal force summed over the x DOFs on x = length.
Answer iga(const analysis::Problem& problem, const Vector3d& point, double length) {
  const auto start = std::chrono::steady_clock::now();
  analysis::NonlinearOptions options;
  options.material = analysis::HyperelasticMaterial::kNeoHookean;
  const auto result = analysis::solve_static_nonlinear(problem, options);
  Answer out;
  const auto& points = problem.patches[0].control_points();
  const analysis::DofMap dofs(problem);
  const analysis::NeoHookeanAssembler assembler(problem, dofs);
  const Eigen::VectorXd internal = assembler.internal_force(
      result[0].displacement,
      analysis::neo_hookean_parameters(problem.material, problem.formulation));
  out.reaction = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if ((points[i] - point).norm() < 1e-12)
      out.displacement = result[0].control_displacements[0][i];
    if (std::abs(points[i].x() - length) < 1e-12)
      out.reaction += internal[dofs.dof(0, static_cast<int>(i), 0)];
  }
  out.seconds = elapsed(start);
  out.steps = result[0].load_steps;
  out.iterations = result[0].iterations;
  out.control = result[0].control_displacements;
  return out;
}

// ccx: the deck of `problem` (one C3D20 element per knot span), neo-Hookean, NLGEOM.
Answer ccx(const analysis::Problem& problem, const Vector3d& point, double length,
           const std::string& name) {
  const auto start = std::chrono::steady_clock::now();
  CalculixOptions options;
  options.element_type = "C3D20";
  options.nonlinear = true;
  options.neo_hookean = true;
  options.print_reactions = true;
  options.newton_tolerance = 1e-9;
  const CalculixDeck deck = make_calculix_deck(problem, options);
  const fs::path dir = fs::temp_directory_path() /
                       ("isospring-neo-hookean-" + std::to_string(getpid()) + "-" + name);
  fs::create_directories(dir);
  std::ofstream(dir / "deck.inp") << deck.text;
  const std::string command = "cd '" + dir.string() + "' && ccx -i deck > ccx.log 2>&1";
  Answer out;
  if (std::system(command.c_str()) != 0) {
    ADD_FAILURE() << "ccx failed; see " << dir / "ccx.log";
    return out;
  }
  const auto u = read_calculix_dat(dir / "deck.dat");
  const auto rf = read_calculix_reactions(dir / "deck.dat");
  out.reaction = 0.0;
  for (size_t n = 0; n < deck.nodes.size(); ++n) {
    const int node = static_cast<int>(n) + 1;
    if ((deck.nodes[n] - point).norm() < 1e-12) out.displacement = u.back().nodes.at(node);
    if (std::abs(deck.nodes[n].x() - length) < 1e-12) out.reaction += rf.back().nodes.at(node).x();
  }
  out.seconds = elapsed(start);
  if (!std::getenv("ISOSPRING_KEEP_TEST_FOLDERS")) fs::remove_all(dir);
  return out;
}

double relative(double a, double b) {
  return std::abs(a - b) / std::abs(b);
}
double relative(const Vector3d& a, const Vector3d& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace

// A quarter of a 2 x 1 x 1 block (symmetry planes x = 0, y = 0, z = 0) stretched 30 % by a
// prescribed end displacement, then pulled by the dead traction that ccx found for it: the exact
// solution is the homogeneous stretch, which both discretisations represent exactly, so they
// differ only by the material law and the solvers' tolerances.
TEST(NeoHookeanCalculix, HomogeneousStretchAgreesToSolverTolerance) {
  if (!ccx_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  const Vector3d size(2.0, 0.5, 0.5);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {kE, kNu, 0.0, 1.0};
  problem.patches.push_back(box(size, 2, {2, 1, 1}));
  for (int d = 0; d < 3; ++d) problem.supports.push_back(symmetry(d));
  analysis::LoadCase load;
  load.id = "stretch";
  problem.load_cases.push_back(load);
  analysis::Problem displaced = problem;
  analysis::Support pull;
  pull.side = {0, 0, 1};
  pull.fixed = {true, false, false};
  pull.value = {0.3 * size.x(), 0, 0};
  displaced.supports.push_back(pull);
  const Answer a = iga(displaced, size, size.x());
  const Answer b = ccx(displaced, size, size.x(), "homogeneous-u");
  std::printf(
      "homogeneous 30%% stretch: reaction isospring %.10g ccx %.10g (%.1e); lateral u "
      "%.10g %.10g (%.1e)\n",
      a.reaction, b.reaction, relative(a.reaction, b.reaction), a.displacement.y(),
      b.displacement.y(), relative(a.displacement.y(), b.displacement.y()));
  EXPECT_LT(relative(a.reaction, b.reaction), 1e-6);
  EXPECT_LT(relative(a.displacement, b.displacement), 1e-6);

  analysis::Problem loaded = problem;
  analysis::Traction t;
  t.side = {0, 0, 1};
  t.value = {b.reaction / (size.y() * size.z()), 0, 0};
  loaded.load_cases[0].tractions.push_back(t);
  const Answer c = iga(loaded, size, size.x());
  const Answer d = ccx(loaded, size, size.x(), "homogeneous-f");
  std::printf("homogeneous dead traction: end u isospring %.10g ccx %.10g (%.1e)\n",
              c.displacement.x(), d.displacement.x(), relative(c.displacement, d.displacement));
  EXPECT_LT(relative(c.displacement, d.displacement), 1e-6);
  EXPECT_NEAR(d.displacement.x(), 0.3 * size.x(), 1e-6 * size.x());
}

}  // namespace isospring::io

namespace isospring::io {
namespace {

// A clamped part pulled or bent: `problem(degree, refinement)` at a given refinement (element
// counts scale with it), compared at `point` and by the reaction on x = length.
struct Convergence {
  Answer iga_coarse, iga_fine, ccx_coarse, ccx_fine;
};

Convergence converge(const std::function<analysis::Problem(int, int)>& problem,
                     const Vector3d& point, double length, const std::string& name, int iga_level,
                     int ccx_level) {
  Convergence c;
  c.iga_coarse = iga(problem(3, iga_level), point, length);
  c.iga_fine = iga(problem(3, 2 * iga_level), point, length);
  c.ccx_coarse = ccx(problem(2, ccx_level), point, length, name + "-coarse");
  c.ccx_fine = ccx(problem(2, 2 * ccx_level), point, length, name + "-fine");
  const std::pair<const char*, const Answer*> rows[] = {{"iga", &c.iga_coarse},
                                                        {"iga fine", &c.iga_fine},
                                                        {"ccx", &c.ccx_coarse},
                                                        {"ccx fine", &c.ccx_fine}};
  for (const auto& [label, a] : rows)
    std::printf("%s %-9s u = (%.7g, %.7g, %.7g), reaction %.7g, %.2f s, %d steps %d iterations\n",
                name.c_str(), label, a->displacement.x(), a->displacement.y(), a->displacement.z(),
                a->reaction, a->seconds, a->steps, a->iterations);
  return c;
}

analysis::Problem clamped_block(int degree, int level) {
  const Vector3d size(2.0, 0.5, 0.5);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {kE, kNu, 0.0, 1.0};
  problem.patches.push_back(box(size, degree, {4 * level, level, level}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  problem.supports.push_back(symmetry(1));
  problem.supports.push_back(symmetry(2));
  analysis::Support pull;
  pull.side = {0, 0, 1};
  pull.fixed = {true, false, false};
  pull.value = {0.3 * size.x(), 0, 0};
  problem.supports.push_back(pull);
  analysis::LoadCase load;
  load.id = "stretch";
  problem.load_cases.push_back(load);
  return problem;
}

// Half (z >= 0) of a length x 0.2 x 0.2 cantilever, `level` elements through the depth.
analysis::Problem cantilever(int degree, int level, double q, double length) {
  const Vector3d size(length, 0.2, 0.1);
  analysis::Problem problem;
  problem.formulation = analysis::Formulation::kSolid;
  problem.material = {kE, kNu, 0.0, 1.0};
  const int along = static_cast<int>(std::lround(5 * length)) * level;
  problem.patches.push_back(box(size, degree, {along, level, level}));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  problem.supports.push_back(symmetry(2));
  analysis::LoadCase load;
  load.id = "bend";
  analysis::Traction t;
  t.side = {0, 0, 1};
  t.value = {0, -q, 0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  return problem;
}

}  // namespace

// A quarter of a 2 x 1 x 1 block clamped at x = 0 and pulled 30 % (u_x = 0.6 on x = 2, the end
// free to contract): the clamp makes the field inhomogeneous. Compared: the reaction on x = 2 and
// the contraction of the free end's corner.
TEST(NeoHookeanCalculix, ClampedBlockStretchedThirtyPercent) {
  if (!ccx_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  const Vector3d corner(2.0, 0.5, 0.5);
  // isospring: degree 3, 8 x 2 x 2 and 16 x 4 x 4 elements; ccx: 16 x 4 x 4 and 32 x 8 x 8.
  const Convergence c = converge(clamped_block, corner, 2.0, "clamped block", 2, 4);
  // Each discretisation converged: refining changes the reaction and the contraction by less
  // than 0.1 % (measured 4e-4 and 3e-4 for both).
  EXPECT_LT(relative(c.iga_coarse.reaction, c.iga_fine.reaction), 1e-3);
  EXPECT_LT(relative(c.ccx_coarse.reaction, c.ccx_fine.reaction), 1e-3);
  EXPECT_LT(relative(c.iga_coarse.displacement.y(), c.iga_fine.displacement.y()), 1e-3);
  EXPECT_LT(relative(c.ccx_coarse.displacement.y(), c.ccx_fine.displacement.y()), 1e-3);
  // The finest of each agree far within 1 % (measured 4e-5 for both).
  const double reaction = relative(c.iga_fine.reaction, c.ccx_fine.reaction);
  const double contraction = relative(c.iga_fine.displacement.y(), c.ccx_fine.displacement.y());
  std::printf("clamped block, 30%% stretch: reaction %.1e, contraction %.1e apart\n", reaction,
              contraction);
  EXPECT_LT(reaction, 1e-3);
  EXPECT_LT(contraction, 1e-3);
  EXPECT_NEAR(c.iga_fine.displacement.x(), 0.6, 1e-12);
}

// Axial engineering strain of the fibre (y, z = 0) at x of the IGA solution: the stretch
// |dx/dX_1| - 1 by central differences of the displacement along x.
double fibre_strain(const analysis::Problem& problem,
                    const analysis::ControlDisplacements& displacements, double x, double y) {
  const Vector3d size = problem.patches[0].control_points().back();
  auto at = [&](double xi) {
    const nurbs::Param u{xi, y / size.y(), 0.0};
    const analysis::FieldPoint f = analysis::evaluate_field(problem, displacements, 0, u);
    return Vector3d(f.point + f.displacement);
  };
  const double h = 1e-4, xi = x / size.x();
  return (at(xi + h) - at(xi - h)).norm() / (2 * h * size.x()) - 1.0;
}

// The cantilever of `length` bent by the dead end traction (0, -q, 0), against ccx; isospring at
// degree 3 and ccx on the same grids, each at `level` and 2 `level` elements through the depth.
// Returns the outer fibres' axial strains at x = length / 10 (isospring's finer solution), away
// from the clamp's corner singularity.
std::pair<double, double> check_cantilever(double length, double q, int level,
                                           const std::string& name) {
  const Vector3d corner(length, 0.0, 0.0);
  auto problem = [&](int degree, int l) { return cantilever(degree, l, q, length); };
  const Convergence c = converge(problem, corner, length, name, level, level);
  // Each discretisation changes by less than the 1 % asked of the comparison from the coarse to
  // the fine mesh, ccx's (full-integration C3D20 bend stiffer on coarse meshes) towards
  // isospring's value.
  EXPECT_LT(relative(c.iga_coarse.displacement, c.iga_fine.displacement), 5e-3);
  EXPECT_LT(relative(c.ccx_coarse.displacement, c.ccx_fine.displacement), 1e-2);
  EXPECT_GT(relative(c.ccx_coarse.displacement, c.iga_fine.displacement),
            relative(c.ccx_fine.displacement, c.iga_fine.displacement));
  const double difference = relative(c.iga_fine.displacement, c.ccx_fine.displacement);
  const analysis::Problem fine = problem(3, 2 * level);
  const double top = fibre_strain(fine, c.iga_fine.control, 0.1 * length, 0.2);
  const double bottom = fibre_strain(fine, c.iga_fine.control, 0.1 * length, 0.0);
  std::printf(
      "%s: end displacement %.1e apart; fibre strains at x = L/10: top %+.3f, bottom "
      "%+.3f\n",
      name.c_str(), difference, top, bottom);
  EXPECT_LT(difference, 1e-2);
  return {top, bottom};
}

// A slender half cantilever 1 x 0.2 x 0.2 under q = E / 200: large rotation, the end drops 40 % of
// the length (measured: 1.3e-3 apart, fibre strains +-12 %).
TEST(NeoHookeanCalculix, CantileverBentByADeadEndLoad) {
  if (!ccx_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  const auto [top, bottom] = check_cantilever(1.0, 5.0, 2, "cantilever");
  EXPECT_GT(top, 0.1);
  EXPECT_LT(bottom, -0.1);
}

// A stubby half cantilever 0.6 x 0.2 x 0.2 under q = E / 50: fibre strains near 30 %.
TEST(NeoHookeanCalculix, StubbyCantileverBentToLargeStrain) {
  if (!ccx_available())
    GTEST_SKIP() << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH";
  const auto [top, bottom] = check_cantilever(0.6, 20.0, 3, "stubby cantilever");
  EXPECT_GT(top, 0.2);
  EXPECT_LT(bottom, -0.2);
}

}  // namespace isospring::io
