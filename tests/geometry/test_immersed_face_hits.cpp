// The line-face intersection of the immersed CAD quadrature
// (geometry/src/immersed_cad_face_hits.hpp) against OpenCascade's IntCurvesFace_Intersector, which
// it must reproduce: on random lines (axis-parallel, as the quadrature uses, and oblique) through
// parts whose faces are planes with many holes, cylinders, cones, spheres and tori, every face
// reports the same hits (parameter and transition, bit for bit: the surface intersection is
// OpenCascade's own); on B-spline faces (trimmed, rational, with degenerate edges, and a
// third-party part whose faces are all B-splines) the same number of hits, the same transitions
// and parameters within 1e-9 (the surface intersection is Bezier subdivision and Newton's
// method). Also: the immersed domain does not depend on the thread count.
#include <gtest/gtest.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Builder.hxx>
#include <Bnd_Box.hxx>
#include <IntCurvesFace_Intersector.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "../../geometry/src/cad_solid_shape.hpp"
#include "../../geometry/src/immersed_cad_face_hits.hpp"
#include "isospring/geometry/immersed_cad.hpp"

namespace isospring::geometry {
namespace {

// A plate with a 3 x 2 array of through-holes whose upper rims are rounded: planar faces with many
// holes, cylinders and tori.
TopoDS_Shape holed_plate() {
  TopoDS_Compound holes;
  BRep_Builder builder;
  builder.MakeCompound(holes);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j)
      builder.Add(holes, BRepPrimAPI_MakeCylinder(
                             gp_Ax2(gp_Pnt(0.2 + 0.3 * i, 0.15 + 0.2 * j, -0.1), gp_Dir(0, 0, 1)),
                             0.05 + 0.01 * i, 0.4)
                             .Shape());
  const TopoDS_Shape plate =
      BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(1.0, 0.5, 0.2).Shape(), holes).Shape();
  BRepFilletAPI_MakeFillet rims(plate);
  for (TopExp_Explorer e(plate, TopAbs_EDGE); e.More(); e.Next()) {
    BRepAdaptor_Curve c(TopoDS::Edge(e.Current()));
    if (c.GetType() == GeomAbs_Circle && std::abs(c.Value(c.FirstParameter()).Z() - 0.2) < 1e-9)
      rims.Add(0.015, TopoDS::Edge(e.Current()));
  }
  return rims.Shape();
}

struct Hit {
  double w;
  int net;
};

std::vector<Hit> reference_hits(IntCurvesFace_Intersector& intersector, const gp_Lin& line,
                                double w0, double w1) {
  std::vector<Hit> hits;
  intersector.Perform(line, w0, w1);
  if (!intersector.IsDone()) return hits;
  for (int i = 1; i <= intersector.NbPnt(); ++i) {
    const IntCurveSurface_TransitionOnCurve t = intersector.Transition(i);
    hits.push_back({intersector.WParameter(i), t == IntCurveSurface_In    ? 1
                                               : t == IntCurveSurface_Out ? -1
                                                                          : 0});
  }
  return hits;
}

void sort(std::vector<Hit>& hits) {
  std::sort(hits.begin(), hits.end(),
            [](const Hit& a, const Hit& b) { return a.w < b.w || (a.w == b.w && a.net < b.net); });
}

// Is `w` a crossing of the part's boundary on `face` with transition `net`? The point lies on the
// face (OpenCascade's exact distance) and the solid's classifier changes there accordingly.
bool confirmed_crossing(const CadSolid& solid, const TopoDS_Face& face, const gp_Lin& line,
                        double w, int net, double size) {
  const auto at = [&](double t) {
    return line.Location().Translated(t * gp_Vec(line.Direction()));
  };
  BRepExtrema_DistShapeShape distance(BRepBuilderAPI_MakeVertex(at(w)).Vertex(), face);
  if (!distance.IsDone() || distance.Value() > 1e-9 * size) return false;
  BRepClass3d_SolidClassifier classifier(solid.shape().solid);
  classifier.Perform(at(w - 1e-5 * size), 1e-9 * size);
  const TopAbs_State before = classifier.State();
  classifier.Perform(at(w + 1e-5 * size), 1e-9 * size);
  const TopAbs_State after = classifier.State();
  return net > 0 ? before == TopAbs_OUT && after == TopAbs_IN
                 : net < 0 && before == TopAbs_IN && after == TopAbs_OUT;
}

// B-spline faces: every hit of IntCurvesFace found again (parameter within `tolerance`, the same
// transition). A hit IntCurvesFace did not report must be a confirmed crossing; returns how many.
long compare_within(const CadSolid& solid, const TopoDS_Face& face, const gp_Lin& line,
                    const std::vector<Hit>& expected, const std::vector<Hit>& got, double size,
                    double tolerance, const std::string& where) {
  std::vector<bool> matched(got.size(), false);
  for (const Hit& e : expected) {
    bool found = false;
    for (size_t i = 0; i < got.size() && !found; ++i)
      if (!matched[i] && std::abs(got[i].w - e.w) <= tolerance && got[i].net == e.net)
        matched[i] = found = true;
    EXPECT_TRUE(found) << where << ": IntCurvesFace's hit at w = " << e.w << " (" << e.net
                       << ") missed";
  }
  long extra = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    if (matched[i]) continue;
    ++extra;
    EXPECT_TRUE(confirmed_crossing(solid, face, line, got[i].w, got[i].net, size))
        << where << ": hit at w = " << got[i].w << " not reported by IntCurvesFace, not a crossing";
  }
  return extra;
}

// Every face of `shape` against `count` random lines through its bounding box, line parameters
// equal to `tolerance` (relative to the box's diagonal); returns the share of line-face pairs
// the bins answered (so that a test can check the fast path is taken).
double expect_same_hits(const CadSolid& solid, int count, unsigned seed, double tolerance = 0.0) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Bnd_Box box;
  BRepBndLib::Add(solid.shape().solid, box);
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  const Eigen::Vector3d lo(x0, y0, z0), hi(x1, y1, z1);
  const double size = (hi - lo).norm();
  long fast = 0, all = 0, hits_seen = 0, extra = 0;
  int face_number = 0;
  for (const TopoDS_Face& face : solid.shape().faces) {
    IntCurvesFace_Intersector reference(face, 1e-9, true, true);
    detail::FaceLineIntersector fast_path(face, 1e-9);
    for (int k = 0; k < count; ++k) {
      Eigen::Vector3d p, d = Eigen::Vector3d::Zero();
      for (int c = 0; c < 3; ++c) p[c] = lo[c] + (hi[c] - lo[c]) * unit(random);
      if (k % 4 == 3) {  // oblique
        for (int c = 0; c < 3; ++c) d[c] = unit(random) - 0.5;
        d.normalize();
      } else {
        d[k % 3] = 1.0;
      }
      const gp_Lin line(gp_Pnt(p.x(), p.y(), p.z()), gp_Dir(d.x(), d.y(), d.z()));
      const double w0 = -3.0 * size, w1 = 3.0 * size;
      std::vector<Hit> expected = reference_hits(reference, line, w0, w1);
      std::vector<detail::FaceHit> got_raw;
      fast_path.perform(line, w0, w1, got_raw);
      std::vector<Hit> got;
      for (const detail::FaceHit& h : got_raw) got.push_back({h.w, h.net});
      sort(expected);
      sort(got);
      const std::string where =
          "face " + std::to_string(face_number) + " line " + std::to_string(k);
      if (tolerance == 0.0) {  // analytic faces: bit for bit
        EXPECT_EQ(got.size(), expected.size()) << where;
        if (got.size() != expected.size()) continue;
        for (size_t i = 0; i < got.size(); ++i) {
          EXPECT_EQ(got[i].w, expected[i].w) << where;
          EXPECT_EQ(got[i].net, expected[i].net) << where;
        }
      } else {
        extra += compare_within(solid, face, line, expected, got, size, tolerance * size, where);
      }
      hits_seen += static_cast<long>(got.size());
    }
    fast += fast_path.fast_lines();
    all += fast_path.fast_lines() + fast_path.full_lines();
    ++face_number;
  }
  EXPECT_GT(hits_seen, count / 4);  // the lines do meet the part
  // OpenCascade's polyhedral pre-search may miss a hit; the other way round is a failure above.
  EXPECT_LE(extra, hits_seen / 100) << "hits IntCurvesFace did not report";
  if (extra > 0)
    std::printf("[face hits] %ld of %ld hits found that IntCurvesFace missed\n", extra, hits_seen);
  return static_cast<double>(fast) / static_cast<double>(all);
}

double expect_same_hits(const TopoDS_Shape& shape, int count, unsigned seed,
                        double tolerance = 0.0) {
  return expect_same_hits(detail::make_cad_solid(shape, "part"), count, seed, tolerance);
}

TEST(ImmersedFaceHits, PlaneCylinderAndTorusFacesMatchIntCurvesFace) {
  // 47 faces; most random lines meet the part away from every trimming curve.
  const double fast = expect_same_hits(holed_plate(), 400, 1);
  EXPECT_GT(fast, 0.5);
}

TEST(ImmersedFaceHits, ConeSphereAndTorusFacesMatchIntCurvesFace) {
  const TopoDS_Shape cone =
      BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0.5, 0.5, 0.0), gp_Dir(0, 0, 1)), 0.5, 0.2, 1.0).Shape();
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0.5, 0.5, 0.5), 0.5).Shape();
  const TopoDS_Shape torus =
      BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0.5, 0.5, 0.5), gp_Dir(1, 1, 1)), 0.35, 0.12).Shape();
  for (const TopoDS_Shape& shape : {cone, sphere, torus})
    EXPECT_GT(expect_same_hits(shape, 600, 2), 0.5);
}

TEST(ImmersedFaceHits, SplineFacesMatchIntCurvesFace) {
  // Converted to B-splines: a sphere (rational, its poles degenerate patch edges) and the holed
  // plate (trimmed planes, cylinders and tori as rational B-splines).
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0.5, 0.5, 0.5), 0.45).Shape();
  EXPECT_GT(expect_same_hits(BRepBuilderAPI_NurbsConvert(sphere).Shape(), 400, 3, 1e-9), 0.5);
  EXPECT_GT(expect_same_hits(BRepBuilderAPI_NurbsConvert(holed_plate()).Shape(), 200, 4, 1e-9),
            0.5);
}

TEST(ImmersedFaceHits, FreeformPartFacesMatchIntCurvesFace) {
  // gmsh's t20 nut (tests/data/parts/SOURCE.md): 21 trimmed B-spline faces from a STEP file.
  const CadSolid part = read_cad_solid(std::filesystem::path(ISOSPRING_SOURCE_DIR) /
                                       "tests/data/parts/gmsh_t20_data.step");
  EXPECT_GT(expect_same_hits(part, 400, 5, 1e-9), 0.5);
}

TEST(ImmersedFaceHits, ImmersedDomainDoesNotDependOnTheThreads) {
  const CadSolid solid = detail::make_cad_solid(holed_plate(), "holed plate");
  ImmersionOptions options;
  options.cell_size = 0.1;
  options.max_depth = 1;
  options.tolerance = 1e-6;
  options.threads = 1;
  ImmersionStats one_stats, two_stats;
  const ImmersedDomain one = immerse_solid(solid, options, &one_stats);
  options.threads = 2;
  const ImmersedDomain two = immerse_solid(solid, options, &two_stats);
  EXPECT_EQ(one_stats.threads, 1);
  EXPECT_EQ(two_stats.threads, 2);
  EXPECT_EQ(one_stats.lines, two_stats.lines);
  EXPECT_GT(one_stats.binned_face_lines, one_stats.face_lines / 2);
  ASSERT_EQ(one.cells.size(), two.cells.size());
  for (size_t c = 0; c < one.cells.size(); ++c) {
    EXPECT_EQ(one.cells[c].span, two.cells[c].span);
    EXPECT_EQ(one.cells[c].points, two.cells[c].points);
    EXPECT_EQ(one.cells[c].weights, two.cells[c].weights);
  }
}

}  // namespace
}  // namespace isospring::geometry
