// CAD parts with holes and many-edged faces: planar faces cut into conforming patches (areas
// against OpenCascade's BRepGProp, Jacobians positive, sides conforming), prisms as volumes
// (volumes against BRepGProp and closed forms), clear messages for what is not cut, and the
// imported plate with a hole converging at the optimal rates against Kirsch.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <gp_Circ.hxx>
#include <map>
#include <nlohmann/json.hpp>

#include "cad_test_io.hpp"
#include "cad_test_parts.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "planar_split_checks.hpp"
#include "run_program.hpp"

namespace isospring::geometry {
namespace {

namespace fs = std::filesystem;

fs::path example(const std::string& name) {
  return fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "cad" / name;
}

// Every face becomes patches; their total area is OpenCascade's (BRepGProp) to 1e-9 relative,
// every cut face's patches are right-handed and conforming (the sides nobody shares add up to
// the face's perimeter). Returns the number of cut faces.
int check_all_faces(const CadModel& model) {
  for (const auto& f : model.face_reports)
    EXPECT_TRUE(f.natural || f.coons || f.split > 0)
        << model.file << " face " << f.index << ": " << f.note;
  const std::vector<nurbs::Patch> patches = cad_patches(model, 0.0, [&] {
    std::vector<int> all;
    for (int f = 0; f < model.faces; ++f) all.push_back(f);
    return all;
  }());
  EXPECT_NEAR(measure(patches) / model.area, 1.0, 1e-9) << model.file;
  int cut = 0;
  for (const auto& f : model.face_reports) {
    if (f.split == 0) continue;
    ++cut;
    EXPECT_GT(f.jacobian_min, 0.0) << model.file << " face " << f.index;
    std::vector<nurbs::Patch> face;
    for (size_t p = 0; p < model.split_patches.size(); ++p)
      if (model.split_patch_face[p] == f.index) face.push_back(model.split_patches[p]);
    EXPECT_EQ(static_cast<int>(face.size()), f.split);
    EXPECT_NEAR(measure(face) / f.area, 1.0, 1e-9) << model.file << " face " << f.index;
    // A conforming cut leaves only the face's edges unshared (their length: BRepGProp).
    EXPECT_NEAR(test::unshared_side_length(face, 1e-12) / f.perimeter, 1.0, 1e-9)
        << model.file << " face " << f.index;
  }
  return cut;
}

TEST(CadSplit, PlateWithHolesExample) {
  const CadModel model = read_cad(example("plate_with_holes.step"));
  // Top and bottom: 7 rectangles and 2 x 4 ring patches each (see test_planar_split.cpp).
  EXPECT_EQ(check_all_faces(model), 2);
  for (const auto& f : model.face_reports)
    if (f.split > 0) {
      EXPECT_EQ(f.split, 15) << f.index;
    }
  // The solid is the prism of a cut face: 15 volume patches, volume as OpenCascade's and as
  // the closed form 0.18 * 0.15 * 0.02 - 2 pi 0.005^2 0.02.
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_EQ(model.solid_notes[0], "");
  EXPECT_EQ(model.volume_patches.size(), 15u);
  const double exact = test::cad_test_parts()["plate_with_holes.step"].exact_volume;
  EXPECT_NEAR(measure(model.volume_patches) / model.volume, 1.0, 1e-9);
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-12);
  for (const auto& p : model.volume_patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  // Conforming volumes: the faces no other patch shares are the part's surface (BRepGProp).
  EXPECT_NEAR(test::unshared_face_area(model.volume_patches, 1e-12) / model.area, 1.0, 1e-9);
  EXPECT_EQ(cad_patches(model).size(), 15u);  // the analysis takes the volumes
  // A cut face alone as a thin plate: its 15 patches extruded by `thickness` along the normal;
  // without thickness, the bottom face (z = 0, facing -z) is a 2D region, right-handed in x-y.
  for (const auto& f : model.face_reports) {
    if (f.split == 0) continue;
    const auto region = cad_patches(model, 0.0, {f.index});
    if (region[0].physical_dim() == 2) {
      for (const auto& p : region) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
    }
    const auto plate = cad_patches(model, 0.001, {f.index});
    ASSERT_EQ(plate.size(), 15u);
    EXPECT_NEAR(measure(plate) / (0.001 * f.area), 1.0, 1e-12);
    for (const auto& p : plate) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  }
  EXPECT_NE(describe(model).find("split into 15 conforming patches"), std::string::npos);
}

TEST(CadSplit, BracketExample) {
  // L section (two 6-edge faces: 3 rectangles each) with a hole across its long leg (two faces
  // with a hole): every face is analysable, and the solid is a block with a through-hole (7
  // volume patches: 3 boxes and the ring of 4 along the hole).
  const CadModel model = read_cad(example("bracket.step"));
  EXPECT_EQ(check_all_faces(model), 4);
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_EQ(model.solid_notes[0], "");
  ASSERT_EQ(model.volume_patches.size(), 7u);
  const double exact = test::cad_test_parts()["bracket.step"].exact_volume;
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-12);
  EXPECT_NEAR(measure(model.volume_patches) / model.volume, 1.0, 1e-9);
  for (const auto& p : model.volume_patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  EXPECT_NEAR(test::unshared_face_area(model.volume_patches, 1e-12) / model.area, 1.0, 1e-9);
}

TEST(CadSplit, ExtrudedLSectionWithAHoleAlongItIsAPrism) {
  // L section (legs 50 x 10 and 10 x 60 mm) with a hole of radius 2 mm along the extrusion,
  // 40 mm deep: the L face is cut into 4 rectangles and a ring of 4, the solid is its prism.
  BRepBuilderAPI_MakePolygon outline;
  for (auto [x, y] :
       {std::pair{0.0, 0.0}, {0.05, 0.0}, {0.05, 0.01}, {0.01, 0.01}, {0.01, 0.06}, {0.0, 0.06}})
    outline.Add(gp_Pnt(x, y, 0));
  outline.Close();
  BRepBuilderAPI_MakeFace face(outline.Wire(), true);
  face.Add(TopoDS::Wire(
      BRepBuilderAPI_MakeWire(
          BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0.005, 0.035, 0), gp_Dir(0, 0, 1)), 0.002)))
          .Wire()
          .Reversed()));
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(face.Face(), gp_Vec(0, 0, 0.04)).Shape();
  const CadModel model = test::step_round_trip(prism, "l_section_with_hole.step");
  EXPECT_EQ(check_all_faces(model), 2);
  ASSERT_EQ(model.solid_notes.size(), 1u);
  EXPECT_EQ(model.solid_notes[0], "");
  EXPECT_EQ(model.volume_patches.size(), 8u);
  const double exact = (0.05 * 0.01 + 0.01 * 0.05) * 0.04 - M_PI * 0.002 * 0.002 * 0.04;
  EXPECT_NEAR(measure(model.volume_patches) / model.volume, 1.0, 1e-9);
  EXPECT_NEAR(measure(model.volume_patches) / exact, 1.0, 1e-12);
  for (const auto& p : model.volume_patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  EXPECT_NEAR(test::unshared_face_area(model.volume_patches, 1e-12) / model.area, 1.0, 1e-9);
}

TEST(CadSplit, ThirdPartyParts) {
  const fs::path dir = fs::path(ISOSPRING_SHARED_DIR) / "cad";
  if (!fs::exists(dir / "plate_caxif.stp"))
    GTEST_SKIP() << "../shared/cad (third-party CAD parts) is not present";
  // CAx-IF plate 180 x 150 x 20 mm with 6 holes: both big faces cut, the solid a prism.
  const CadModel plate = read_cad(dir / "plate_caxif.stp");
  EXPECT_EQ(check_all_faces(plate), 2);
  EXPECT_EQ(plate.solid_notes[0], "");
  // The CAx-IF edges are degree-5 polynomial B-splines: the Jacobian of the extruded patches
  // is a polynomial of degree <= 9 per direction, integrated exactly by 8 Gauss points a span.
  const MeasureRule exact_for_degree_9{8, 1};
  EXPECT_NEAR(measure(plate.volume_patches, exact_for_degree_9) / plate.volume, 1.0, 1e-9);
  EXPECT_NEAR(plate.volume / 5.305752223e-04, 1.0, 1e-9);  // ../shared/cad/README.md
  // CAx-IF L-bracket: 4 faces with holes and 2 L-shaped faces cut; the solid is a block with
  // one hole through one leg and three through the other (57 volume patches). Two of its holes
  // have degree-5 polynomial edges at one end (4.6e-6 short of the circle's area) and exact arcs
  // at the other: the holes are built from their cylinders, so the volume is the drawing's
  // exactly, and OpenCascade's differs by 1.7e-8, within the ends' disagreement (7.7e-8).
  const CadModel bracket = read_cad(dir / "l_bracket_caxif.stp");
  EXPECT_EQ(check_all_faces(bracket), 6);
  EXPECT_NEAR(bracket.area / 2.462831929e-02, 1.0, 1e-9);
  EXPECT_EQ(bracket.solid_notes[0], "");
  EXPECT_EQ(bracket.volume_patches.size(), 57u);
  const double drawing = (0.06 * 0.01 + 0.04 * 0.01) * 0.1 - 4 * M_PI * 25e-6 * 0.01;
  EXPECT_NEAR(measure(bracket.volume_patches) / drawing, 1.0, 1e-12);
  EXPECT_NEAR(measure(bracket.volume_patches) / bracket.volume, 1.0, 2e-8);
  EXPECT_NE(bracket.solid_remarks[0].find("within the 7.66e-08 by which the file's holes "
                                          "disagree between their two ends"),
            std::string::npos)
      << bracket.solid_remarks[0];
  for (const auto& p : bracket.volume_patches) EXPECT_GT(jacobian_range(p, 4).min, 0.0);
  // Conforming: the unshared faces are the part's surface, to the file's edge fits.
  EXPECT_NEAR(test::unshared_face_area(bracket.volume_patches, 1e-12) / bracket.area, 1.0, 1e-7);
  // CadQuery cube + cylinder: the cylinder's disks are 5 patches each; both bodies volumes.
  const CadModel cubes = read_cad(dir / "cube_cylinder_cadquery.step");
  EXPECT_EQ(check_all_faces(cubes), 2);
  for (const auto& note : cubes.solid_notes) EXPECT_EQ(note, "");
  EXPECT_NEAR(measure(cubes.volume_patches) / cubes.volume, 1.0, 1e-9);
}

TEST(CadSplit, FaceThatCannotBeCutIsNamed) {
  // A triangle with a hole: slanted outline edges around a hole are not cut.
  BRepBuilderAPI_MakePolygon outline(gp_Pnt(0, 0, 0), gp_Pnt(0.04, 0, 0), gp_Pnt(0, 0.04, 0), true);
  BRepBuilderAPI_MakeFace face(outline.Wire(), true);
  const TopoDS_Edge circle =
      BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0.01, 0.01, 0), gp_Dir(0, 0, 1)), 0.003));
  face.Add(TopoDS::Wire(BRepBuilderAPI_MakeWire(circle).Wire().Reversed()));
  const CadModel model = test::step_round_trip(face.Face(), "triangle_with_hole.step");
  ASSERT_EQ(model.faces, 1);
  EXPECT_EQ(model.face_reports[0].split, 0);
  EXPECT_NE(model.face_reports[0].note.find("cannot be cut into 4-sided patches: the outline has "
                                            "a slanted edge"),
            std::string::npos)
      << model.face_reports[0].note;
  try {
    cad_patches(model);
    FAIL() << "the triangle with a hole must be refused";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle_with_hole.step: face 0 (plane) cannot be "
                                         "analysed"),
              std::string::npos)
        << e.what();
  }
}

// `import` writes the cut patches with a report of per-patch Jacobian bounds and the volume
// check against OpenCascade; `info --json` says for every face how it will be analysed.
TEST(CadSplit, ImportReportAndInfo) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const testing::TemporaryFolder folder;
  const fs::path out = folder.path() / "plate.json";
  const auto result = testing::run_isospring("import " + example("plate_with_holes.step").string() +
                                             " -o " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(io::read_patch_file(out).size(), 15u);
  std::ifstream in(out.string() + ".report.json");
  const auto report = nlohmann::json::parse(in);
  EXPECT_EQ(report["patch_count"], 15);
  EXPECT_LT(std::abs(report["measure_relative_error"].get<double>()), 1e-9);
  ASSERT_EQ(report["patches"].size(), 15u);
  for (const auto& p : report["patches"]) EXPECT_GT(p["jacobian_min"].get<double>(), 0.0);
  int split = 0;
  for (const auto& f : report["faces"]) split += f["split_patches"].get<int>() > 0;
  EXPECT_EQ(split, 2);

  const auto info = testing::run_isospring("info --json " + example("bracket.step").string());
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  std::map<std::string, int> kinds;
  for (const auto& f : j["cad"]["face_analysis"]) kinds[f["analysis"].get<std::string>()] += 1;
  EXPECT_EQ(kinds["split"], 4);  // two L sections (3 rectangles), two faces with the hole (5)
  EXPECT_EQ(kinds["exact patch"] + kinds["Coons patch"], 5);
  EXPECT_EQ(kinds["not supported"], 0);
  EXPECT_EQ(j["cad"]["usable_faces"], 9);
}

// Patch test on the imported plate (15 prism volumes): pressure p on its whole surface (hole
// walls included) and rollers on x = 0, y = 0, z = 0 give the uniform stress -p I, i.e. the
// linear displacement u = -p (1 - 2 nu) / E x, which conforming exact patches reproduce up to
// quadrature (10 Gauss points: round-off; the default 3 leaves 2e-5 on the rational patches).
// The patch test through `analyze` on an imported part's volume patches: pressure p on its whole
// surface (hole walls included) with rollers on the faces in x = 0, y = 0 and z = 0 gives the
// uniform stress -p I, i.e. u = -eps x with eps = p (1 - 2 nu) / E, reproduced exactly by the
// isoparametric patches when their interfaces are glued; the strain energy is 3/2 p eps V.
// Returns the number of roller and pressure sides.
std::pair<size_t, size_t> expect_patch_test(const std::string& part, double exact_volume) {
  const CadModel model = read_cad(example(part));
  const std::vector<nurbs::Patch> volumes = cad_patches(model);
  // Boundary sides: those no other patch has (same control points, any order).
  struct Side {
    int patch, dir, end;
    std::vector<std::array<double, 3>> points;
  };
  std::vector<Side> sides;
  double farthest = 0.0;  // the largest |x| of a control point: where |u| is largest
  for (int p = 0; p < static_cast<int>(volumes.size()); ++p) {
    for (const auto& x : volumes[static_cast<size_t>(p)].control_points())
      farthest = std::max(farthest, x.norm());
    for (int dir = 0; dir < 3; ++dir)
      for (int end = 0; end < 2; ++end) {
        const nurbs::Patch face = boundary_side(volumes[static_cast<size_t>(p)], dir, end);
        Side side{p, dir, end, {}};
        for (const auto& x : face.control_points()) side.points.push_back({x.x(), x.y(), x.z()});
        std::sort(side.points.begin(), side.points.end());
        sides.push_back(side);
      }
  }
  auto same = [](const Side& a, const Side& b) {
    if (a.points.size() != b.points.size()) return false;
    for (size_t i = 0; i < a.points.size(); ++i)
      for (int c = 0; c < 3; ++c)
        if (std::abs(a.points[i][static_cast<size_t>(c)] - b.points[i][static_cast<size_t>(c)]) >
            1e-12)
          return false;
    return true;
  };
  const double pressure = 1e6, E = 2e11, nu = 0.3;
  nlohmann::json boundary = nlohmann::json::array(), pressures = nlohmann::json::array();
  for (const Side& side : sides) {
    if (std::any_of(sides.begin(), sides.end(),
                    [&](const Side& o) { return o.patch != side.patch && same(side, o); }))
      continue;
    const std::string name = std::string(1, "uvw"[side.dir]) + (side.end ? "1" : "0");
    bool roller = false;
    for (int axis = 0; axis < 3; ++axis)
      if (std::all_of(side.points.begin(), side.points.end(), [&](const auto& x) {
            return std::abs(x[static_cast<size_t>(axis)]) < 1e-12;
          })) {
        boundary.push_back(
            {{"side", name}, {"patch", side.patch}, {"fix", {std::string(1, "xyz"[axis])}}});
        roller = true;
      }
    if (!roller) pressures.push_back({{"side", name}, {"patch", side.patch}, {"value", pressure}});
  }
  const testing::TemporaryFolder folder;
  const fs::path& dir = folder.path();
  fs::copy_file(example(part), dir / part);
  const nlohmann::json kase = {{"schema_version", 1},
                               {"name", "patch_test"},
                               {"geometry", {{"type", "cad"}, {"file", part}}},
                               {"analysis", {{"quadrature_points", 10}}},
                               {"material", {{"E", E}, {"nu", nu}}},
                               {"boundary", boundary},
                               {"load_cases", {{{"id", "pressure"}, {"pressures", pressures}}}}};
  std::ofstream(dir / "case.json") << kase.dump(2);
  const auto result = testing::run_isospring("analyze " + (dir / "case.json").string() + " -o " +
                                             (dir / "out").string() + " --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir / "out" / "report.json");
  const auto report = nlohmann::json::parse(in)["load_cases"][0];
  const double strain = pressure * (1 - 2 * nu) / E;
  EXPECT_NEAR(report["max_displacement"].get<double>() / (strain * farthest), 1.0, 1e-11) << part;
  EXPECT_NEAR(report["strain_energy"].get<double>() / (1.5 * pressure * strain * exact_volume), 1.0,
              1e-11)
      << part;
  return {boundary.size(), pressures.size()};
}

TEST(CadSplit, ImportedPlatePrismPassesThePatchTest) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const auto [rollers, loaded] = expect_patch_test(
      "plate_with_holes.step", test::cad_test_parts()["plate_with_holes.step"].exact_volume);
  EXPECT_EQ(rollers, 21u);  // x = 0: 3, y = 0: 3 (each 1 side), z = 0: 15
  EXPECT_EQ(loaded, 29u);   // x = 0.18: 3, y = 0.15: 3, z = 0.02: 15, 2 holes: 8
}

// The bracket's 7 block patches (3 boxes, a ring of 4 through the long leg) are glued into one
// body: the patch test holds to round-off.
TEST(CadSplit, ImportedBracketBlockPassesThePatchTest) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const auto [rollers, loaded] =
      expect_patch_test("bracket.step", test::cad_test_parts()["bracket.step"].exact_volume);
  // 42 sides, 7 interfaces (corner box - each leg box, leg box - ring, 4 within the ring):
  // 28 on the surface. Rollers: x = 0: 2 boxes + the 4 ring patches, y = 0: 2 boxes, z = 0:
  // 3 boxes + the ring's lower patch (its square reaches the bottom).
  EXPECT_EQ(rollers, 12u);
  EXPECT_EQ(loaded, 16u);
}

// The Kirsch plate (square [-4, 4]^2, hole of radius 1, plane stress) made in OpenCascade,
// written as STEP, imported (4 ring patches) and analysed by `isospring study`: exact
// displacement on two outer sides, exact traction on the other two. Optimal rates for p = 2
// are L2 O(h^3), energy O(h^2).
TEST(CadSplit, ImportedKirschPlateConvergesOptimally) {
  if (!fs::exists(ISOSPRING_EXECUTABLE)) GTEST_SKIP() << "build the isospring program first";
  const testing::TemporaryFolder folder;
  const fs::path& dir = folder.path();
  BRepBuilderAPI_MakePolygon square(gp_Pnt(-4, -4, 0), gp_Pnt(4, -4, 0), gp_Pnt(4, 4, 0),
                                    gp_Pnt(-4, 4, 0), true);
  BRepBuilderAPI_MakeFace face(square.Wire(), true);
  face.Add(TopoDS::Wire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Circ(
                                                    gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 1.0)))
                            .Wire()
                            .Reversed()));
  const CadModel model = test::step_round_trip(face.Face(), "kirsch_plate.step");
  ASSERT_EQ(model.face_reports[0].split, 4) << model.face_reports[0].note;
  const auto patches = cad_patches(model);
  // Closed form to the accuracy of measure()'s Gauss rule on these rational patches.
  EXPECT_NEAR(measure(patches) / (64 - M_PI), 1.0, 1e-10);
  EXPECT_NEAR(measure(patches) / model.area, 1.0, 1e-10);
  fs::copy_file(model.file, dir / "kirsch_plate.step");
  // Every patch: u along the hole, v outward (v1 on the square); elements must divide evenly.
  int spans = 1;
  for (const auto& p : patches) spans = std::lcm(spans, p.knots(0).num_elements());
  const int elements = 4 * spans;
  nlohmann::json boundary = nlohmann::json::array(), tractions = nlohmann::json::array();
  for (int p = 0; p < 4; ++p)
    if (p % 2 == 0)
      boundary.push_back({{"side", "v1"}, {"patch", p}, {"value", "analytic"}});
    else
      tractions.push_back({{"side", "v1"}, {"patch", p}, {"value", "analytic"}});
  const nlohmann::json kase = {
      {"schema_version", 1},
      {"name", "kirsch_from_step"},
      {"geometry", {{"type", "cad"}, {"file", "kirsch_plate.step"}}},
      {"discretization", {{"degree", 2}, {"elements", {elements, elements}}}},
      {"analysis", {{"type", "plane_stress"}, {"thickness", 1.0}}},
      {"material", {{"E", 1e5}, {"nu", 0.3}}},
      {"analytic", {{"type", "kirsch"}, {"traction", 10.0}, {"radius", 1.0}}},
      {"boundary", boundary},
      {"load_cases", {{{"id", "tension"}, {"tractions", tractions}}}}};
  std::ofstream(dir / "case.json") << kase.dump(2);
  const auto start = std::chrono::steady_clock::now();
  const auto result =
      testing::run_isospring("study " + (dir / "case.json").string() + " -o " +
                             (dir / "study").string() + " --levels 4 --degrees 2 --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir / "study" / "report.json");
  const auto report = nlohmann::json::parse(in);
  const auto& levels = report["degrees"][0]["levels"];
  ASSERT_EQ(levels.size(), 4u);
  for (size_t l = 0; l < levels.size(); ++l)
    std::printf("level %zu: dofs %d, L2 %.3e (rate %s), energy %s (rate %s)\n", l,
                levels[l]["dofs"].get<int>(), levels[l]["relative_l2_error"].get<double>(),
                levels[l]["rate"].dump().c_str(), levels[l]["relative_energy_error"].dump().c_str(),
                levels[l]["energy_rate"].dump().c_str());
  std::printf("study time %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  for (size_t l = 1; l < levels.size(); ++l)
    EXPECT_LT(levels[l]["relative_l2_error"].get<double>(),
              levels[l - 1]["relative_l2_error"].get<double>());
  EXPECT_GE(levels[3]["rate"].get<double>(), 2.8);
  EXPECT_GE(levels[3]["energy_rate"].get<double>(), 1.9);
}

}  // namespace
}  // namespace isospring::geometry
