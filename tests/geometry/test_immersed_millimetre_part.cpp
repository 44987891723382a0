// A part a millimetre across (Analysis Situs' wavy cube, tests/data/parts): the boundary quadrature
// of its faces against their closed forms. Its sides are trapezoids of 1 x (1, 1.2) mm and
// 1 x (1.2, 0.8) mm under a bicubic Bezier top, whose volume is the mean of the top's control
// heights (each Bernstein polynomial integrates to 1 / 4) times the unit square: 1.05 mm^3. The
// hatcher's confusion distance used to be an absolute 1e-8 in (u, v), metres on a plane, 1e-5 of
// this part's side: two sides came out 1.05e-5 too large.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

TEST(ImmersedMillimetrePart, FacesAndVolumeOfTheWavyCubeAreExact) {
  const fs::path file =
      fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/analysissitus_wavy_cube.stp";
  if (!fs::exists(file)) GTEST_SKIP() << "tests/data/parts (third-party parts) is absent";
  const CadSolid solid = read_cad_solid(file);
  ImmersionOptions options;
  options.threads = 1;
  const ImmersedDomain domain = immerse_solid(solid, options);
  std::vector<double> area(6, 0.0);
  for (const BoundaryPoint& b : domain.boundary) area.at(static_cast<size_t>(b.face)) += b.weight;
  // Faces as the file orders them: the bottom, the side y = 0, the top, the sides x = 1 mm,
  // x = 0 and y = 1 mm (mm^2; the top's area is OpenCascade's, it has no closed form).
  const double top = measure_solid(solid).area * 1e6 - (1.0 + 1.1 + 1.0 + 1.1 + 1.0);
  const std::array<double, 6> exact = {1.0, 1.1, top, 1.0, 1.1, 1.0};
  for (size_t f = 0; f < 6; ++f)
    EXPECT_NEAR(area[f] * 1e6, exact[f], 1e-9 * exact[f]) << "face " << f;
  EXPECT_NEAR(top, 1.0388117349, 1e-9);
  // The cells' rule meets the immersion's tolerance (1e-7 by default); measured 1.1e-9.
  EXPECT_NEAR(measure_quadrature(domain).volume * 1e9, 1.05, 1e-8);
}

}  // namespace
}  // namespace isospring::geometry
