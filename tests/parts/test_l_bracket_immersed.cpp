// The CAx-IF L-bracket (../shared/cad/l_bracket_caxif.stp) analysed immersed: its exact B-rep in
// a B-spline grid (geometry::immerse_solid, analysis::solve_immersed), the long leg's end
// (y = 60 mm) clamped by Nitsche's method and a traction of 1 MPa on the short leg's end
// (x = 50 mm) along -y and +z, both faces chosen by plane selectors: the problem of
// examples/l_bracket, whose body-fitted 57-patch model was compared with CalculiX there.
//
// Compared with CalculiX (examples/l_bracket/calculix_reference.json, written by
// calculix_reference.py: gmsh's quadratic tetrahedra on the same STEP file, nothing of isospring):
// the strain energies of both load cases and the displacements of the loaded end's four corners
// of one graded grid against CalculiX's finest mesh (h = 2 mm). The Richardson limit of three
// uniform grids (LBracketImmersed.DISABLED_ExtrapolatedLimitMatchesCalculixWithinHalfAPercent)
// and the refinement table of docs/immersed.md ("The CAx-IF L-bracket", from
// LBracketImmersed.DISABLED_RefinementTable) run with --gtest_also_run_disabled_tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/immersed_case.hpp"

namespace isospring {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kPart = fs::path(ISOSPRING_SHARED_DIR) / "cad/l_bracket_caxif.stp";
const fs::path kExample = fs::path(ISOSPRING_SOURCE_DIR) / "examples/l_bracket";
const std::array<std::string, 2> kLoadCases{"shear_y", "shear_z"};
const std::array<Eigen::Vector3d, 2> kTractions{Eigen::Vector3d(0, -1e6, 0),
                                                Eigen::Vector3d(0, 0, 1e6)};
const std::array<Eigen::Vector3d, 4> kCorners{
    Eigen::Vector3d(0.05, 0, 0), Eigen::Vector3d(0.05, 0.01, 0), Eigen::Vector3d(0.05, 0, 0.1),
    Eigen::Vector3d(0.05, 0.01, 0.1)};

struct Grid {
  Eigen::Vector3i cells;  // over the part's bounding box [0, 50] x [0, 60] x [0, 100] mm
  int degree = 2;
  std::string label;
  // Graded: cells of `smallest` (m) at the re-entrant edge's planes x = 10 and y = 10 mm and at
  // the clamped face's outline (x = 0, 10, y = 60, z = 0, 100 mm), growing by `ratio`; the part's
  // planar faces' coordinates are kept as cell boundaries, so that every planar face lies on a grid
  // plane.
  double smallest = 0;
  double ratio = 1.5;
  std::string towards =
      "rc";  // r: the re-entrant edge, c: the clamp's outline, l: the loaded face's
};

struct Outcome {
  int dofs = 0, inside_cells = 0, cut_cells = 0, sliver_cells = 0;
  Eigen::Vector3i cells = Eigen::Vector3i::Zero();          // of the grid, after grading
  std::array<double, 2> energy{};                           // per load case (J)
  std::array<std::array<Eigen::Vector3d, 4>, 2> corners{};  // per load case, m
  double wall_seconds = 0, cpu_seconds = 0;
};

int face_on_plane(const std::vector<geometry::SolidFace>& faces, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal) {
  geometry::FaceSelector s;
  s.point = point;
  s.direction = normal;
  const std::vector<int> found = geometry::select_faces(faces, s);
  EXPECT_EQ(found.size(), 1u) << geometry::describe(s);
  return found.empty() ? -1 : found.front();
}

// The immersion options of `grid` on the part.
geometry::ImmersionOptions immersion_options(const Grid& grid, const geometry::CadSolid& solid,
                                             int clamped, int loaded) {
  geometry::ImmersionOptions immersion;
  immersion.degree = grid.degree;
  immersion.cells = grid.cells;
  if (grid.smallest > 0) {
    immersion.breaks = geometry::planar_face_coordinates(solid);
    const auto add = [&](const std::vector<geometry::GradingPlane>& planes) {
      immersion.grading.insert(immersion.grading.end(), planes.begin(), planes.end());
    };
    if (grid.towards.find('r') != std::string::npos)
      add({{0, 0.01, grid.smallest, grid.ratio}, {1, 0.01, grid.smallest, grid.ratio}});
    if (grid.towards.find('c') != std::string::npos)
      add(geometry::grading_towards_face(solid, clamped, grid.smallest, grid.ratio));
    if (grid.towards.find('l') != std::string::npos)
      add(geometry::grading_towards_face(solid, loaded, grid.smallest, grid.ratio));
  }
  return immersion;
}

Outcome analyse(const Grid& grid) {
  const auto wall = std::chrono::steady_clock::now();
  const std::clock_t cpu = std::clock();
  const geometry::CadSolid solid = geometry::read_cad_solid(kPart);
  const std::vector<geometry::SolidFace> faces = geometry::solid_faces(solid);
  const int clamped = face_on_plane(faces, {0, 0.06, 0}, {0, 1, 0});
  const int loaded = face_on_plane(faces, {0.05, 0, 0}, {1, 0, 0});
  const geometry::ImmersionOptions immersion = immersion_options(grid, solid, clamped, loaded);
  geometry::ImmersionStats stats;
  const geometry::ImmersedDomain domain = geometry::immerse_solid(solid, immersion, &stats);

  analysis::ImmersedOptions options;
  options.material.youngs_modulus = 210e9;
  options.material.poisson_ratio = 0.3;
  analysis::ImmersedSupport clamp;
  clamp.face = clamped;
  clamp.fixed = {true, true, true};
  options.supports = {clamp};
  Outcome out;
  out.inside_cells = stats.inside_cells;
  out.sliver_cells = stats.sliver_cells;
  for (int d = 0; d < 3; ++d) out.cells[d] = domain.background.knots(d).num_elements();
  out.cut_cells = stats.cut_cells;
  for (size_t c = 0; c < kLoadCases.size(); ++c) {
    analysis::ImmersedTraction t;
    t.face = loaded;
    t.value = kTractions[c];
    options.tractions = {t};
    const analysis::ImmersedResult r = analysis::solve_immersed(domain, options);
    out.dofs = r.dofs;
    out.energy[c] = r.strain_energy;
    for (size_t k = 0; k < kCorners.size(); ++k)
      out.corners[c][k] = analysis::evaluate_immersed(domain, r, kCorners[k]).displacement;
  }
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  out.cpu_seconds = static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
  return out;
}

// CalculiX's run with mesh size h (mm).
const json& calculix_run(const json& reference, double h) {
  for (const json& r : reference.at("runs"))
    if (r.at("h_mm").get<double>() == h) return r;
  throw std::runtime_error("calculix_reference.json has no run at h = " + std::to_string(h));
}

json read_reference() {
  std::ifstream in(kExample / "calculix_reference.json");
  return json::parse(in);
}

// Relative differences against one CalculiX run: the strain energies and the corner components
// above 10 % of the load case's largest (20 of them: shear_y moves the corners in x and y,
// shear_z in all three directions).
struct Differences {
  std::array<double, 2> energy{};
  std::vector<double> corners;
  double largest_corner = 0;
};

Differences differences(const Outcome& o, const json& run) {
  Differences d;
  for (size_t c = 0; c < kLoadCases.size(); ++c) {
    const json& lc = run.at("load_cases").at(kLoadCases[c]);
    // NaN (a failed comparison) when the reference has no energy.
    d.energy[c] = o.energy[c] / lc.value("strain_energy_J", std::nan("")) - 1.0;
    double largest = 0;
    for (const json& corner : lc.at("corners"))
      for (const json& u : corner.at("u_m")) largest = std::max(largest, std::abs(u.get<double>()));
    for (size_t k = 0; k < kCorners.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        const double theirs = lc.at("corners")[k].at("u_m")[static_cast<size_t>(i)].get<double>();
        if (std::abs(theirs) < 0.1 * largest) continue;
        d.corners.push_back(o.corners[c][k][i] / theirs - 1.0);
        d.largest_corner = std::max(d.largest_corner, std::abs(d.corners.back()));
      }
  }
  return d;
}

void print(const Grid& g, const Outcome& o, const json& reference) {
  const Differences d2 = differences(o, calculix_run(reference, 2.0));
  std::printf(
      "[l-bracket] %s p=%d cells %dx%dx%d (%d inside, %d cut, %d slivers left out): %d DOFs; "
      "energy %.6e / %.6e J "
      "(vs CalculiX h=2: %+.3f %% / %+.3f %%); u_y(50,0,0) shear_y %.5e, u_z(50,0,0) shear_z "
      "%.5e m; corners max |diff| %.3f %%; %.1f s wall, %.1f s CPU\n",
      g.label.c_str(), g.degree, o.cells.x(), o.cells.y(), o.cells.z(), o.inside_cells, o.cut_cells,
      o.sliver_cells, o.dofs, o.energy[0], o.energy[1], 100 * d2.energy[0], 100 * d2.energy[1],
      o.corners[0][0].y(), o.corners[1][0].z(), 100 * d2.largest_corner, o.wall_seconds,
      o.cpu_seconds);
  for (size_t c = 0; c < kLoadCases.size(); ++c) {
    std::printf("[l-bracket]   %s corners (m):", kLoadCases[c].c_str());
    for (const Eigen::Vector3d& u : o.corners[c])
      std::printf(" %.6e %.6e %.6e", u.x(), u.y(), u.z());
    std::printf("\n");
  }
}

// Richardson extrapolation of values on grids halved twice: the observed rate q from
// (f1 - f2) / (f2 - f3) = 2^q and the limit f3 + (f3 - f2) / (2^q - 1). NaN when the changes do
// not shrink monotonically (no rate can be fitted).
struct Limit {
  double value = std::nan(""), rate = std::nan("");
};
Limit richardson(double f1, double f2, double f3) {
  const double ratio = (f1 - f2) / (f2 - f3);
  if (!(ratio > 1.0)) return {};
  return {f3 + (f3 - f2) / (ratio - 1.0), std::log2(ratio)};
}

// The body-fitted 57-patch model of examples/l_bracket/case.json (degree 3, 4 elements per patch
// direction, 59,409 DOFs, strong clamp; `isospring analyze`, docs/immersed.md): its energies (J).
constexpr std::array<double, 2> kBodyFittedEnergy{3.81357e-2, 1.05758e-2};

// One graded grid (Grid::smallest): degree 2 on 5 mm base cells, 0.625 mm cells at the re-entrant
// edge's planes and the clamped face's outline, where the stresses are singular; the planar faces
// on grid planes. 37,026 DOFs, measured 137-148 s of CPU on one thread (a loaded machine; 2.3 GB).
Grid graded_grid(double smallest) {
  Grid g{{10, 12, 20}, 2, "graded " + std::to_string(smallest * 1e3).substr(0, 5) + " mm"};
  g.smallest = smallest;
  return g;
}

// The one grid within 0.5 % of CalculiX h = 2 mm in both energies (measured -0.26 % and -0.23 %)
// and in the eight corner displacements along the load (-0.17 % .. -0.19 %), and within 0.5 % of
// the body-fitted energies (-0.41 %, -0.38 %). The other twelve corner components above 10 % of
// the largest within 1 % (measured within 0.55 %; u_y under shear_z is the largest, -0.45 % ..
// -0.55 %, and moved away from CalculiX from the 1.25 mm grading to this one: not resolved).
TEST(LBracketImmersed, OneGradedGridMatchesCalculixWithinHalfAPercent) {
  if (!fs::exists(kPart))
    GTEST_SKIP() << kPart << " (third-party CAD part in ../shared) is not present";
  const json reference = read_reference();
  const json& finest = calculix_run(reference, 2.0);
  const Grid grid = graded_grid(0.625e-3);
  const Outcome o = analyse(grid);
  print(grid, o, reference);
  int compared = 0;
  for (size_t c = 0; c < kLoadCases.size(); ++c) {
    const json& lc = finest.at("load_cases").at(kLoadCases[c]);
    const double ccx_energy = lc.value("strain_energy_J", std::nan(""));
    EXPECT_LT(std::abs(o.energy[c] / ccx_energy - 1.0), 5e-3) << kLoadCases[c];
    EXPECT_LT(std::abs(o.energy[c] / kBodyFittedEnergy[c] - 1.0), 5e-3) << kLoadCases[c];
    double largest = 0;
    for (const json& corner : lc.at("corners"))
      for (const json& u : corner.at("u_m")) largest = std::max(largest, std::abs(u.get<double>()));
    const int along = c == 0 ? 1 : 2;  // the load's direction
    for (size_t k = 0; k < kCorners.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        const double theirs = lc.at("corners")[k].at("u_m")[static_cast<size_t>(i)].get<double>();
        if (std::abs(theirs) < 0.1 * largest) continue;
        ++compared;
        EXPECT_LT(std::abs(o.corners[c][k][i] / theirs - 1.0), i == along ? 5e-3 : 1e-2)
            << kLoadCases[c] << " corner " << k << " u"
            << "xyz"[i] << ": " << o.corners[c][k][i] << ", CalculiX " << theirs;
      }
  }
  EXPECT_EQ(compared, 20);  // shear_y: ux and uy at 4 corners; shear_z: all 3 at 4 corners
}

// examples/l_bracket/immersed_graded.json is the grid of the test above: the same degree, cells,
// breaks and grading planes (in another order, which the knots do not depend on).
TEST(LBracketImmersed, GradedCaseFileIsTheTestedGrid) {
  if (!fs::exists(kPart))
    GTEST_SKIP() << kPart << " (third-party CAD part in ../shared) is not present";
  const io::ImmersedCase c = io::read_immersed_case(kExample / "immersed_graded.json");
  const std::vector<geometry::SolidFace> faces = geometry::solid_faces(*c.cad);
  const geometry::ImmersionOptions tested = immersion_options(
      graded_grid(0.625e-3), *c.cad, face_on_plane(faces, {0, 0.06, 0}, {0, 1, 0}),
      face_on_plane(faces, {0.05, 0, 0}, {1, 0, 0}));
  EXPECT_EQ(c.immersion.degree, tested.degree);
  EXPECT_EQ(c.immersion.cells, tested.cells);
  EXPECT_EQ(c.immersion.breaks, tested.breaks);
  const auto key = [](const geometry::GradingPlane& p) {
    return std::make_tuple(p.axis, p.at, p.smallest, p.ratio);
  };
  std::vector<std::tuple<int, double, double, double>> theirs, ours;
  for (const auto& p : c.immersion.grading) theirs.push_back(key(p));
  for (const auto& p : tested.grading) ours.push_back(key(p));
  std::sort(theirs.begin(), theirs.end());
  std::sort(ours.begin(), ours.end());
  EXPECT_EQ(theirs, ours);
  ASSERT_EQ(c.load_cases.size(), 2u);
}

// Degree 2 on cells of 10, 5 and 2.5 mm (one, two and four across each leg; every face of the part
// but the holes lies on grid planes): 45 s of CPU together. The re-entrant edge of the L and the
// clamp's edges are singular and the splines are smooth across them, so the grids converge slowly
// (energy rates 1.43 and 1.48, measured): the limit is extrapolated and compared.
std::vector<Grid> test_grids() {
  return {{{5, 6, 10}, 2, "uniform 10 mm"},
          {{10, 12, 20}, 2, "uniform 5 mm"},
          {{20, 24, 40}, 2, "uniform 2.5 mm"}};
}

TEST(LBracketImmersed, DISABLED_ExtrapolatedLimitMatchesCalculixWithinHalfAPercent) {
  if (!fs::exists(kPart))
    GTEST_SKIP() << kPart << " (third-party CAD part in ../shared) is not present";
  const json reference = read_reference();
  const json& finest = calculix_run(reference, 2.0);
  std::vector<Outcome> runs;
  for (const Grid& g : test_grids()) {
    runs.push_back(analyse(g));
    print(g, runs.back(), reference);
  }
  // Each load case's energy and its corners' displacements along the load, extrapolated, within
  // 0.5 % of CalculiX (measured: energies +0.09 % and +0.42 %, the corner (50, 0, 0) +0.04 % and
  // +0.45 %); the other corner components above 10 % of the largest within 1.5 % (u_x of the
  // corners at y = 10 mm under shear_y may change sign between the grids' changes: then the
  // finest grid's value is compared).
  int compared = 0;
  for (size_t c = 0; c < kLoadCases.size(); ++c) {
    const json& lc = finest.at("load_cases").at(kLoadCases[c]);
    const Limit e = richardson(runs[0].energy[c], runs[1].energy[c], runs[2].energy[c]);
    const double ccx_energy = lc.value("strain_energy_J", std::nan(""));
    std::printf("[l-bracket] %s: energy rate %.2f, limit %.6e J, %+.3f %% from CalculiX h = 2 mm\n",
                kLoadCases[c].c_str(), e.rate, e.value, 100 * (e.value / ccx_energy - 1.0));
    EXPECT_LT(std::abs(e.value / ccx_energy - 1.0), 5e-3) << kLoadCases[c];
    double largest = 0;
    for (const json& corner : lc.at("corners"))
      for (const json& u : corner.at("u_m")) largest = std::max(largest, std::abs(u.get<double>()));
    const int along = c == 0 ? 1 : 2;  // the load's direction
    for (size_t k = 0; k < kCorners.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        const double theirs = lc.at("corners")[k].at("u_m")[static_cast<size_t>(i)].get<double>();
        if (std::abs(theirs) < 0.1 * largest) continue;
        const Limit u = richardson(runs[0].corners[c][k][i], runs[1].corners[c][k][i],
                                   runs[2].corners[c][k][i]);
        const double ours = std::isnan(u.value) ? runs[2].corners[c][k][i] : u.value;
        ++compared;
        EXPECT_TRUE(i != along || !std::isnan(u.value)) << "no rate along the load";
        EXPECT_LT(std::abs(ours / theirs - 1.0), i == along ? 5e-3 : 1.5e-2)
            << kLoadCases[c] << " corner " << k << " u"
            << "xyz"[i] << ": " << ours << " (extrapolated: " << !std::isnan(u.value)
            << "), CalculiX " << theirs;
      }
  }
  EXPECT_EQ(compared, 20);  // shear_y: ux and uy at 4 corners; shear_z: all 3 at 4 corners
}

TEST(LBracketImmersed, DISABLED_RefinementTable) {
  if (!fs::exists(kPart))
    GTEST_SKIP() << kPart << " (third-party CAD part in ../shared) is not present";
  const json reference = read_reference();
  std::vector<Grid> grids = test_grids();
  grids.push_back({{5, 6, 10}, 3, "uniform 10 mm"});
  grids.push_back({{10, 12, 20}, 3, "uniform 5 mm"});
  grids.push_back(graded_grid(2.5e-3));
  grids.push_back(graded_grid(1.25e-3));
  grids.push_back(graded_grid(0.625e-3));
  Grid cubic = graded_grid(2.5e-3);
  cubic.degree = 3;
  grids.push_back(cubic);
  for (const Grid& g : grids) print(g, analyse(g), reference);
}

}  // namespace
}  // namespace isospring
