// Patches to STEP/IGES: B-spline faces (volumes as their boundary faces), in metres.
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRepLib.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <algorithm>
#include <cctype>
#include <cmath>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/nurbs/error.hpp"
#include "occt_conversion.hpp"
#include "occt_silence.hpp"

namespace isospring::geometry {

nurbs::Patch boundary_side(const nurbs::Patch& patch, int dir, int end) {
  if (patch.param_dim() < 2 || dir < 0 || dir >= patch.param_dim())
    throw std::invalid_argument("boundary_side: needs a surface or volume and a valid direction");
  std::vector<nurbs::KnotVector> knots;
  for (int d = 0; d < patch.param_dim(); ++d)
    if (d != dir) knots.push_back(patch.knots(d));
  const int layer = end == 0 ? 0 : patch.num_points(dir) - 1;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  // Net order is preserved (first remaining direction fastest).
  for (int a = 0; a < patch.num_points(); ++a)
    if (patch.net_position(a)[static_cast<size_t>(dir)] == layer) {
      points.push_back(patch.control_point(a));
      weights.push_back(patch.weight(a));
    }
  return nurbs::Patch(knots, points, weights);
}

namespace {

TopoDS_Face occt_face(const nurbs::Patch& surface) {
  BRepBuilderAPI_MakeFace face(detail::occt_from_patch(surface), 1e-9);
  if (!face.IsDone()) throw std::runtime_error("OpenCascade could not build a face");
  return face.Face();
}

// The six sides of a volume with outward normals (the min side of a right-handed volume is
// reversed).
std::vector<nurbs::Patch> volume_sides(const nurbs::Patch& patch) {
  std::vector<nurbs::Patch> sides;
  for (int dir = 0; dir < 3; ++dir)
    for (int end = 0; end < 2; ++end) {
      const nurbs::Patch side = boundary_side(patch, dir, end);
      sides.push_back((end == 0) == (dir != 1) ? reverse_direction(side, 0) : side);
    }
  return sides;
}

// A volume patch as a closed solid: its sides sewn into one shell (the sides share their
// boundary curves exactly, up to round-off, so the sewing tolerance only has to absorb that),
// made a solid and oriented so that its volume is positive. Empty with `why` set when the sewing
// does not give one closed shell.
TopoDS_Solid volume_solid(const nurbs::Patch& patch, std::string& why) {
  Eigen::Vector3d lo = patch.control_point(0), hi = lo;
  for (int a = 0; a < patch.num_points(); ++a) {
    lo = lo.cwiseMin(patch.control_point(a));
    hi = hi.cwiseMax(patch.control_point(a));
  }
  const double tolerance = std::max(1e-7, 1e-7 * (hi - lo).norm());
  BRepBuilderAPI_Sewing sewing(tolerance);
  for (const auto& side : volume_sides(patch)) sewing.Add(occt_face(side));
  sewing.Perform();
  const TopoDS_Shape sewn = sewing.SewedShape();
  std::vector<TopoDS_Shell> shells;
  for (TopExp_Explorer e(sewn, TopAbs_SHELL); e.More(); e.Next())
    shells.push_back(TopoDS::Shell(e.Current()));
  if (shells.size() != 1) {
    why = "sewing its six sides gave " + std::to_string(shells.size()) + " shells, not one";
    return {};
  }
  if (sewing.NbFreeEdges() > 0 || !BRep_Tool::IsClosed(shells.front())) {
    why = "sewing its six sides left " + std::to_string(sewing.NbFreeEdges()) +
          " free edge(s) (a collapsed or non-matching side)";
    return {};
  }
  BRepBuilderAPI_MakeSolid make(shells.front());
  if (!make.IsDone()) {
    why = "OpenCascade could not make a solid of its closed shell";
    return {};
  }
  TopoDS_Solid solid = make.Solid();
  BRepLib::OrientClosedSolid(solid);
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  if (!(props.Mass() > 0.0)) {
    why = "its solid has no positive volume";
    return {};
  }
  return solid;
}

}  // namespace

CadWriteSummary write_cad(const std::filesystem::path& file,
                          const std::vector<nurbs::Patch>& patches) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool step = ext == ".step" || ext == ".stp", iges = ext == ".iges" || ext == ".igs";
  if (!step && !iges)
    throw nurbs::InputError(file.string() + ": unknown CAD extension '" + ext +
                            "'; use .step, .stp, .iges or .igs");
  for (const auto& patch : patches)
    if (patch.param_dim() != 2 && patch.param_dim() != 3)
      throw nurbs::InputError(file.string() + ": curves cannot be written as CAD faces");
  CadWriteSummary summary;
  try {
    BRep_Builder builder;
    TopoDS_Compound compound;
    builder.MakeCompound(compound);
    for (size_t p = 0; p < patches.size(); ++p) {
      const nurbs::Patch& patch = patches[p];
      if (patch.param_dim() == 2) {
        builder.Add(compound, occt_face(patch));
        ++summary.faces;
        continue;
      }
      summary.faces += 6;
      std::string why;
      const TopoDS_Solid solid = volume_solid(patch, why);
      if (!solid.IsNull()) {
        builder.Add(compound, solid);
        ++summary.solids;
      } else {
        summary.notes.push_back("volume patch " + std::to_string(p) +
                                " written as 6 faces, not a solid: " + why);
        for (const auto& side : volume_sides(patch)) builder.Add(compound, occt_face(side));
      }
    }
    const detail::SilenceOpenCascade silence;  // the writers' statistics would go to stdout
    STEPControl_Controller::Init();            // the unit statics exist only after initialisation
    IGESControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", "M");
    // Written next to the target and renamed when complete (atomic on one file system): a failed
    // or interrupted export never leaves a truncated part where the user expects a good one.
    // (io/atomic_file.hpp cannot be used here: io comes after geometry in the module order.)
    const std::filesystem::path temporary =
        file.parent_path() / ("." + file.filename().string() + ".isospring-tmp" + ext);
    const std::string name = temporary.string();
    struct RemoveOnFailure {
      const std::filesystem::path& path;
      bool keep = false;
      ~RemoveOnFailure() {
        std::error_code ignored;
        if (!keep) std::filesystem::remove(path, ignored);
      }
    } cleanup{temporary};
    if (step) {
      Interface_Static::SetCVal("write.step.unit", "M");  // before the writer builds its model
      STEPControl_Writer writer;
      if (writer.Transfer(compound, STEPControl_AsIs) != IFSelect_RetDone ||
          writer.Write(name.c_str()) != IFSelect_RetDone)
        throw std::runtime_error("OpenCascade could not write " + name);
    } else {
      // Mode 1 (B-rep): solids as manifold solid B-rep objects (186) with shared edges, faces
      // as B-rep faces (510); mode 0 would write every face as a separate trimmed surface (144)
      // and lose the solid.
      IGESControl_Writer writer("M", summary.solids > 0 ? 1 : 0);
      // The writer divides shape coordinates by GlobalSection::UnitValue(), the file unit in
      // "cascade" units. OCCT 7.6 sets the model's cascade unit from its process-wide default
      // (millimetres), not from xstep.cascade.unit, so without this a 0.1 m edge is written as
      // 1e-4 under the unit flag M. Our shapes are in metres: 1000 mm per cascade unit.
      IGESData_GlobalSection section = writer.Model()->GlobalSection();
      section.SetCascadeUnit(1000.0);
      writer.Model()->SetGlobalSection(section);
      if (std::abs(writer.Model()->GlobalSection().UnitValue() - 1.0) > 1e-15)
        throw std::runtime_error("OpenCascade IGES writer: file unit is not the shape unit (m)");
      writer.AddShape(compound);
      writer.ComputeModel();
      if (!writer.Write(name.c_str()))
        throw std::runtime_error("OpenCascade could not write " + name);
    }
    std::error_code error;
    std::filesystem::rename(temporary, file, error);
    if (error)
      throw std::runtime_error(file.string() + ": cannot move the written part into place (" +
                               error.message() + ")");
    cleanup.keep = true;
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(file.string() + ": OpenCascade failed: " + e.GetMessageString());
  }
  return summary;
}

}  // namespace isospring::geometry
