// Every CAD part the project ships or reads (examples/cad, examples/immersed, tests/data/parts and
// the third-party parts of ../shared/cad): the immersed quadrature's volume, centroid (cells) and
// area (boundary points) against OpenCascade's BRepGProp, to 1e-6 (for a shell that does not
// close, 1e-5 or the bound its gap allows, below). The folders are listed, not the files, so a part
// added to one of them is checked too; a file with several solids is checked body by body;
// ../shared is skipped with a message when it is absent.
//
// The default grid (10 cells along the longest side); coarse grids and moved parts are
// test_immersed_coarse_grids.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "../common/cad_parts.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace fs = std::filesystem;

namespace isospring::geometry {
namespace {

using test::cad_files;
using test::solids_of;

struct Errors {
  double volume = 0, area = 0, centroid = 0;
  double tolerance = 1e-6;  // volume and centroid: 1e-6, or (a shell that is open) below
};

// The quadrature against OpenCascade. A shell that does not close (its faces' trimmed pieces leave
// gaps or overlap within the edges' tolerances) has int n dA = g != 0, and then the volume the
// divergence theorem gives, V(c) = 1/3 int (x - c).n dA, depends on the point c by -g.c / 3:
// OpenCascade's volume is one such value, the cells' volume (lines crossing the faces) another,
// and neither is the part's volume better than about |g| d / (3 V) (d the box's diagonal). Four
// shipped parts have such shells (|g| / area: gmsh's t20 nut 8.1e-6, the CAx-IF AP209 bracket
// 2.8e-6, gmsh's housing 4.9e-7, OCCT's screw 4.5e-7; the others 1.4e-8 or less): they are
// checked to 1e-5 or that bound where it is larger (the bracket: 4.4e-5; its volume is 1.2e-5
// and its centroid 2.9e-5 off), the rest to 1e-6.
// The CAx-IF GD&T block, whose shell closes, was 1.40e-6 off: OpenCascade's reader had fitted the
// trimming circles of its top and bottom faces loosely (1.9e-5 m off between the points it
// checks), and both OpenCascade's volume (3.2e-7 below the closed form) and the cells' (lines
// trimmed by those pcurves) followed the fit. The import rebuilds such pcurves
// (geometry/src/cad_pcurves.hpp); the block is now 2.8e-9 off, and test_cad_pcurves.cpp checks
// OpenCascade's measures of it against the closed form.
Errors check(const CadSolid& solid, const std::string& label) {
  ImmersionOptions options;
  options.threads = 1;
  const std::clock_t start = std::clock();
  ImmersionStats stats;
  const ImmersedDomain domain = immerse_solid(solid, options, &stats);
  const double cpu = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  const SolidMeasures q = measure_quadrature(domain), m = measure_solid(solid);
  Eigen::Vector3d gap = Eigen::Vector3d::Zero();
  for (const BoundaryPoint& b : domain.boundary) gap += b.weight * b.normal;
  Errors e;
  e.volume = std::abs(q.volume / m.volume - 1.0);
  e.area = std::abs(q.area / m.area - 1.0);
  e.centroid = (q.centroid - m.centroid).norm() / std::cbrt(m.volume);
  const double bound = gap.norm() * domain.extent.norm() / (3.0 * m.volume);
  e.tolerance = gap.norm() / m.area < 1e-7 ? 1e-6 : std::max(1e-5, bound);
  std::printf(
      "[parts] %s: volume %.2e, area %.2e, centroid %.2e; |int n dA| / area %.1e (bound "
      "|g| d / 3V %.1e), tolerance %.0e (%d cut cells, %ld boxes, %.1f s CPU)\n",
      label.c_str(), e.volume, e.area, e.centroid, gap.norm() / m.area, bound, e.tolerance,
      stats.cut_cells, stats.cut_boxes, cpu);
  return e;
}

void check_folder(const fs::path& dir, int& checked) {
  for (const fs::path& file : cad_files(dir)) {
    const std::vector<CadSolid> solids = solids_of(file);
    for (size_t body = 0; body < solids.size(); ++body) {
      const std::string label = fs::relative(file, dir.parent_path()).string() +
                                (solids.size() > 1 ? ", solid " + std::to_string(body) : "");
      const Errors e = check(solids[body], label);
      EXPECT_LT(e.volume, e.tolerance) << label;
      EXPECT_LT(e.area, 1e-6) << label;
      EXPECT_LT(e.centroid, e.tolerance) << label;
      ++checked;
    }
  }
}

TEST(ImmersedCad, EveryShippedPartMatchesOpenCascade) {
  const fs::path source(ISOSPRING_SOURCE_DIR);
  int checked = 0;
  for (const char* dir : {"examples/cad", "examples/immersed", "tests/data/parts"})
    check_folder(source / dir, checked);
  EXPECT_GE(checked, 16);  // 5 + 3 + 8 solids when this test was written
}

TEST(ImmersedCad, EverySharedPartMatchesOpenCascade) {
  const fs::path dir = fs::path(ISOSPRING_SHARED_DIR) / "cad";
  if (!fs::exists(dir))
    GTEST_SKIP() << "the third-party parts of ../shared/cad are not present (" << dir << ")";
  int checked = 0;
  check_folder(dir, checked);
  EXPECT_GE(checked, 6);  // cube and cylinder, L-bracket, plate, CATIA cylinder, torus
}

}  // namespace
}  // namespace isospring::geometry
