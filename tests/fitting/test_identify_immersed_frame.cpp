// Markers on an immersed domain whose grid is turned (ImmersionOptions::frame): the
// identification's marker rows evaluate the background basis at world points through the frame.
// CadQuery's cylinder (examples/immersed/cube_cylinder.step, clamped on face 0, a traction on
// face 1) turned by a generic rotation Q (Euler angles 20, 35 and 10 degrees) and immersed in the
// frame Q is the unturned problem seen from another frame: the simulated marker displacements at
// the turned markers are the unturned ones turned by Q, to round-off (1e-9 of the largest), and a
// marker off the turned grid is listed as outside.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "isospring/fitting/identify_immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::fitting {
namespace {

TEST(IdentifyImmersedFrame, TurnedGridsMarkersAreTheUnturnedOnesTurned) {
  const double degree = M_PI / 180.0;
  const Eigen::Matrix3d q = (Eigen::AngleAxisd(20 * degree, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(35 * degree, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(10 * degree, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const geometry::CadSolid cylinder = geometry::read_cad_solid(
      std::string(ISOSPRING_SOURCE_DIR) + "/examples/immersed/cube_cylinder.step", 0);
  geometry::ImmersionOptions o;
  o.cells = Eigen::Vector3i(4, 4, 4);
  // A margin that no face lies on a grid plane: without it the end disks lie on the box's
  // planes, the turned B-rep 1e-18 m off them, and three cells next to the clamp that are inside
  // unturned came out cut (with the same volume) turned; their Nitsche penalties then differ and
  // the energy by 1e-4 (a different discretisation, not a wrong one). docs/immersed.md, "User
  // frame".
  o.margin = 0.0013;
  const geometry::ImmersedDomain plain = geometry::immerse_solid(cylinder, o);
  o.frame = q;
  const geometry::ImmersedDomain turned =
      geometry::immerse_solid(geometry::transform_solid(cylinder, q), o);

  const auto cases = [](const Eigen::Matrix3d& r) {
    ImmersedCalibrationCase lc;
    lc.id = "shear";
    lc.options.material.youngs_modulus = 1e6;
    lc.options.material.poisson_ratio = 0.3;
    lc.options.material.density = 1100.0;
    lc.options.supports = {{0, {true, true, true}, Eigen::Vector3d::Zero(), nullptr, false}};
    lc.options.tractions = {{1, r * Eigen::Vector3d(200, 0, 500), nullptr}};
    return std::vector<ImmersedCalibrationCase>{lc};
  };
  std::vector<Marker> markers, turned_markers;
  int k = 0;
  for (const auto& b : plain.boundary) {
    if (b.face == 0 || k++ % 7 != 0) continue;
    Marker m;
    m.load_case = "shear";
    m.position = b.point;
    m.row = static_cast<int>(markers.size()) + 2;
    markers.push_back(m);
    m.position = q * b.point;
    turned_markers.push_back(m);
  }
  ASSERT_GT(markers.size(), 10u);
  EXPECT_TRUE(immersed_markers_outside(turned, turned_markers).empty());
  const std::vector<Eigen::Vector3d> u =
      simulate_immersed_markers(plain, cases(Eigen::Matrix3d::Identity()), markers, {});
  const std::vector<Eigen::Vector3d> v =
      simulate_immersed_markers(turned, cases(q), turned_markers, {});
  ASSERT_EQ(u.size(), v.size());
  double largest = 0, worst = 0;
  for (size_t i = 0; i < u.size(); ++i) {
    largest = std::max(largest, u[i].norm());
    worst = std::max(worst, (v[i] - q * u[i]).norm());
  }
  EXPECT_LT(worst, 1e-9 * largest);
  // A marker beside the part, outside the turned grid's box though inside the unturned one's.
  Marker off = turned_markers.front();
  off.position = q * (plain.origin + 0.999 * plain.extent.cwiseProduct(Eigen::Vector3d(1, 1, 1)));
  off.position += q * Eigen::Vector3d(0.01, 0, 0);
  EXPECT_EQ(immersed_markers_outside(turned, {off}).size(), 1u);
}

}  // namespace
}  // namespace isospring::fitting
