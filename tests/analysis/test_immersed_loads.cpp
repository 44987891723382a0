// The loads-only assembly (assemble_immersed_loads) against the whole one (assemble_immersed's
// right-hand side): on a 3D box with a cylindrical hole, cut by the grid on every side, every kind
// of load (gravity and body force over the cut cells, a traction and a pressure on cut faces, a
// traction on the free components of a supported face, a prescribed support value through the
// Nitsche penalty) gives the same vector to the last bit, since it is the same sums in the same
// order; and what would make it another vector (other supports, another domain) is refused.
#include <gtest/gtest.h>

#include <string>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_implicit.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {
namespace {

// Faces (immersed_implicit.hpp): 0/1 x = min/max, 2/3 y, 4/5 z, 6 the hole.
geometry::ImmersedDomain holed_block(double offset) {
  geometry::ImplicitShape shape;
  shape.dimension = 3;
  shape.box_max = {2.0, 1.0, 0.5};
  shape.circles.push_back({Eigen::Vector2d(1.0, 0.5), 0.25, false});
  geometry::ImplicitGrid grid;
  grid.degree = 2;
  grid.elements = {6, 4, 3};
  grid.grid_min = Eigen::Vector3d(-0.3, -0.2, -0.2) + Eigen::Vector3d::Constant(offset);
  grid.grid_max = grid.grid_min + Eigen::Vector3d(2.6, 1.5, 0.9);
  return geometry::immerse_implicit(shape, grid);
}

ImmersedOptions clamped() {
  ImmersedOptions o;
  o.material.youngs_modulus = 2e5;
  o.material.poisson_ratio = 0.3;
  o.material.density = 7.8;
  ImmersedSupport clamp;
  clamp.face = 0;
  clamp.fixed = {true, true, true};
  ImmersedSupport sym;
  sym.face = 4;
  sym.symmetry = true;
  ImmersedSupport slide;  // holds y only, so a traction on it acts in x and z
  slide.face = 2;
  slide.fixed = {false, true, false};
  o.supports = {clamp, sym, slide};
  return o;
}

std::vector<ImmersedOptions> load_cases() {
  std::vector<ImmersedOptions> cases(6, clamped());
  cases[0].gravity = {0.0, -9.81, 0.0};
  cases[1].body_force = {3.0, -1.0, 2.0};
  cases[2].tractions = {{1, Eigen::Vector3d(10.0, 5.0, -2.0), nullptr}};
  cases[3].pressures = {{6, 40.0}};
  cases[4].tractions = {{2, Eigen::Vector3d(7.0, 100.0, 3.0), nullptr}};  // y is held there
  cases[5].supports[2].value_function = [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(0.0, 1e-3 * x.x() * x.x(), 0.0);
  };
  cases[5].supports[0].value = {1e-4, -2e-4, 3e-4};
  cases[5].gravity = {0.0, 0.0, 9.81};
  return cases;
}

TEST(ImmersedLoads, EveryLoadIsTheWholeAssemblysRightHandSide) {
  for (const double offset : {0.0, 0.013}) {
    const geometry::ImmersedDomain domain = holed_block(offset);
    const std::vector<ImmersedOptions> cases = load_cases();
    const ImmersedSystem first = assemble_immersed(domain, cases[0]);
    ASSERT_FALSE(first.nitsche_penalties.empty());
    for (size_t c = 0; c < cases.size(); ++c) {
      const ImmersedSystem whole = assemble_immersed(domain, cases[c]);
      const Eigen::VectorXd loads = assemble_immersed_loads(domain, cases[c], first);
      ASSERT_EQ(loads.size(), whole.force.size());
      EXPECT_GT(whole.force.norm(), 0.0) << c;
      // Bit for bit: the same terms summed in the same order.
      EXPECT_EQ((loads - whole.force).cwiseAbs().maxCoeff(), 0.0)
          << "case " << c << ", offset " << offset;
    }
  }
}

TEST(ImmersedLoads, OtherSupportsOrAnotherDomainAreRefused) {
  const geometry::ImmersedDomain domain = holed_block(0.0);
  const ImmersedSystem system = assemble_immersed(domain, clamped());
  ImmersedOptions other = clamped();
  other.supports[2].fixed = {true, true, false};
  const auto message = [&](const geometry::ImmersedDomain& d, const ImmersedOptions& o) {
    try {
      assemble_immersed_loads(d, o, system);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(domain, other).find("supports"), std::string::npos) << message(domain, other);
  other = clamped();
  other.material.youngs_modulus = 1e5;
  EXPECT_NE(message(domain, other).find("material"), std::string::npos);
  const geometry::ImmersedDomain shifted = holed_block(0.1);
  EXPECT_NE(message(shifted, clamped()).find("another domain"), std::string::npos)
      << message(shifted, clamped());
}

}  // namespace
}  // namespace isospring::analysis
