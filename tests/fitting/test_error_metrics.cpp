// %e_rms / %e_max on control points, on the displacement field and on the physical surface,
// against closed forms. The fields are NURBS combinations of control values: a field whose
// control values are affine in the control points is that affine field everywhere (affine
// invariance), and on a boundary face of an open-knot patch only the face's own control points
// have non-zero basis functions.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/fitting/error_metrics.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::fitting {
namespace {

using Field = std::vector<std::vector<Eigen::Vector3d>>;

// The unit cube as one degree-2 patch with 4 x 4 x 4 control points (2 elements per direction).
nurbs::Patch cube_patch() {
  nurbs::Patch cube = geometry::box(1.0, 1.0, 1.0)[0];
  for (int d = 0; d < 3; ++d) cube = nurbs::elevate_degree(cube, d, 1);
  return nurbs::refine_uniform(cube, 2);
}

TEST(ErrorMetrics, ControlPointsClosedForm) {
  const std::vector<Eigen::Vector3d> ref{{3, 4, 0}, {1, 0, 0}}, model{{3, 4, 0}, {1, 0, 2}};
  const ErrorMetrics m = error_metrics(ref, model);
  EXPECT_DOUBLE_EQ(m.o_max, 5.0);
  EXPECT_DOUBLE_EQ(m.percent_e_max, 40.0);                          // 100 * 2 / 5
  EXPECT_DOUBLE_EQ(m.percent_e_rms, 100.0 * std::sqrt(2.0) / 5.0);  // sqrt(4 / 2) / 5
}

// Reference u = X (affine), model = X + d: the error is |d| at every point of the surface and
// o_max = |(1, 1, 1)| = sqrt(3), attained at the sampled corner.
TEST(ErrorMetrics, SurfaceOfAShiftedAffineField) {
  const nurbs::Patch cube = cube_patch();
  ASSERT_EQ(cube.num_points(), 64);
  Field ref(1), model(1);
  const Eigen::Vector3d d(0.01, -0.02, 0.02);  // |d| = 0.03
  for (const auto& x : cube.control_points()) {
    ref[0].push_back(x);
    model[0].push_back(x + d);
  }
  const ErrorMetrics s = surface_error_metrics({cube}, ref, model, 11);
  EXPECT_EQ(s.points, 11 * 11 * 11 - 9 * 9 * 9);  // each surface sample once
  EXPECT_NEAR(s.o_max, std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(s.percent_e_rms, 100.0 * 0.03 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(s.percent_e_max, 100.0 * 0.03 / std::sqrt(3.0), 1e-12);
}

// A difference at the 8 interior control points only: invisible on the surface (exactly zero),
// visible in the volume field.
TEST(ErrorMetrics, InteriorDifferenceIsZeroOnTheSurface) {
  const nurbs::Patch cube = cube_patch();
  Field ref(1), model(1);
  for (int index = 0; index < cube.num_points(); ++index) {
    const Eigen::Vector3d x = cube.control_point(index);
    const auto ijk = cube.net_position(index);
    const bool interior = ijk[0] % 3 != 0 && ijk[1] % 3 != 0 && ijk[2] % 3 != 0;
    ref[0].push_back(x);
    model[0].push_back(interior ? Eigen::Vector3d(x + Eigen::Vector3d(0, 0, 0.1)) : x);
  }
  const ErrorMetrics s = surface_error_metrics({cube}, ref, model, 11);
  EXPECT_EQ(s.percent_e_max, 0.0);
  const ErrorMetrics v = field_error_metrics({cube}, ref, model, 11);
  EXPECT_GT(v.percent_e_max, 1.0);
}

// Two such cubes glued along x = 1; the model differs from the reference (u = X) only at the 4
// control points inside the shared face (net index 3 of the first cube, 0 of the second, the
// same nodes). Those have zero basis functions on every outer face, so with the interface left
// out the surface error is exactly zero; sampled anyway, the interface shows it. Each cube keeps
// 11^3 - 9^3 - 9^2 samples: its outer shell minus the interface's interior grid.
TEST(ErrorMetrics, InterfaceBetweenPatchesIsNotSurface) {
  const nurbs::Patch a = cube_patch();
  nurbs::Patch b = a;
  for (int i = 0; i < b.num_points(); ++i)
    b.set_control_point(i, a.control_point(i) + Eigen::Vector3d(1, 0, 0));
  analysis::Problem problem;
  problem.patches = {a, b};
  const analysis::DofMap dofs(problem);
  ASSERT_EQ(dofs.num_nodes(), 2 * 64 - 16);  // the 4 x 4 interface points are shared
  const auto inner = analysis::inner_sides(problem.patches, dofs);
  Field ref(2), model(2);
  for (int p = 0; p < 2; ++p) {
    const nurbs::Patch& patch = problem.patches[static_cast<size_t>(p)];
    for (int index = 0; index < patch.num_points(); ++index) {
      const Eigen::Vector3d x = patch.control_point(index);
      const auto ijk = patch.net_position(index);
      const bool on_interface_inside =
          ijk[0] == (p == 0 ? 3 : 0) && ijk[1] % 3 != 0 && ijk[2] % 3 != 0;
      ref[p].push_back(x);
      model[p].push_back(on_interface_inside ? Eigen::Vector3d(x + Eigen::Vector3d(0.1, 0, 0)) : x);
    }
  }
  const ErrorMetrics s = surface_error_metrics(problem.patches, ref, model, 11, inner);
  EXPECT_EQ(s.points, 2 * (11 * 11 * 11 - 9 * 9 * 9 - 9 * 9));
  EXPECT_EQ(s.percent_e_max, 0.0);
  EXPECT_NEAR(s.o_max, std::sqrt(2.0 * 2.0 + 1.0 + 1.0), 1e-14);  // the corner (2, 1, 1)
  const ErrorMetrics all = surface_error_metrics(problem.patches, ref, model, 11);
  EXPECT_GT(all.percent_e_max, 1.0);
  // inner faces for a different number of patches: a programming error caught with a message.
  EXPECT_THROW(surface_error_metrics(problem.patches, ref, model, 11, {inner[0]}),
               nurbs::InputError);
}

// A membrane (surface patch) is its own surface: both samplings agree exactly.
TEST(ErrorMetrics, MembraneSurfaceIsTheField) {
  const nurbs::Patch disk = geometry::disk(1.0)[0];
  Field ref(1), model(1);
  for (const auto& x : disk.control_points()) {
    ref[0].push_back(Eigen::Vector3d(x.y(), -x.x(), 0));
    model[0].push_back(Eigen::Vector3d(1.1 * x.y(), -x.x(), 0));
  }
  const ErrorMetrics s = surface_error_metrics({disk}, ref, model, 9);
  const ErrorMetrics f = field_error_metrics({disk}, ref, model, 9);
  EXPECT_EQ(s.points, f.points);
  EXPECT_EQ(s.percent_e_rms, f.percent_e_rms);
}

}  // namespace
}  // namespace isospring::fitting
