// Face selectors of immersed supports and loads (geometry/cad_face_selection.hpp and the case
// file's "face" field, io/immersed_case.hpp) on a part built with OpenCascade and saved as STEP
// with named faces: a 40 x 20 x 10 mm block with a through-hole of radius 4 mm along z at
// (10, 10) mm. Every selection is checked against the face's closed-form area (the selected face
// is the intended one, not just some face) and against OpenCascade's own centroid.
#include <gtest/gtest.h>
#include <unistd.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <GProp_GProps.hxx>
#include <Interface_Static.hxx>
#include <STEPConstruct.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <Transfer_FinderProcess.hxx>
#include <XSControl_TransferWriter.hxx>
#include <XSControl_WorkSession.hxx>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "isospring/geometry/cad_face_selection.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"

namespace fs = std::filesystem;
using isospring::nurbs::InputError;

namespace isospring::geometry {
namespace {

constexpr double kA = 0.04, kB = 0.02, kC = 0.01, kR = 0.004;  // block and hole (m)

fs::path temp_dir() {
  const fs::path dir =
      fs::temp_directory_path() / ("isospring_test_face_selection-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// The block with its hole, the face at x = 0 named "clamp" and the one at x = kA "load_end".
fs::path holed_block() {
  static fs::path file;
  if (!file.empty()) return file;
  const TopoDS_Shape part = BRepAlgoAPI_Cut(
      BRepPrimAPI_MakeBox(kA, kB, kC).Shape(),
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.01, 0.01, -0.001), gp_Dir(0, 0, 1)), kR, kC + 0.002)
          .Shape());
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  EXPECT_EQ(writer.Transfer(part, STEPControl_AsIs), IFSelect_RetDone);
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(part, TopAbs_FACE, faces);
  for (int f = 1; f <= faces.Extent(); ++f) {
    GProp_GProps props;
    BRepGProp::SurfaceProperties(faces(f), props);
    const double x = props.CentreOfMass().X();
    const char* name = std::abs(x) < 1e-12 ? "clamp" : std::abs(x - kA) < 1e-12 ? "load_end" : "";
    if (!*name) continue;
    const Handle(StepRepr_RepresentationItem) item =
        STEPConstruct::FindEntity(writer.WS()->TransferWriter()->FinderProcess(), faces(f));
    EXPECT_FALSE(item.IsNull());
    item->SetName(new TCollection_HAsciiString(name));
  }
  file = temp_dir() / "holed_block.step";
  EXPECT_EQ(writer.Write(file.string().c_str()), IFSelect_RetDone);
  return file;
}

const std::vector<SolidFace>& faces() {
  static const std::vector<SolidFace> list = solid_faces(read_cad_solid(holed_block()));
  return list;
}

const SolidFace& face(int index) {
  for (const SolidFace& f : faces())
    if (f.index == index) return f;
  throw std::runtime_error("no face " + std::to_string(index));
}

FaceSelector plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  FaceSelector s;
  s.kind = FaceSelector::Kind::kPlane;
  s.point = point;
  s.direction = normal;
  return s;
}

TEST(FaceSelection, TheFacesAreDescribed) {
  ASSERT_EQ(faces().size(), 7u);  // six planes and the hole
  double area = 0;
  int planes = 0, cylinders = 0;
  for (const SolidFace& f : faces()) {
    area += f.area;
    planes += f.surface_type == "plane";
    cylinders += f.surface_type == "cylinder";
    EXPECT_GT(f.samples.size(), 20u) << "face " << f.index;
    if (f.surface_type == "plane") {  // the outward normal: from the centroid out of the block
      EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
      const Eigen::Vector3d centre(kA / 2, kB / 2, kC / 2);
      EXPECT_GT(f.normal.dot(f.centroid - centre), 0) << "face " << f.index;
    }
  }
  EXPECT_EQ(planes, 6);
  EXPECT_EQ(cylinders, 1);
  const double closed_form =
      2 * (kA * kB + kB * kC + kC * kA) - 2 * M_PI * kR * kR + 2 * M_PI * kR * kC;
  EXPECT_NEAR(area, closed_form, 1e-9 * closed_form);
}

TEST(FaceSelection, PlaneSelectsTheFacesInIt) {
  const std::vector<int> x0 = select_faces(faces(), plane({0, 0.005, 0.002}, {-2, 0, 0}));
  ASSERT_EQ(x0.size(), 1u);
  EXPECT_NEAR(face(x0[0]).area, kB * kC, 1e-12);
  EXPECT_NEAR(face(x0[0]).normal.x(), -1.0, 1e-12);
  // The top face, with the hole in it.
  const std::vector<int> top = select_faces(faces(), plane({0.03, 0.01, kC}, {0, 0, 1}));
  ASSERT_EQ(top.size(), 1u);
  EXPECT_NEAR(face(top[0]).area, kA * kB - M_PI * kR * kR, 1e-12);
  // The plane through the hole's axis cuts faces but contains none.
  EXPECT_TRUE(select_faces(faces(), plane({0.01, 0.01, 0}, {0, 1, 0})).empty());
  // A plane 2 micrometres off: outside the default 1e-6 m, inside a tolerance of 3e-6 m.
  FaceSelector off = plane({kA + 2e-6, 0, 0}, {1, 0, 0});
  EXPECT_TRUE(select_faces(faces(), off).empty());
  off.tolerance = 3e-6;
  EXPECT_EQ(select_faces(faces(), off).size(), 1u);
}

TEST(FaceSelection, BoxSelectsTheFacesInsideIt) {
  FaceSelector s;
  s.kind = FaceSelector::Kind::kBox;
  s.box_min = {0.03, -1, -1};
  s.box_max = {1, 1, 1};
  const std::vector<int> end = select_faces(faces(), s);  // only the end face lies wholly inside
  ASSERT_EQ(end.size(), 1u);
  EXPECT_NEAR(face(end[0]).centroid.x(), kA, 1e-12);
  s.box_min = {-1, -1, -1};
  EXPECT_EQ(select_faces(faces(), s).size(), 7u);
  // Around the hole only: its wall, not the top and bottom faces it pierces.
  s.box_min = {0.01 - kR, 0.01 - kR, 0};
  s.box_max = {0.01 + kR, 0.01 + kR, kC};
  const std::vector<int> hole = select_faces(faces(), s);
  ASSERT_EQ(hole.size(), 1u);
  EXPECT_EQ(face(hole[0]).surface_type, "cylinder");
}

TEST(FaceSelection, CylinderSelectsTheHole) {
  FaceSelector s;
  s.kind = FaceSelector::Kind::kCylinder;
  s.point = {0.01, 0.01, 0.5};  // any point of the axis
  s.direction = {0, 0, -3};
  s.radius = kR;
  const std::vector<int> hole = select_faces(faces(), s);
  ASSERT_EQ(hole.size(), 1u);
  EXPECT_NEAR(face(hole[0]).area, 2 * M_PI * kR * kC, 1e-12);
  EXPECT_NEAR(face(hole[0]).radius, kR, 1e-15);
  s.radius = kR + 1e-5;  // 10 micrometres larger: no face
  EXPECT_TRUE(select_faces(faces(), s).empty());
  s.tolerance = 2e-5;
  EXPECT_EQ(select_faces(faces(), s), hole);
}

TEST(FaceSelection, NameSelectsTheStepFace) {
  FaceSelector s;
  s.kind = FaceSelector::Kind::kName;
  s.name = "clamp";
  const std::vector<int> clamp = select_faces(faces(), s);
  ASSERT_EQ(clamp.size(), 1u);
  EXPECT_EQ(clamp, select_faces(faces(), plane({0, 0, 0}, {1, 0, 0})));
  s.name = "load_end";
  EXPECT_EQ(select_faces(faces(), s), select_faces(faces(), plane({kA, 0, 0}, {1, 0, 0})));
  s.name = "Clamp";  // names are exact
  EXPECT_TRUE(select_faces(faces(), s).empty());
}

TEST(FaceSelection, BadSelectorsAreRefused) {
  EXPECT_THROW(select_faces(faces(), plane({0, 0, 0}, {0, 0, 0})), InputError);
  FaceSelector s = plane({0, 0, 0}, {1, 0, 0});
  s.tolerance = -1;
  EXPECT_THROW(select_faces(faces(), s), InputError);
  s = FaceSelector();
  s.kind = FaceSelector::Kind::kBox;
  s.box_min = {1, 0, 0};
  EXPECT_THROW(select_faces(faces(), s), InputError);
}

// The case file: a selector becomes the faces it matches, one that matches none names the field.
nlohmann::json case_with(const nlohmann::json& support_face, const nlohmann::json& load_face) {
  return {
      {"geometry", {{"type", "immersed"}, {"file", holed_block().filename().string()}}},
      {"material", {{"E", 2e11}, {"nu", 0.3}}},
      {"boundary", {{{"face", support_face}, {"fix", {"x", "y", "z"}}}}},
      {"load_cases", {{{"id", "pull"}, {"pressures", {{{"face", load_face}, {"value", -1e6}}}}}}}};
}

TEST(FaceSelection, CaseFileSelectorsBecomeFaces) {
  const fs::path case_file = holed_block().parent_path() / "case.json";
  const nlohmann::json c =
      case_with({{"name", "clamp"}},
                {{"box", {{"min", {-1, -1, -1}}, {"max", {1, 1, 1}}}}, {"tolerance", 0}});
  const io::ImmersedCase read = io::build_immersed_case(c, case_file);
  ASSERT_EQ(read.supports.size(), 1u);
  EXPECT_EQ(read.supports[0].face, select_faces(faces(), plane({0, 0, 0}, {1, 0, 0}))[0]);
  EXPECT_EQ(read.load_cases[0].pressures.size(), 7u);  // every face
  const io::ImmersedCase by_cylinder = io::build_immersed_case(
      case_with({{"cylinder", {{"point", {0.01, 0.01, 0}}, {"axis", {0, 0, 1}}, {"radius", kR}}}},
                {{"plane", {{"point", {kA, 0, 0}}, {"normal", {1, 0, 0}}}}}),
      case_file);
  EXPECT_EQ(face(by_cylinder.supports[0].face).surface_type, "cylinder");
  EXPECT_NEAR(face(by_cylinder.load_cases[0].pressures[0].face).centroid.x(), kA, 1e-12);
}

void expect_refused(const nlohmann::json& c, const std::vector<std::string>& words) {
  try {
    io::build_immersed_case(c, holed_block().parent_path() / "case.json");
    FAIL() << "accepted " << c.dump();
  } catch (const InputError& e) {
    for (const std::string& w : words)
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
}

TEST(FaceSelection, CaseFileSelectorThatMatchesNothingIsNamed) {
  expect_refused(case_with({{"plane", {{"point", {0.5, 0, 0}}, {"normal", {1, 0, 0}}}}}, 0),
                 {"case.json: boundary[0].face", "matches none", "tolerance", "face index"});
  expect_refused(case_with(0, {{"name", "top"}}),
                 {"load_cases[0].pressures[0].face", "'clamp', 'load_end'"});
  expect_refused(case_with({{"plane", {{"point", {0, 0, 0}}, {"normal", {0, 0, 0}}}}}, 0),
                 {"boundary[0].face.plane.normal", "zero"});
  expect_refused(
      case_with({{"plane", {{"point", {0, 0, 0}}, {"normal", {1, 0, 0}}}}, {"name", "clamp"}}, 0),
      {"boundary[0].face", "exactly one"});
  expect_refused(case_with({{"sphere", 1}}, 0), {"boundary[0].face", "sphere"});
}

// "grading" in the case file: the planes of grading_towards_face for that face.
TEST(FaceSelection, CaseFileGradingGradesTowardsTheFace) {
  const int clamp = select_faces(faces(), plane({0, 0, 0}, {1, 0, 0}))[0];
  nlohmann::json c = case_with(clamp, 0);
  c["geometry"]["grading"] = {{"face", clamp}, {"smallest", 0.002}, {"ratio", 1.4}};
  const io::ImmersedCase read =
      io::build_immersed_case(c, holed_block().parent_path() / "case.json");
  const std::vector<GradingPlane> expected =
      grading_towards_face(read_cad_solid(holed_block()), clamp, 0.002, 1.4);
  ASSERT_EQ(read.immersion.grading.size(), 5u);  // x = 0; y = 0, kB; z = 0, kC
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(read.immersion.grading[i].axis, expected[i].axis);
    EXPECT_EQ(read.immersion.grading[i].at, expected[i].at);
    EXPECT_EQ(read.immersion.grading[i].smallest, 0.002);
    EXPECT_EQ(read.immersion.grading[i].ratio, 1.4);
  }
  c["geometry"]["grading"] = {{"face", 99}, {"smallest", 0.002}};
  expect_refused(c, {"geometry.grading.face"});
  c["geometry"]["grading"] = {{"face", clamp}, {"smallest", 0.002}, {"ratio", 0.5}};
  expect_refused(c, {"geometry.grading.ratio"});
}

// A list of grading items (a face by selector, a plane by axis) and the planar faces kept on grid
// planes: the planes of each item in order and planar_face_coordinates as the breaks.
TEST(FaceSelection, CaseFileGradingListAndPlanarFaces) {
  nlohmann::json c = case_with(0, 0);
  c["geometry"]["grading"] = {{{"face", {{"name", "clamp"}}}, {"smallest", 0.002}},
                              {{"plane", {{"axis", "y"}, {"at", 0.013}}}, {"smallest", 0.001}}};
  c["geometry"]["keep_planar_faces"] = true;
  const io::ImmersedCase read =
      io::build_immersed_case(c, holed_block().parent_path() / "case.json");
  ASSERT_EQ(read.immersion.grading.size(), 6u);  // the clamp's 5 planes, then y = 0.013
  EXPECT_EQ(read.immersion.grading[0].axis, 0);
  EXPECT_EQ(read.immersion.grading[5].axis, 1);
  EXPECT_EQ(read.immersion.grading[5].at, 0.013);
  EXPECT_EQ(read.immersion.grading[5].smallest, 0.001);
  EXPECT_EQ(read.immersion.grading[5].ratio, 1.5);
  const std::array<std::vector<double>, 3> planar =
      planar_face_coordinates(read_cad_solid(holed_block()));
  EXPECT_EQ(read.immersion.breaks, planar);
  EXPECT_EQ(planar[0], (std::vector<double>{0.0, kA}));
  c["geometry"]["grading"] = {{{"plane", {{"axis", "w"}, {"at", 0.0}}}, {"smallest", 0.001}}};
  expect_refused(c, {"geometry.grading[0].plane.axis", "'w'"});
  c["geometry"]["grading"] = {{{"smallest", 0.001}}};
  expect_refused(c, {"geometry.grading[0]", "\"face\" or \"plane\""});
}

}  // namespace
}  // namespace isospring::geometry
