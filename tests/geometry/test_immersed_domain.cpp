// Immersed domains of CAD solids (immersed_cad.hpp): the quadrature's volume, area and centroid
// against OpenCascade's (BRepGProp) and closed forms, on shapes built with OpenCascade and on
// third-party parts; the boundary points against the divergence theorem and the per-face areas
// `isospring info` reports; bad parts and options.
#include <gtest/gtest.h>
#include <unistd.h>

#include <BRepBuilderAPI_MakeShell.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Builder.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace fs = std::filesystem;
using isospring::nurbs::InputError;

namespace isospring::geometry {
namespace {

fs::path shared_cad() {
  const char* env = std::getenv("ISOSPRING_SHARED_DIR");
  return fs::path(env ? env : ISOSPRING_SHARED_DIR) / "cad";
}

fs::path temp_dir() {
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_immersed-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

fs::path write_step(const TopoDS_Shape& shape, const std::string& name) {
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  EXPECT_EQ(writer.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
  const fs::path file = temp_dir() / name;
  EXPECT_EQ(writer.Write(file.string().c_str()), IFSelect_RetDone);
  return file;
}

// Relative errors of the quadrature against OpenCascade (centroid: relative to the part's size).
struct Errors {
  double volume = 0.0, area = 0.0, centroid = 0.0;
  SolidMeasures quadrature, occt;
};

Errors errors(const CadSolid& solid, const ImmersedDomain& domain) {
  Errors e;
  e.quadrature = measure_quadrature(domain);
  e.occt = measure_solid(solid);
  const double size = std::cbrt(e.occt.volume);
  e.volume = std::abs(e.quadrature.volume / e.occt.volume - 1.0);
  e.area = std::abs(e.quadrature.area / e.occt.area - 1.0);
  e.centroid = (e.quadrature.centroid - e.occt.centroid).norm() / size;
  return e;
}

// The quadrature agrees with OpenCascade to `tolerance`; prints the errors for the docs' table.
Errors expect_matches_occt(const CadSolid& solid, const ImmersionOptions& options = {},
                           double tolerance = 1e-6) {
  ImmersionStats stats;
  const ImmersedDomain domain = immerse_solid(solid, options, &stats);
  const Errors e = errors(solid, domain);
  EXPECT_LT(e.volume, tolerance) << solid.name();
  EXPECT_LT(e.area, tolerance) << solid.name();
  EXPECT_LT(e.centroid, tolerance) << solid.name();
  int cut = 0;
  size_t points = 0;
  for (const ImmersedCell& cell : domain.cells) {
    cut += cell.kind == CellKind::kCut;
    points += cell.points.size();
  }
  std::printf(
      "[immersed] %s: volume %.2e, area %.2e, centroid %.2e (cells %zu, cut %d, points %zu, "
      "boundary points %zu; %.2f s boundary, %.2f s classification, %.2f s cut cells, "
      "%ld lines, %ld classified, %ld of %ld face-line tests fast)\n",
      solid.name().c_str(), e.volume, e.area, e.centroid, domain.cells.size(), cut, points,
      domain.boundary.size(), stats.boundary_seconds, stats.classification_seconds,
      stats.cut_cell_seconds, stats.lines, stats.classified_lines, stats.binned_face_lines,
      stats.face_lines);
  for (const std::string& w : domain.warnings) std::printf("[immersed]   warning: %s\n", w.c_str());
  return e;
}

TEST(ImmersedCad, SphereMatchesItsClosedForm) {
  const double r = 0.04;
  const gp_Pnt centre(0.013, 0.007, -0.002);
  const CadSolid solid =
      detail::make_cad_solid(BRepPrimAPI_MakeSphere(centre, r).Shape(), "sphere");
  const Errors e = expect_matches_occt(solid);
  EXPECT_NEAR(e.quadrature.volume, 4.0 / 3.0 * M_PI * r * r * r, 1e-6 * e.quadrature.volume);
  EXPECT_NEAR(e.quadrature.area, 4.0 * M_PI * r * r, 1e-6 * e.quadrature.area);
  EXPECT_LT((e.quadrature.centroid - Eigen::Vector3d(0.013, 0.007, -0.002)).norm(), 1e-6 * r);
}

TEST(ImmersedCad, CylinderAndTorusMatchTheirClosedForms) {
  const double r = 0.03, h = 0.08;
  const CadSolid cylinder = detail::make_cad_solid(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.01, 0.0, 0.0), gp_Dir(0, 0, 1)), r, h).Shape(),
      "cylinder");
  const Errors c = expect_matches_occt(cylinder);
  EXPECT_NEAR(c.quadrature.volume, M_PI * r * r * h, 1e-6 * c.quadrature.volume);
  EXPECT_NEAR(c.quadrature.area, 2 * M_PI * r * (r + h), 1e-6 * c.quadrature.area);
  const double R = 0.05, a = 0.02;
  const CadSolid torus = detail::make_cad_solid(
      BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 1, 1)), R, a).Shape(), "torus");
  const Errors t = expect_matches_occt(torus);
  EXPECT_NEAR(t.quadrature.volume, 2 * M_PI * M_PI * R * a * a, 1e-6 * t.quadrature.volume);
  EXPECT_NEAR(t.quadrature.area, 4 * M_PI * M_PI * R * a, 1e-6 * t.quadrature.area);
}

TEST(ImmersedCad, ObliqueCylinderMatchesItsClosedForm) {
  // Sharp circular edges crossing the cells obliquely: what the octree is there for.
  const double r = 0.02, h = 0.07;
  const CadSolid solid = detail::make_cad_solid(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 2, 3)), r, h).Shape(),
      "oblique cylinder");
  const Errors e = expect_matches_occt(solid);
  EXPECT_NEAR(e.quadrature.volume, M_PI * r * r * h, 1e-6 * e.quadrature.volume);
}

TEST(ImmersedCad, FilletedBoxMatchesTheSteinerFormula) {
  // A box with every edge rounded by r is the inner box (a-2r, b-2r, c-2r) grown by a ball of r.
  const double a = 0.1, b = 0.06, c = 0.04, r = 0.01;
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(a, b, c).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next())
    fillet.Add(r, TopoDS::Edge(e.Current()));
  const CadSolid solid = detail::make_cad_solid(fillet.Shape(), "filleted box");
  const Errors e = expect_matches_occt(solid);
  const double A = a - 2 * r, B = b - 2 * r, C = c - 2 * r;
  const double volume = A * B * C + 2 * (A * B + B * C + C * A) * r + M_PI * (A + B + C) * r * r +
                        4.0 / 3.0 * M_PI * r * r * r;
  // OpenCascade's corner patches approximate the sphere octants.
  EXPECT_NEAR(e.quadrature.volume, volume, 1e-5 * volume);
}

TEST(ImmersedCad, BoundaryPointsObeyTheDivergenceTheorem) {
  // (1/3) sum w x.n = volume from the cells, sum w n = 0: the boundary's normals and weights
  // against the cells' weights, two independent integrations (a box with rounded edges: planes,
  // cylinders and OpenCascade's corner blends).
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(0.05, 0.04, 0.03).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next())
    fillet.Add(0.008, TopoDS::Edge(e.Current()));
  const CadSolid solid = detail::make_cad_solid(fillet.Shape(), "rounded box");
  const ImmersedDomain domain = immerse_solid(solid);
  double flux = 0.0;
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  for (const BoundaryPoint& p : domain.boundary) {
    EXPECT_NEAR(p.normal.norm(), 1.0, 1e-12);
    EXPECT_GT(p.weight, 0.0);
    flux += p.weight * p.point.dot(p.normal) / 3.0;
    normal_sum += p.weight * p.normal;
  }
  const SolidMeasures m = measure_quadrature(domain);
  std::printf("[immersed] divergence: flux/volume - 1 = %.2e, |sum w n| / area = %.2e\n",
              flux / m.volume - 1.0, normal_sum.norm() / m.area);
  EXPECT_NEAR(flux, m.volume, 1e-6 * m.volume);
  EXPECT_LT(normal_sum.norm(), 1e-7 * m.area);
}

TEST(ImmersedCad, CellsAreKnotSpansOfAnAffineBackground) {
  const CadSolid solid = detail::make_cad_solid(
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), 0.01, 0.05).Shape(),
      "cylinder");
  ImmersionOptions options;
  options.degree = 3;
  options.cells = {7, 4, 5};
  options.margin = 0.002;
  const ImmersedDomain d = immerse_solid(solid, options);
  ASSERT_EQ(d.background.param_dim(), 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(d.background.degree(k), 3);
    EXPECT_EQ(d.background.knots(k).num_elements(), options.cells[k]);
  }
  // Parametric and physical coordinates are related by origin and extent.
  for (const nurbs::Param& u : {nurbs::Param{0.1, 0.7, 0.3}, nurbs::Param{0.9, 0.2, 0.55}})
    EXPECT_LT((d.background.derivatives(u).point -
               (d.origin + d.extent.cwiseProduct(Eigen::Vector3d(u[0], u[1], u[2]))))
                  .norm(),
              1e-14);
  EXPECT_NEAR(d.origin.x(), -0.002, 1e-12);
  EXPECT_NEAR(d.extent.x(), 0.054, 1e-12);
  BRepClass3d_SolidClassifier classifier(solid.shape().solid);
  const Eigen::Vector3d h = d.extent.cwiseQuotient(options.cells.cast<double>());
  int cut = 0;
  for (const ImmersedCell& cell : d.cells) {
    const Eigen::Vector3i element = cell.span - Eigen::Vector3i::Constant(3);
    ASSERT_TRUE((element.array() >= 0).all() && (element.array() < options.cells.array()).all());
    const Eigen::Vector3d lo = d.origin + h.cwiseProduct(element.cast<double>());
    double volume = 0.0;
    for (size_t q = 0; q < cell.points.size(); ++q) {
      EXPECT_GT(cell.weights[q], 0.0);
      volume += cell.weights[q];
      const Eigen::Vector3d& x = cell.points[q];
      ASSERT_TRUE((x.array() >= lo.array() - 1e-12).all() &&
                  (x.array() <= (lo + h).array() + 1e-12).all());
      classifier.Perform(gp_Pnt(x.x(), x.y(), x.z()), 1e-12);
      EXPECT_NE(classifier.State(), TopAbs_OUT);
    }
    if (cell.kind == CellKind::kInside) {
      EXPECT_EQ(cell.points.size(), 64u);  // (p + 1)^3 Gauss points
      EXPECT_NEAR(volume, h.prod(), 1e-12 * h.prod());
    } else {
      ++cut;
      EXPECT_LT(volume, h.prod() * (1 + 1e-12));
    }
  }
  EXPECT_GT(cut, 0);
  EXPECT_EQ(d.face_count, 3);
}

TEST(ImmersedCad, FacesKeepTheNumbersAndAreasInfoReports) {
  // The bracket of examples/cad: its faces' areas from read_cad (OpenCascade) against the sums of
  // the boundary weights per face index.
  const fs::path file = fs::path(ISOSPRING_SOURCE_DIR) / "examples/cad/bracket.step";
  const CadModel model = read_cad(file);
  const ImmersedDomain d = immerse_solid(read_cad_solid(file));
  ASSERT_EQ(d.face_count, model.faces);
  std::vector<double> area(static_cast<size_t>(model.faces), 0.0);
  for (const BoundaryPoint& p : d.boundary) area[static_cast<size_t>(p.face)] += p.weight;
  for (const CadFace& f : model.face_reports)
    EXPECT_NEAR(area[static_cast<size_t>(f.index)], f.area, 1e-9 * f.area) << "face " << f.index;
}

TEST(ImmersedCad, ExamplePartsMatchOpenCascade) {
  for (const char* name :
       {"block.step", "torus.step", "tube.step", "plate_with_holes.step", "bracket.step"})
    expect_matches_occt(read_cad_solid(fs::path(ISOSPRING_SOURCE_DIR) / "examples/cad" / name));
}

TEST(ImmersedCad, FreeformPartMatchesOpenCascade) {
  // gmsh's t20 nut (tests/data/parts/SOURCE.md): every one of its 21 faces a trimmed B-spline,
  // so every line-face hit goes through the B-spline path (immersed_cad_spline_hits.hpp). With
  // the defaults the volume is 6.2e-6 and the centroid 2.3e-6 off: its chamfers cross cells
  // obliquely and 1,038 pieces stop at max_depth 4 above the Gauss-order tolerance (the domain's
  // warning); the hits are IntCurvesFace's (tests/geometry/test_immersed_face_hits.cpp), whose
  // own run gives the same volume to 2e-7 on a coarser grid (6 cells, no bisection). The pieces'
  // error estimates add up to 1.4e-6 and the higher Gauss order everywhere moves the volume by
  // 1.4e-8: the rest is the B-rep's, whose shell is open by int n dA = 8.1e-6 of its area, so
  // that its divergence-theorem volume moves by 1.6e-4 between the origin and the centroid as the
  // reference point (test_immersed_every_part.cpp). So 1e-5.
  const CadSolid part =
      read_cad_solid(fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/gmsh_t20_data.step");
  const Errors e = expect_matches_occt(part, {}, 1e-5);
  EXPECT_LT(e.area, 1e-9);  // the boundary points do not depend on the cut cells
}

TEST(ImmersedCad, CadQueryBodiesMatchTheirClosedForms) {
  // CadQuery's test part (tests/geometry/data/SOURCE.md): a 10 mm cube and a cylinder r 5 mm,
  // h 10 mm, in one file; each body on its own.
  const fs::path file =
      fs::path(ISOSPRING_SOURCE_DIR) / "tests/geometry/data/red_cube_blue_cylinder.step";
  for (const int body : {0, 1}) {
    const Errors e = expect_matches_occt(read_cad_solid(file, body));
    if (e.quadrature.centroid.x() < 0.0) {  // the cube, x in [-10, 0] mm
      EXPECT_NEAR(e.quadrature.volume, 1e-6, 1e-6 * 1e-6);
      EXPECT_LT((e.quadrature.centroid - Eigen::Vector3d(-0.005, 0.005, 0.005)).norm(), 1e-9);
    } else {
      EXPECT_NEAR(e.quadrature.volume, M_PI * 25e-6 * 0.01, 1e-6 * e.quadrature.volume);
      EXPECT_LT((e.quadrature.centroid - Eigen::Vector3d(0.01, 0.005, 0.005)).norm(), 1e-9);
    }
  }
  try {
    read_cad_solid(file);
    FAIL() << "two solids accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 solids"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("choose one"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_cad_solid(file, 2), InputError);
}

TEST(ImmersedCad, SharedPartsMatchOpenCascade) {
  const fs::path dir = shared_cad();
  if (!fs::exists(dir / "l_bracket_caxif.stp"))
    GTEST_SKIP() << "third-party parts not found in " << dir
                 << " (set ISOSPRING_SHARED_DIR to the shared folder)";
  for (const char* name :
       {"l_bracket_caxif.stp", "plate_caxif.stp", "torus_ap203.stp", "cylinder_catia.igs"})
    expect_matches_occt(read_cad_solid(dir / name));
  EXPECT_THROW(read_cad_solid(dir / "cube_cylinder_cadquery.step"), InputError);
}

TEST(ImmersedCad, OpenShellIsRefusedWithTheFix) {
  // Five faces of a box, sewn: a shell with a hole.
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(0.02, 0.02, 0.02).Shape();
  BRepBuilderAPI_Sewing sewing(1e-6);
  int n = 0;
  for (TopExp_Explorer f(box, TopAbs_FACE); f.More(); f.Next())
    if (n++ < 5) sewing.Add(f.Current());
  sewing.Perform();
  const fs::path file = write_step(sewing.SewedShape(), "open_shell.step");
  try {
    read_cad_solid(file);
    FAIL() << "open shell accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open shell"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(ImmersedCad, SeveralSolidsAreRefusedWithTheFix) {
  TopoDS_Compound both;
  BRep_Builder builder;
  builder.MakeCompound(both);
  builder.Add(both, BRepPrimAPI_MakeBox(0.01, 0.01, 0.01).Shape());
  builder.Add(both, BRepPrimAPI_MakeBox(gp_Pnt(0.02, 0, 0), 0.01, 0.01, 0.01).Shape());
  const fs::path file = write_step(both, "two_boxes.step");
  EXPECT_THROW(read_cad_solid(file), InputError);
  EXPECT_THROW(detail::make_cad_solid(both, "two boxes"), InputError);
  const ImmersedDomain second = immerse_solid(read_cad_solid(file, 1));
  EXPECT_NEAR(measure_quadrature(second).volume, 1e-6, 1e-15);
  EXPECT_NEAR(measure_quadrature(second).centroid.x(), 0.025, 1e-12);
}

TEST(ImmersedCad, PartSmallerThanOneCellAndBadOptionsAreRefused) {
  const CadSolid solid =
      detail::make_cad_solid(BRepPrimAPI_MakeBox(0.01, 0.02, 0.005).Shape(), "small box");
  const auto message = [&](const ImmersionOptions& o) {
    try {
      immerse_solid(solid, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  ImmersionOptions o;
  o.cell_size = 0.05;
  EXPECT_NE(message(o).find("smaller than one cell"), std::string::npos) << message(o);
  o = {};
  o.degree = 0;
  EXPECT_NE(message(o).find("degree"), std::string::npos);
  o = {};
  o.cells = {4, 0, 4};
  EXPECT_NE(message(o).find("cells"), std::string::npos);
  o = {};
  o.margin = -1.0;
  EXPECT_NE(message(o).find("margin"), std::string::npos);
  o = {};
  o.box_min = {0.001, 0, 0};
  o.box_max = {0.02, 0.03, 0.01};
  EXPECT_NE(message(o).find("does not contain the part"), std::string::npos) << message(o);
  o = {};
  o.gauss = 2;
  EXPECT_NE(message(o).find("gauss"), std::string::npos);
}

TEST(ImmersedCad, UserBoxAndOffsetsKeepTheAccuracy) {
  // The same part at small offsets to a fixed grid: the cells are cut differently, the measures
  // stay within the tolerance.
  for (const double shift : {0.0, 1e-4, 3.3e-3}) {
    const CadSolid solid = detail::make_cad_solid(
        BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(shift, 0.5 * shift, 0), gp_Dir(0, 1, 0)), 0.015,
                                 0.04)
            .Shape(),
        "shifted cylinder");
    ImmersionOptions o;
    o.box_min = {-0.02, -0.01, -0.02};
    o.box_max = {0.025, 0.05, 0.02};
    o.cells = {9, 12, 8};
    expect_matches_occt(solid, o);
  }
}

}  // namespace
}  // namespace isospring::geometry
