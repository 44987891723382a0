// Cook's membrane, nearly incompressible (plane strain, E = 250, nu = 0.4999): the tapered panel
// with corners (0, 0), (48, 44), (48, 60), (0, 44), clamped at x = 0 and loaded by a uniform
// shear traction 100 / 16 on x = 48 (total 100). The benchmark of locking-free formulations;
// its reference is the vertical displacement of the upper right corner (48, 60).
#include <gtest/gtest.h>

#include <cstdio>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::analysis {
namespace {

Problem cook(int p, int n, Volumetric volumetric) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  const nurbs::Patch panel({linear, linear}, {{0, 0, 0}, {48, 44, 0}, {0, 44, 0}, {48, 60, 0}});
  Problem problem;
  problem.formulation = Formulation::kPlaneStrain;
  problem.volumetric = volumetric;
  problem.material = {250.0, 0.4999, 1.0, 1.0};
  problem.patches.push_back(nurbs::k_refine(panel, {p, p, 0}, {n, n, 1}));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, false};
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "shear";
  load.tractions.push_back({{0, 0, 1}, Eigen::Vector3d(0.0, 100.0 / 16.0, 0.0), {}});
  problem.load_cases.push_back(load);
  return problem;
}

double tip_deflection(int p, int n, Volumetric volumetric) {
  const Problem problem = cook(p, n, volumetric);
  const StaticResult result = solve_static(problem);
  return evaluate_field(problem, result.load_cases[0].control_displacements, 0, {1.0, 1.0, 0.0})
      .displacement.y();
}

TEST(BbarCook, TipDeflectionConvergesMonotonically) {
  for (int p : {2, 3}) {
    std::vector<double> tip;
    for (int n : {4, 8, 16, 32}) tip.push_back(tip_deflection(p, n, Volumetric::kBbar));
    const double locked = tip_deflection(p, 4, Volumetric::kDisplacement);
    std::printf(
        "Cook B-bar p=%d: tip %.6f %.6f %.6f %.6f (4..32); displacement formulation 4x4 %.6f\n", p,
        tip[0], tip[1], tip[2], tip[3], locked);
    for (size_t i = 1; i < tip.size(); ++i) EXPECT_GT(tip[i], tip[i - 1]);
  }
}

}  // namespace
}  // namespace isospring::analysis
