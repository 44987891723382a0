// Builds examples/immersed/rounded_bracket.step, the non-block part of the immersed tour
// (docs/immersed-tour.md): an L-shaped bracket 60 x 30 mm, 8 mm thick, with a 20 mm high
// upright, a through-hole of radius 6 mm in its base, the base's outer vertical edges rounded
// (r 6 mm) and the inner corner of the L filleted (r 4 mm). `isospring import` refuses it as
// body-fitted volumes (fillets, a hole through a non-prismatic solid), so it takes the immersed
// path. Written with OpenCascade (BRepPrimAPI, BRepAlgoAPI, BRepFilletAPI) in metres; faces
// are named in the STEP file (ADVANCED_FACE names) so that a case can select them by name.
//
//   g++ -std=c++17 -O1 scripts/make_rounded_bracket.cpp -I/usr/include/opencascade \
//     -lTKernel -lTKMath -lTKBRep -lTKTopAlgo -lTKPrim -lTKBO -lTKFillet -lTKG3d -lTKGeomBase \
//     -lTKSTEP -lTKXSBase -lTKSTEPBase -lTKShHealing -o /tmp/make_rounded_bracket
//   /tmp/make_rounded_bracket examples/immersed/rounded_bracket.step
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Interface_Static.hxx>
#include <STEPConstruct.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TransferBRep_ShapeMapper.hxx>
#include <Transfer_FinderProcess.hxx>
#include <XSControl_TransferWriter.hxx>
#include <XSControl_WorkSession.hxx>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

// A vertical edge (along z) at (x, y), if the edge is one.
bool vertical_at(const TopoDS_Edge& edge, double x, double y) {
  TopoDS_Vertex a, b;
  TopExp::Vertices(edge, a, b);
  const gp_Pnt p = BRep_Tool::Pnt(a), q = BRep_Tool::Pnt(b);
  return std::abs(p.X() - x) < 1e-9 && std::abs(q.X() - x) < 1e-9 && std::abs(p.Y() - y) < 1e-9 &&
         std::abs(q.Y() - y) < 1e-9 && std::abs(p.Z() - q.Z()) > 1e-9;
}

// An edge along y at (x, z).
bool along_y_at(const TopoDS_Edge& edge, double x, double z) {
  TopoDS_Vertex a, b;
  TopExp::Vertices(edge, a, b);
  const gp_Pnt p = BRep_Tool::Pnt(a), q = BRep_Tool::Pnt(b);
  return std::abs(p.X() - x) < 1e-9 && std::abs(q.X() - x) < 1e-9 && std::abs(p.Z() - z) < 1e-9 &&
         std::abs(q.Z() - z) < 1e-9 && std::abs(p.Y() - q.Y()) > 1e-9;
}

// The name of a planar face from where it lies: the clamp face (x = 0 of the upright) and the
// loaded face (the base's far end, x = 60 mm); others unnamed.
std::string face_name(const TopoDS_Face& face) {
  GProp_GProps props;
  BRepGProp::SurfaceProperties(face, props);
  const gp_Pnt c = props.CentreOfMass();
  if (std::abs(c.X()) < 1e-9) return "clamp";
  if (std::abs(c.X() - 0.06) < 1e-9) return "load_end";
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_rounded_bracket OUT.step\n");
    return 2;
  }
  const double t = 0.008;  // thickness of base and upright
  // Base 60 x 30 x 8 mm, upright 8 x 30 x 28 mm at x = 0.
  TopoDS_Shape part = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeBox(0.06, 0.03, t).Shape(),
                                       BRepPrimAPI_MakeBox(t, 0.03, 0.028).Shape())
                          .Shape();
  ShapeUpgrade_UnifySameDomain unify(part);
  unify.Build();
  part = unify.Shape();
  {  // The base's two outer vertical edges at x = 60 mm, r 6 mm.
    BRepFilletAPI_MakeFillet fillet(part);
    for (TopExp_Explorer e(part, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(e.Current());
      if (vertical_at(edge, 0.06, 0.0) || vertical_at(edge, 0.06, 0.03)) fillet.Add(0.006, edge);
    }
    part = fillet.Shape();
  }
  {  // The inner corner of the L (the edge along y at x = t, z = t), r 4 mm.
    BRepFilletAPI_MakeFillet fillet(part);
    for (TopExp_Explorer e(part, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(e.Current());
      if (along_y_at(edge, t, t)) fillet.Add(0.004, edge);
    }
    part = fillet.Shape();
  }
  // A through-hole of radius 6 mm in the base at (38, 15) mm.
  part = BRepAlgoAPI_Cut(
             part, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.038, 0.015, -0.001), gp_Dir(0, 0, 1)),
                                            0.006, t + 0.002)
                       .Shape())
             .Shape();

  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");  // the shape is in metres
  Interface_Static::SetCVal("write.step.unit", "M");
  Interface_Static::SetCVal("write.step.schema", "AP214IS");
  STEPControl_Writer writer;
  if (writer.Transfer(part, STEPControl_AsIs) != IFSelect_RetDone) return 1;
  // Name the faces: the STEP entity written for each face carries the name.
  const Handle(Transfer_FinderProcess) process = writer.WS()->TransferWriter()->FinderProcess();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(part, TopAbs_FACE, faces);
  for (int f = 1; f <= faces.Extent(); ++f) {
    const std::string name = face_name(TopoDS::Face(faces(f)));
    if (name.empty()) continue;
    const Handle(StepRepr_RepresentationItem) item = STEPConstruct::FindEntity(process, faces(f));
    if (!item.IsNull()) item->SetName(new TCollection_HAsciiString(name.c_str()));
  }
  if (writer.Write(argv[1]) != IFSelect_RetDone) return 1;
  std::printf("wrote %s: %d faces\n", argv[1], faces.Extent());
  return 0;
}
