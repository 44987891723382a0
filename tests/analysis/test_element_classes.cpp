// Equal element matrices on affine patches (analysis/src/element_classes.hpp): which patches are
// affine, how many classes a uniform knot vector gives (by hand: on span s the basis is defined
// by the 2p knots t_{s-p+1} .. t_{s+p}, so with open uniform knots only the first and last p - 1
// spans see the repeated end knots: 2p - 1 classes per direction, 3 at p = 2), and the reference:
// every element matrix taken from its class equals the element's own integration, on a uniform box,
// a graded box and a rotated, sheared (still affine) box; a curved or rational patch caches
// nothing.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "analysis_models.hpp"
#include "assembly_structure.hpp"
#include "element_classes.hpp"
#include "isospring/analysis/constraints.hpp"

namespace isospring::analysis {
namespace {
using testing::graded_k_refine;
using testing::sphere_octant;

nurbs::Patch box(std::array<int, 3> elements, int degree = 2,
                 const Eigen::Matrix3d& map = Eigen::Matrix3d::Identity()) {
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        points.push_back(map * Eigen::Vector3d(2.0 * i, 1.0 * j, 0.5 * k));
  return nurbs::k_refine(nurbs::Patch({linear, linear, linear}, points), {degree, degree, degree},
                         {elements[0], elements[1], elements[2]});
}

Problem problem_of(nurbs::Patch patch) {
  Problem problem;
  problem.material = {210e9, 0.3, 7800, 1.0};
  problem.patches.push_back(std::move(patch));
  Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  LoadCase load;
  load.id = "g";
  load.gravity = {0, 0, -9.81};
  problem.load_cases.push_back(load);
  return problem;
}

// Max relative difference between the class matrices and each element's own integral.
double cached_against_integrated(const Problem& problem, long long* cached) {
  const SupportedProblem supported = number_and_support(problem);
  const detail::AssemblyStructure structure(problem, supported.dofs);
  const detail::ElementStiffness reuse(problem, structure);
  const detail::ElementStiffness reference(problem, structure, false);
  *cached = reuse.cached_elements();
  detail::QuadraturePoint point;
  Eigen::MatrixXd a, b;
  double worst = 0;
  for (int e = 0; e < static_cast<int>(structure.elements.size()); ++e) {
    reuse(e, point, a);
    reference(e, point, b);
    worst = std::max(worst, (a - b).norm() / b.norm());
  }
  return worst;
}

TEST(ElementClasses, AffineBoxesAreRecognisedAndCurvedOrPerturbedOnesAreNot) {
  EXPECT_TRUE(detail::affine_patch(box({6, 5, 4})));
  const Eigen::Matrix3d shear =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
      (Eigen::Matrix3d() << 1, 0.3, 0, 0, 1, 0.2, 0, 0, 1).finished();
  EXPECT_TRUE(detail::affine_patch(box({6, 5, 4}, 3, shear)));
  EXPECT_TRUE(
      detail::affine_patch(graded_k_refine(box({1, 1, 1}, 1), {2, 2, 2}, {4, 4, 8}, 2, 1.5)));
  nurbs::Patch moved = box({6, 5, 4});
  std::vector<Eigen::Vector3d> points = moved.control_points();
  points[static_cast<size_t>(moved.index(3, 2, 2))].x() += 1e-6;
  moved = nurbs::Patch(moved.all_knots(), points, moved.weights());
  EXPECT_FALSE(detail::affine_patch(moved));
  EXPECT_FALSE(detail::affine_patch(sphere_octant(1.0, 2.0)));  // rational, curved
}

TEST(ElementClasses, UniformKnotsGive2pMinus1ClassesPerDirection) {
  for (int degree : {2, 3}) {
    const nurbs::Patch patch = box({8, 6, 5}, degree);
    const detail::PatchQuadrature quadrature = detail::PatchQuadrature::volume(patch, 0);
    const detail::ElementClasses classes = detail::affine_element_classes(quadrature);
    const size_t per_direction = static_cast<size_t>(2 * degree - 1);
    EXPECT_EQ(classes.first.size(), per_direction * per_direction * per_direction);
    ASSERT_EQ(classes.of_element.size(), 8u * 6u * 5u);
    for (size_t c = 0; c < classes.first.size(); ++c)
      EXPECT_EQ(classes.of_element[static_cast<size_t>(classes.first[c])], static_cast<int>(c));
    // Elements p - 1 .. n - p of every direction are the interior class; element 0 is not.
    const auto at = [](int i, int j, int k) { return static_cast<size_t>(i + 8 * (j + 6 * k)); };
    const int interior = classes.of_element[at(degree - 1, degree - 1, degree - 1)];
    EXPECT_EQ(classes.of_element[at(8 - degree, 6 - degree, 5 - degree)], interior);
    EXPECT_NE(classes.of_element[at(degree - 2, degree - 1, degree - 1)], interior);
    EXPECT_NE(classes.of_element[at(0, 0, 0)], classes.of_element[at(7, 5, 4)]);
  }
}

TEST(ElementClasses, ClassMatricesEqualEachElementsOwnIntegral) {
  long long cached = 0;
  EXPECT_LT(cached_against_integrated(problem_of(box({8, 6, 5})), &cached), 1e-13);
  EXPECT_EQ(cached, 8 * 6 * 5);
  const Eigen::Matrix3d shear =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
      (Eigen::Matrix3d() << 1, 0.3, 0, 0, 1, 0.2, 0, 0, 1).finished();
  EXPECT_LT(cached_against_integrated(problem_of(box({12, 12, 10}, 3, shear)), &cached), 1e-13);
  EXPECT_EQ(cached, 12 * 12 * 10);  // 5^3 classes
}

TEST(ElementClasses, GradedOrCurvedPatchesIntegrateEveryElement) {
  long long cached = 0;
  // Graded knots: each span of the graded direction is a class of its own, so 4 x 4 x 8 classes
  // for 128 elements, more than the one in eight worth a cache.
  const nurbs::Patch graded = graded_k_refine(box({1, 1, 1}, 1), {2, 2, 2}, {4, 4, 8}, 2, 1.5);
  EXPECT_LT(cached_against_integrated(problem_of(graded), &cached), 1e-15);
  EXPECT_EQ(cached, 0);
  const nurbs::Patch octant = nurbs::k_refine(sphere_octant(1.0, 2.0), {2, 2, 2}, {4, 4, 4});
  EXPECT_LT(cached_against_integrated(problem_of(octant), &cached), 1e-15);
  EXPECT_EQ(cached, 0);
}

}  // namespace
}  // namespace isospring::analysis
