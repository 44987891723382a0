// The CAx-IF L-bracket (../shared/cad/l_bracket_caxif.stp) analysed immersed: its exact B-rep in
// a B-spline grid (geometry::immerse_solid, analysis::solve_immersed), the long leg's end
// (y = 60 mm) clamped by Nitsche's method and a traction of 1 MPa on the short leg's end
// (x = 50 mm) along -y and +z, both faces chosen by plane selectors: the problem of
// examples/l_bracket, whose body-fitted 57-patch model was compared with CalculiX there.
//
// Compared with CalculiX (examples/l_bracket/calculix_reference.json, written by
// calculix_reference.py: gmsh's quadratic tetrahedra on the same STEP file, nothing of isospring):
// the strain energies of both load cases and the displacements of the loaded end's four corners,
// Richardson-extrapolated from three uniform grids, against CalculiX's finest mesh (h = 2 mm).
// The refinement table of docs/immersed.md ("The CAx-IF L-bracket") comes from
// LBracketImmersed.DISABLED_RefinementTable (run it with --gtest_also_run_disabled_tests).
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/geometry/immersed_cad.hpp"

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
  std::vector<geometry::GradingPlane> grading;
  std::string label;
};

struct Outcome {
  int dofs = 0, inside_cells = 0, cut_cells = 0;
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

Outcome analyse(const Grid& grid) {
  const auto wall = std::chrono::steady_clock::now();
  const std::clock_t cpu = std::clock();
  const geometry::CadSolid solid = geometry::read_cad_solid(kPart);
  const std::vector<geometry::SolidFace> faces = geometry::solid_faces(solid);
  geometry::ImmersionOptions immersion;
  immersion.degree = grid.degree;
  immersion.cells = grid.cells;
  immersion.grading = grid.grading;
  geometry::ImmersionStats stats;
  const geometry::ImmersedDomain domain = geometry::immerse_solid(solid, immersion, &stats);

  analysis::ImmersedOptions options;
  options.material.youngs_modulus = 210e9;
  options.material.poisson_ratio = 0.3;
  analysis::ImmersedSupport clamp;
  clamp.face = face_on_plane(faces, {0, 0.06, 0}, {0, 1, 0});
  clamp.fixed = {true, true, true};
  options.supports = {clamp};
  const int loaded = face_on_plane(faces, {0.05, 0, 0}, {1, 0, 0});
  Outcome out;
  out.inside_cells = stats.inside_cells;
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
      "[l-bracket] %s p=%d cells %dx%dx%d (%d inside, %d cut): %d DOFs; energy %.6e / %.6e J "
      "(vs CalculiX h=2: %+.3f %% / %+.3f %%); u_y(50,0,0) shear_y %.5e, u_z(50,0,0) shear_z "
      "%.5e m; corners max |diff| %.3f %%; %.1f s wall, %.1f s CPU\n",
      g.label.c_str(), g.degree, g.cells.x(), g.cells.y(), g.cells.z(), o.inside_cells, o.cut_cells,
      o.dofs, o.energy[0], o.energy[1], 100 * d2.energy[0], 100 * d2.energy[1], o.corners[0][0].y(),
      o.corners[1][0].z(), 100 * d2.largest_corner, o.wall_seconds, o.cpu_seconds);
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

// Degree 2 on cells of 10, 5 and 2.5 mm (one, two and four across each leg; every face of the part
// but the holes lies on grid planes): about 50 s of CPU together. The re-entrant edge of the L and
// the clamp's edges are singular and the splines are smooth across them, so the grids converge
// slowly (energy rate 1.7, measured): the limit is extrapolated and compared.
std::vector<Grid> test_grids() {
  return {{{5, 6, 10}, 2, {}, "uniform 10 mm"},
          {{10, 12, 20}, 2, {}, "uniform 5 mm"},
          {{20, 24, 40}, 2, {}, "uniform 2.5 mm"}};
}

TEST(LBracketImmersed, ExtrapolatedLimitMatchesCalculixWithinHalfAPercent) {
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
  // 0.5 % of CalculiX (measured: 0.27 % at most); the other corner components above 10 % of the
  // largest within 1.5 % (measured: u_y under shear_z 1.18 % above CalculiX, where the finest
  // grid is already 0.85 % above it; u_x of the corners at y = 10 mm under shear_y changes sign
  // between the grids' changes, so the finest grid's value is compared: 0.50 %).
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
  grids.push_back({{5, 6, 10}, 3, {}, "uniform 10 mm"});
  grids.push_back({{10, 12, 20}, 3, {}, "uniform 5 mm"});
  for (const Grid& g : grids) print(g, analyse(g), reference);
}

}  // namespace
}  // namespace isospring
