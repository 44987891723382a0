// Rigid placements of a CAD solid (transform_solid), the immersion's user frame
// (ImmersionOptions::frame) and the principal axes (principal_frame), by identities: the CAx-IF
// nut (tests/data/parts/caxif_nut.stp: a 20 x 15 x 3 mm plate with a bore, eight faces) turned by
// a generic rotation Q (Euler angles 20, 35 and 10 degrees about z, y and x: no face stays normal
// to an axis) and moved, immersed on a grid in the frame Q, must give the unmoved nut's
// quadrature moved (volume, area, per-face area, centroid) and the same gravity solution with
// gravity turned by Q (strain energy, displacements at corresponding points turned by Q). Only
// round-off separates the two: the turned B-rep's points are 1e-16 of the part's size off, so the
// tolerances are 1e-9 relative (the quadrature's own accuracy is 1e-6, against OpenCascade's).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

const fs::path kNut = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/caxif_nut.stp";
constexpr double kDegree = M_PI / 180.0;

Eigen::Matrix3d generic_rotation() {
  return (Eigen::AngleAxisd(20 * kDegree, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(35 * kDegree, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(10 * kDegree, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

const Eigen::Vector3d kShift(0.011, -0.023, 0.037);  // m, about the nut's size

std::vector<double> face_areas(const ImmersedDomain& domain) {
  std::vector<double> areas(static_cast<size_t>(domain.face_count), 0.0);
  for (const BoundaryPoint& b : domain.boundary) areas[static_cast<size_t>(b.face)] += b.weight;
  return areas;
}

#define SKIP_WITHOUT_NUT() \
  if (!fs::exists(kNut)) GTEST_SKIP() << kNut << " (a third-party part) is absent"

TEST(TransformSolid, MovesTheMeasuresAndKeepsTheFaces) {
  SKIP_WITHOUT_NUT();
  const CadSolid nut = read_cad_solid(kNut);
  const Eigen::Matrix3d q = generic_rotation();
  const CadSolid moved = transform_solid(nut, q, kShift);
  EXPECT_EQ(moved.face_count(), nut.face_count());
  EXPECT_EQ(moved.name(), nut.name());
  const SolidMeasures a = measure_solid(nut), b = measure_solid(moved);
  EXPECT_NEAR(b.volume, a.volume, 1e-9 * a.volume);
  EXPECT_NEAR(b.area, a.area, 1e-9 * a.area);
  EXPECT_LT((b.centroid - (q * a.centroid + kShift)).norm(), 1e-9 * 0.02);
}

TEST(TransformSolid, RefusesWhatIsNotARotation) {
  SKIP_WITHOUT_NUT();
  const CadSolid nut = read_cad_solid(kNut);
  const auto message = [&](const Eigen::Matrix3d& m) {
    try {
      transform_solid(nut, m);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Eigen::Matrix3d stretched = generic_rotation();
  stretched.col(0) *= 1.001;
  EXPECT_NE(message(stretched).find("not a rotation"), std::string::npos) << message(stretched);
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, 1, -1).asDiagonal();
  EXPECT_NE(message(mirror).find("reflection"), std::string::npos) << message(mirror);
  ImmersionOptions options;
  options.frame = mirror;
  try {
    immerse_solid(nut, options);
    ADD_FAILURE() << "a mirror frame was accepted";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame"), std::string::npos) << e.what();
  }
}

struct Immersed {
  ImmersedDomain domain;
  analysis::ImmersedResult result;
};

// The nut clamped on face 4 (x = 0) under gravity `g`, on 2 mm cells (p = 2), in `frame`.
Immersed solve(const CadSolid& solid, const Eigen::Matrix3d& frame, const Eigen::Vector3d& g) {
  ImmersionOptions immersion;
  immersion.cell_size = 0.002;
  immersion.frame = frame;
  immersion.threads = 1;
  Immersed out;
  out.domain = immerse_solid(solid, immersion);
  analysis::ImmersedOptions options;
  options.material.youngs_modulus = 210e9;
  options.material.poisson_ratio = 0.3;
  options.material.density = 7850;
  analysis::ImmersedSupport clamp;
  clamp.face = 4;
  clamp.fixed = {true, true, true};
  options.supports = {clamp};
  options.gravity = g;
  out.result = analysis::solve_immersed(out.domain, options);
  return out;
}

TEST(ImmersedFrame, TurnedPartInItsFrameIsTheUnturnedOneTurned) {
  SKIP_WITHOUT_NUT();
  const CadSolid nut = read_cad_solid(kNut);
  const Eigen::Matrix3d q = generic_rotation();
  const CadSolid moved = transform_solid(nut, q, kShift);
  const Eigen::Vector3d g(0, 0, -9.81);
  const Immersed plain = solve(nut, Eigen::Matrix3d::Identity(), g);
  const Immersed turned = solve(moved, q, q * g);
  const ImmersedDomain &a = plain.domain, &b = turned.domain;

  // The same grid and cells, seen from the frame.
  ASSERT_EQ(b.cells.size(), a.cells.size());
  EXPECT_LT((b.extent - a.extent).norm(), 1e-12);
  EXPECT_LT((b.frame - q).norm(), 1e-15);
  EXPECT_LT((b.origin - (a.origin + q.transpose() * kShift)).norm(), 1e-12);
  const SolidMeasures ma = measure_quadrature(a), mb = measure_quadrature(b);
  EXPECT_NEAR(mb.volume, ma.volume, 1e-9 * ma.volume);
  EXPECT_NEAR(mb.area, ma.area, 1e-9 * ma.area);
  EXPECT_LT((mb.centroid - (q * ma.centroid + kShift)).norm(), 1e-9 * 0.02);
  const std::vector<double> fa = face_areas(a), fb = face_areas(b);
  for (size_t f = 0; f < fa.size(); ++f) EXPECT_NEAR(fb[f], fa[f], 1e-9 * ma.area) << "face " << f;
  // And OpenCascade's measures of the moved part, to the quadrature's accuracy.
  const SolidMeasures exact = measure_solid(moved);
  EXPECT_NEAR(mb.volume, exact.volume, 1e-6 * exact.volume);
  EXPECT_NEAR(mb.area, exact.area, 1e-6 * exact.area);
  EXPECT_LT((mb.centroid - exact.centroid).norm(), 1e-6 * 0.02);
  // Normals turn with the part: per face, int n dA (the face's area vector) turned by Q. (The
  // face rules double their pieces until a face's area repeats to 1e-9, so round-off may stop
  // one a doubling earlier or later: the point counts may differ, the integrals may not.)
  std::vector<Eigen::Vector3d> na(fa.size(), Eigen::Vector3d::Zero()), nb = na;
  for (const BoundaryPoint& p : a.boundary) na[static_cast<size_t>(p.face)] += p.weight * p.normal;
  for (const BoundaryPoint& p : b.boundary) nb[static_cast<size_t>(p.face)] += p.weight * p.normal;
  for (size_t f = 0; f < fa.size(); ++f)
    EXPECT_LT((nb[f] - q * na[f]).norm(), 1e-9 * ma.area) << "face " << f;
  // The same elastic solution: energy, DOFs, displacements at corresponding points.
  EXPECT_EQ(turned.result.dofs, plain.result.dofs);
  EXPECT_NEAR(turned.result.strain_energy, plain.result.strain_energy,
              1e-9 * plain.result.strain_energy);
  const Eigen::Vector3d points[] = {{0.02, 0.0075, 0.0}, {0.02, 0.0, 0.003}, {0.01, 0.014, 0.0015}};
  const double largest =
      analysis::evaluate_immersed(a, plain.result, points[0]).displacement.norm();
  for (const Eigen::Vector3d& x : points) {
    const Eigen::Vector3d ua = analysis::evaluate_immersed(a, plain.result, x).displacement;
    const Eigen::Vector3d ub =
        analysis::evaluate_immersed(b, turned.result, q * x + kShift).displacement;
    EXPECT_LT((ub - q * ua).norm(), 1e-9 * largest) << "at " << x.transpose();
  }
}

TEST(ImmersedFrame, PrincipalAxesFollowTheRotation) {
  SKIP_WITHOUT_NUT();
  const CadSolid nut = read_cad_solid(kNut);
  const Eigen::Matrix3d q = generic_rotation();
  const PrincipalFrame a = principal_frame(nut), b = principal_frame(transform_solid(nut, q));
  EXPECT_TRUE(a.note.empty()) << a.note;
  EXPECT_TRUE(b.note.empty()) << b.note;
  for (const PrincipalFrame* f : {&a, &b}) {
    EXPECT_LT((f->axes.transpose() * f->axes - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(f->axes.determinant(), 1.0, 1e-12);
    EXPECT_LE(f->moments[0], f->moments[1]);
    EXPECT_LE(f->moments[1], f->moments[2]);
  }
  EXPECT_LT((b.moments - a.moments).norm(), 1e-9 * a.moments.norm());
  // The nut's axes are the file's (a plate in the x-y plane, longest along x), up to sign; the
  // turned nut's are Q's, up to sign. The angle between them (the cross product's norm) is
  // OpenCascade's integration error: 8.9e-9 rad, turned or not. (It makes the turned nut's
  // box 1.3e-10 m longer than its extent, which a cell size dividing the extent exactly turns
  // into one more layer of cells: docs/immersed.md, "User frame".)
  double angle = 0;
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(a.axes.col(k).cross(Eigen::Vector3d::Unit(k)).norm(), 1e-7) << k;
    EXPECT_LT(b.axes.col(k).cross(q.col(k)).norm(), 1e-7) << k;
    angle = std::max(angle, b.axes.col(k).cross(q.col(k)).norm());
  }
  std::printf("turned nut's principal axes off Q's by %.2e rad\n", angle);
  // Immersed in its principal frame, the turned nut gets the unturned nut's box (its faces along
  // the grid planes, none cut obliquely) and the volume to the quadrature's accuracy.
  ImmersionOptions options;
  options.cell_size = 0.002;
  const ImmersedDomain plain = immerse_solid(nut, options);
  options.frame = b.axes;
  const ImmersedDomain turned = immerse_solid(transform_solid(nut, q), options);
  // (Its axes are Q's up to sign, so the part is the unturned one turned by 180 degrees about
  // some axes, which the cut-cell rules treat alike only to their tolerance, not to round-off.)
  EXPECT_LT((turned.extent - plain.extent).norm(), 1e-9);
  EXPECT_NEAR(measure_quadrature(turned).volume, measure_solid(nut).volume,
              1e-6 * measure_solid(nut).volume);
}

// A cylinder (the CAx-IF rod, along z) has two equal moments: the fallback keeps the odd axis
// first and takes the world axis least aligned with it into the plane of the other two.
TEST(ImmersedFrame, PrincipalAxesOfARodFallBackToTheWorldAxes) {
  const fs::path rod = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/caxif_rod.stp";
  if (!fs::exists(rod)) GTEST_SKIP() << rod << " (a third-party part) is absent";
  const PrincipalFrame f = principal_frame(read_cad_solid(rod));
  EXPECT_NE(f.note.find("2 and 3"), std::string::npos) << f.note;
  EXPECT_NEAR(std::abs(f.axes.col(0).z()), 1.0, 1e-9);
  EXPECT_LT((f.axes.transpose() * f.axes - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(f.axes.determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace isospring::geometry
