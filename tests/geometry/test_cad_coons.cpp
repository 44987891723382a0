// Trimmed four-sided CAD faces as Coons patches of their edges, on parts made with OpenCascade:
// boundary curves against OCCT's edges, orientation against the (convex) solid's centroid, areas
// against closed forms and BRepGProp, and faces whose Coons patch is not the surface reported.
#include <gtest/gtest.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Pln.hxx>

#include "cad_test_io.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/point_inversion.hpp"
#include "isospring/nurbs/quadrature.hpp"

namespace isospring::geometry {
namespace {

CadModel round_trip(const TopoDS_Shape& shape, const std::string& name) {
  return test::step_round_trip(shape, name);
}

TopoDS_Shape below(const gp_Pnt& point, const gp_Dir& up) {
  return test::half_space_below(point, up);
}

GProp_GProps volume_properties(const TopoDS_Shape& shape) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props, 1e-9);
  return props;
}

// Every side of every Coons face patch is one of the shape's edges: 11 OCCT samples
// (BRepAdaptor_Curve) of the edge lie on the patch side (point inversion), and the side's ends are
// the edge's ends, so the side is the whole edge. Returns the largest distance over all sides.
double boundary_error(const CadModel& model, const TopoDS_Shape& shape) {
  std::vector<TopoDS_Edge> edges;
  for (TopExp_Explorer ex(shape, TopAbs_EDGE); ex.More(); ex.Next())
    edges.push_back(TopoDS::Edge(ex.Current()));
  double worst = 0.0;
  for (size_t p = 0; p < model.face_patches.size(); ++p) {
    if (!model.face_reports[static_cast<size_t>(model.patch_face[p])].coons) continue;
    for (int dir = 0; dir < 2; ++dir)
      for (int end = 0; end < 2; ++end) {
        const nurbs::Patch side = boundary_side(model.face_patches[p], 1 - dir, end);
        double best = INFINITY;
        for (const TopoDS_Edge& edge : edges) {
          BRepAdaptor_Curve curve(edge);
          double error = 0.0;
          for (int n = 0; n <= 10 && error < best; ++n) {
            const gp_Pnt x = curve.Value(curve.FirstParameter() +
                                         (curve.LastParameter() - curve.FirstParameter()) * n / 10);
            error = std::max(
                error, nurbs::invert_point(side, Eigen::Vector3d(x.X(), x.Y(), x.Z())).distance);
          }
          // Ends of the side against the edge's ends (either way round): the side is not longer.
          const gp_Pnt a = curve.Value(curve.FirstParameter()),
                       b = curve.Value(curve.LastParameter());
          const Eigen::Vector3d s0 = side.point({side.param_min(0), 0, 0}),
                                s1 = side.point({side.param_max(0), 0, 0});
          const Eigen::Vector3d ea(a.X(), a.Y(), a.Z()), eb(b.X(), b.Y(), b.Z());
          error = std::max(error, std::min(std::max((s0 - ea).norm(), (s1 - eb).norm()),
                                           std::max((s0 - eb).norm(), (s1 - ea).norm())));
          best = std::min(best, error);
        }
        worst = std::max(worst, best);
      }
  }
  return worst;
}

// Smallest (dX/du x dX/dv) . (x - c) / |dX/du x dX/dv| / |x - c| over samples of the usable face
// patches: positive when every patch's normal points away from the point c inside a convex solid.
double smallest_outward_cosine(const CadModel& model, const Eigen::Vector3d& c) {
  double smallest = INFINITY;
  for (const nurbs::Patch& patch : model.face_patches)
    for (int a = 1; a < 8; ++a)
      for (int b = 1; b < 8; ++b) {
        const nurbs::Param u{patch.param_min(0) + (patch.param_max(0) - patch.param_min(0)) * a / 8,
                             patch.param_min(1) + (patch.param_max(1) - patch.param_min(1)) * b / 8,
                             0};
        const nurbs::PatchDerivatives d = patch.derivatives(u);
        const Eigen::Vector3d n = d.first.col(0).cross(d.first.col(1));
        smallest = std::min(smallest, n.dot(d.point - c) / n.norm() / (d.point - c).norm());
      }
  return smallest;
}

// Volume by the divergence theorem over the face patches (sum of integral x . n dA / 3).
double flux_volume(const std::vector<nurbs::Patch>& faces) {
  const nurbs::GaussRule g = nurbs::gauss_legendre(10);
  double volume = 0.0;
  for (const nurbs::Patch& f : faces) {
    const auto u = f.knots(0).unique(), v = f.knots(1).unique();
    for (size_t i = 0; i + 1 < u.size(); ++i)
      for (size_t j = 0; j + 1 < v.size(); ++j)
        for (size_t a = 0; a < g.points.size(); ++a)
          for (size_t b = 0; b < g.points.size(); ++b) {
            const double du = (u[i + 1] - u[i]) / 2, dv = (v[j + 1] - v[j]) / 2;
            const nurbs::PatchDerivatives d =
                f.derivatives({u[i] + du * (1 + g.points[a]), v[j] + dv * (1 + g.points[b]), 0});
            volume += g.weights[a] * g.weights[b] * du * dv *
                      d.point.dot(d.first.col(0).cross(d.first.col(1))) / 3.0;
          }
  }
  return volume;
}

TEST(CadCoons, PlanarQuadrilateralCutFromALargerPlane) {
  // A convex, non-parallelogram quadrilateral on a tilted plane: its UV box is larger than the
  // face (trimmed), and it has four straight edges.
  const Eigen::Vector3d origin(0.01, 0.02, 0.03);
  const Eigen::Vector3d e1 = Eigen::Vector3d(1, 0.2, 0.1).normalized();
  const Eigen::Vector3d e2 = e1.cross(Eigen::Vector3d(0.1, -0.3, 1)).cross(e1).normalized();
  const std::vector<std::pair<double, double>> corners{
      {0, 0}, {0.1, -0.01}, {0.08, 0.06}, {-0.015, 0.04}};
  BRepBuilderAPI_MakePolygon polygon;
  std::vector<Eigen::Vector3d> x;
  for (auto [s, t] : corners) {
    x.push_back(origin + s * e1 + t * e2);
    polygon.Add(gp_Pnt(x.back().x(), x.back().y(), x.back().z()));
  }
  polygon.Close();
  const Eigen::Vector3d n = e1.cross(e2);
  const gp_Pln plane(gp_Pnt(origin.x(), origin.y(), origin.z()), gp_Dir(n.x(), n.y(), n.z()));
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(plane, polygon.Wire()).Face();
  const CadModel model = round_trip(face, "quad.step");
  ASSERT_EQ(model.faces, 1);
  const CadFace& report = model.face_reports[0];
  EXPECT_FALSE(report.natural);
  ASSERT_TRUE(report.coons) << report.note;
  ASSERT_EQ(model.face_patches.size(), 1u);
  const nurbs::Patch& patch = model.face_patches[0];
  // Exact area of the quadrilateral: half the cross product of its diagonals.
  const double exact = 0.5 * (x[2] - x[0]).cross(x[3] - x[1]).norm();
  // OCCT writes STEP reals with 12 significant digits, so the corners read back are 1e-12
  // (relative) off the ones above; the bilinear patch itself is integrated exactly by Gauss.
  EXPECT_NEAR(measure(patch) / exact, 1.0, 1e-10);
  EXPECT_NEAR(measure(patch) / report.area, 1.0, 1e-9);  // BRepGProp at eps 1e-9
  EXPECT_LT(boundary_error(model, face), 1e-11);         // measured 3.7e-13 m: 12-digit coordinates
  EXPECT_LT(report.coons_deviation, 1e-12);              // m; the plane's axes carry 12 digits too
  // Orientation: dX/du x dX/dv along the face normal (forward face: the plane's normal).
  const nurbs::PatchDerivatives d = patch.derivatives({0.5, 0.5, 0});
  EXPECT_GT(d.first.col(0).cross(d.first.col(1)).normalized().dot(n), 1.0 - 1e-12);
  EXPECT_NE(describe(model).find("usable Coons patch"), std::string::npos);
}

TEST(CadCoons, BoxCutByASlantedPlaneIsClosedByItsFacePatches) {
  // Four trapezoid sides and a slanted parallelogram top (all trimmed planes), a natural bottom.
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(0.1, 0.05, 0.04).Shape();
  const gp_Dir up(-0.08, 0.1, 1.0);  // plane z = 0.025 + 0.08 x - 0.1 y
  const TopoDS_Shape part = BRepAlgoAPI_Common(box, below(gp_Pnt(0, 0, 0.025), up)).Shape();
  const GProp_GProps props = volume_properties(part);
  const double exact = 0.1 * 0.05 * (0.025 + 0.08 * 0.05 - 0.1 * 0.025);  // mean height
  ASSERT_NEAR(props.Mass() / exact, 1.0, 1e-9);
  const CadModel model = round_trip(part, "cut_box.step");
  ASSERT_EQ(model.faces, 6);
  int coons = 0;
  for (const auto& f : model.face_reports) coons += f.coons;
  EXPECT_EQ(coons, 5);
  ASSERT_EQ(model.face_patches.size(), 6u);
  EXPECT_LT(boundary_error(model, part), 1e-12);
  const gp_Pnt c = props.CentreOfMass();
  EXPECT_GT(smallest_outward_cosine(model, {c.X(), c.Y(), c.Z()}), 0.05);
  // Closed and outward: the divergence theorem over the patches gives the volume.
  EXPECT_NEAR(flux_volume(model.face_patches) / exact, 1.0, 1e-13);
  double area = 0.0;
  for (const auto& f : model.face_reports) area += f.area;
  EXPECT_NEAR(measure(model.face_patches) / area, 1.0, 1e-9);
  // Still a hexahedron with planar faces: one trilinear volume patch of the same volume.
  ASSERT_EQ(model.volume_patches.size(), 1u);
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-13);
}

TEST(CadCoons, CylinderSectorCutBySlantedPlane) {
  // Quarter cylinder r = 0.05, cut by z = 0.06 + 0.3 x: the curved face has a bottom arc, two
  // vertical lines and a top ellipse arc; its Coons patch lies on the cylinder.
  const double r = 0.05;
  const TopoDS_Shape sector = BRepPrimAPI_MakeCylinder(r, 0.2, M_PI / 2).Shape();
  const TopoDS_Shape part =
      BRepAlgoAPI_Common(sector, below(gp_Pnt(0, 0, 0.06), gp_Dir(-0.3, 0, 1))).Shape();
  const CadModel model = round_trip(part, "cylinder_wedge.step");
  const nurbs::Patch* curved = nullptr;
  int reported = 0;
  for (size_t p = 0; p < model.face_patches.size(); ++p)
    if (model.face_reports[static_cast<size_t>(model.patch_face[p])].surface_type == "cylinder")
      curved = &model.face_patches[p];
  for (const auto& f : model.face_reports)
    if (!f.natural && !f.coons) {
      ++reported;  // the quarter disc at the bottom and the quarter ellipse at the top: 3 edges
      EXPECT_EQ(f.edges, 3);
      // Not one Coons patch, but cut like a disk: a central square and four patches out to the
      // loop (Jacobians positive, area as OpenCascade's to 1e-9: checked by the cut).
      EXPECT_EQ(f.split, 5) << f.note;
    }
  EXPECT_EQ(reported, 2);
  ASSERT_NE(curved, nullptr);
  // On the cylinder: every sample at radius r.
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; b <= 10; ++b) {
      const Eigen::Vector3d x = curved->point({a / 10.0, b / 10.0, 0});
      EXPECT_NEAR(std::hypot(x.x(), x.y()), r, 1e-15);
    }
  // Area: integral over theta of r (0.06 + 0.3 r cos theta).
  const double exact = r * (0.06 * M_PI / 2 + 0.3 * r);
  EXPECT_NEAR(measure(*curved) / exact, 1.0, 1e-12);
  EXPECT_LT(boundary_error(model, part), 1e-12);
  const gp_Pnt c = volume_properties(part).CentreOfMass();
  EXPECT_GT(smallest_outward_cosine(model, {c.X(), c.Y(), c.Z()}), 0.0);
}

TEST(CadCoons, SphereFaceBoundedByFourArcsIsReportedWithItsDeviation) {
  // A sphere (axis x, seam underneath) cut by a box: the spherical face has four circular arcs,
  // and the Coons patch of four arcs is not on the sphere. The four vertical sides are planar
  // faces bounded by three lines and an arc: Coons patches of rational and polynomial edges.
  const double R = 0.05;
  const TopoDS_Shape sphere =
      BRepPrimAPI_MakeSphere(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), gp_Dir(0, 0, -1)), R).Shape();
  const TopoDS_Shape box =
      BRepPrimAPI_MakeBox(gp_Pnt(-0.03, -0.02, 0), gp_Pnt(0.03, 0.02, 0.1)).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Common(sphere, box).Shape();
  const CadModel model = round_trip(part, "sphere_cap.step");
  int spherical = 0, coons = 0;
  for (const auto& f : model.face_reports) {
    if (f.surface_type == "sphere") {
      ++spherical;
      EXPECT_FALSE(f.natural || f.coons);
      EXPECT_NE(f.note.find("off the sphere surface"), std::string::npos) << f.note;
      EXPECT_NE(f.note.find("split it"), std::string::npos) << f.note;
    }
    if (f.coons) {
      ++coons;
      EXPECT_EQ(f.surface_type, "plane");
      EXPECT_NEAR(measure(model.face_patches[static_cast<size_t>(
                      std::find(model.patch_face.begin(), model.patch_face.end(), f.index) -
                      model.patch_face.begin())]) /
                      f.area,
                  1.0, 1e-9);
    }
  }
  EXPECT_EQ(spherical, 1);
  EXPECT_EQ(coons, 4);
  // Hexahedral topology (8 vertices, 12 edges, 6 four-sided faces), but no volume patch.
  EXPECT_TRUE(model.volume_patches.empty());
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_NE(model.solid_notes[0].find("not the blend of its edges"), std::string::npos)
      << model.solid_notes[0];
  EXPECT_LT(boundary_error(model, part), 1e-12);
  try {
    cad_patches(model);
    FAIL() << "the spherical face must be rejected";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sphere"), std::string::npos);
  }
}

}  // namespace
}  // namespace isospring::geometry
