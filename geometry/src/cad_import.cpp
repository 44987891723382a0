// STEP/IGES import through OpenCascade: faces to NURBS patches, hexahedral solids to volumes.
#include <BRepAdaptor_Surface.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "cad_face_recognisers.hpp"
#include "cad_pcurves.hpp"
#include "cad_reader.hpp"
#include "cad_solid_recognisers.hpp"
#include "crash_guard.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/conforming_sides.hpp"
#include "isospring/geometry/construction.hpp"
#include "isospring/nurbs/error.hpp"
#include "occt_box.hpp"
#include "occt_silence.hpp"
#include "step_entities.hpp"

namespace isospring::geometry {

namespace {

using nurbs::InputError;

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Entities OpenCascade could not read in a STEP file (`unreadable`, described) are harmless when
// none of them belongs to the geometry and the shape transferred and is valid: then a warning;
// otherwise the file is refused as corrupted.
void judge_unreadable_entities(const std::filesystem::path& file, bool outside_geometry,
                               const std::string& unreadable, const TopoDS_Shape& shape,
                               std::vector<std::string>& warnings) {
  const std::string name = file.string();
  const std::string corrupted = name + ": " + unreadable +
                                ": the file is corrupted (e.g. a misspelled entity name) or uses "
                                "entities OpenCascade does not support; export it again as STEP "
                                "AP203/AP214";
  if (!outside_geometry) throw InputError(corrupted);
  if (shape.IsNull()) throw InputError(corrupted + " (the shape did not transfer)");
  if (!BRepCheck_Analyzer(shape).IsValid())
    throw InputError(corrupted + " (the transferred shape is not valid)");
  warnings.push_back(name + ": " + unreadable +
                     ": skipped; they are outside the geometry (e.g. styles, validation "
                     "properties, units) and the shape transferred and is valid");
}

// Reads the file into one shape, in metres; returns the unit the file declares.
TopoDS_Shape read_shape_unguarded(const std::filesystem::path& file, std::string& file_unit,
                                  std::vector<std::string>& warnings) {
  const std::string name = file.string();
  if (!std::filesystem::exists(file))
    throw InputError(name + ": file not found; give the path of a .step/.stp/.iges/.igs file");
  if (std::filesystem::file_size(file) == 0)
    throw InputError(name + ": the file is empty; export the part again from the CAD program");
  const std::string ext = lower_extension(file);
  // OCCT converts coordinates to this unit whatever the file declares (default: millimetres).
  // The static exists only once the translators are initialised; setting it earlier is ignored.
  STEPControl_Controller::Init();
  IGESControl_Controller::Init();
  if (!Interface_Static::SetCVal("xstep.cascade.unit", "M") ||
      std::string(Interface_Static::CVal("xstep.cascade.unit")) != "M")
    throw std::runtime_error("OpenCascade refused xstep.cascade.unit = M");
  // The readers report progress ("Total number of loaded entities", transfer statistics) through
  // the default messenger, i.e. on stdout, which `info --json` and `--quiet` must keep clean.
  const detail::SilenceOpenCascade silence;
  TopoDS_Shape shape;
  if (ext == ".step" || ext == ".stp") {
    {  // A STEP file starts with ISO-10303-21; anything else is not worth handing to OCCT.
      std::ifstream in(file);
      std::string head(64, '\0');
      in.read(head.data(), 64);
      if (head.find("ISO-10303-21") == std::string::npos)
        throw InputError(name +
                         ": not a STEP file (no ISO-10303-21 header); export it as STEP "
                         "AP203/AP214 or use an .iges file");
    }
    STEPControl_Reader reader;
    if (reader.ReadFile(name.c_str()) != IFSelect_RetDone)
      throw InputError(name +
                       ": OpenCascade cannot parse this STEP file (truncated or invalid); "
                       "export it again");
    // Judged before the transfer when they touch the geometry: a transfer may dereference them.
    const std::string unreadable = detail::unreadable_step_entities(reader.Model());
    const bool outside_geometry =
        !unreadable.empty() && detail::unreadable_entities_outside_geometry(reader.Model(), file);
    if (!unreadable.empty() && !outside_geometry)
      judge_unreadable_entities(file, false, unreadable, TopoDS_Shape(), warnings);
    TColStd_SequenceOfAsciiString length, angle, solid_angle;
    reader.FileUnits(length, angle, solid_angle);
    file_unit = length.IsEmpty() ? "unknown" : length.First().ToCString();
    if (reader.NbRootsForTransfer() == 0)
      throw InputError(name +
                       ": the STEP file holds no transferable shapes (truncated or empty "
                       "model); export it again");
    reader.TransferRoots();
    shape = reader.OneShape();
    if (!unreadable.empty())
      judge_unreadable_entities(file, outside_geometry, unreadable, shape, warnings);
  } else if (ext == ".iges" || ext == ".igs") {
    IGESControl_Reader reader;
    if (reader.ReadFile(name.c_str()) != IFSelect_RetDone)
      throw InputError(name +
                       ": OpenCascade cannot parse this IGES file (truncated or invalid); "
                       "export it again");
    const Handle(IGESData_IGESModel) model = reader.IGESModel();
    if (model.IsNull() || reader.NbRootsForTransfer() == 0)
      throw InputError(name +
                       ": the IGES file holds no transferable entities (truncated or not "
                       "IGES); export it again");
    const Handle(TCollection_HAsciiString) unit = model->GlobalSection().UnitName();
    file_unit = unit.IsNull() ? "unknown" : unit->ToCString();
    reader.TransferRoots();
    shape = reader.OneShape();
  } else {
    throw InputError(name + ": unknown CAD extension '" + ext +
                     "'; use .step, .stp, .iges or .igs");
  }
  if (shape.IsNull())
    throw InputError(name +
                     ": the file holds no geometry OpenCascade can transfer (no solids, "
                     "shells or faces)");
  // Pcurves the reader fitted loosely would trim the faces wrongly (cad_pcurves.hpp).
  detail::rebuild_stray_pcurves(shape);
  return shape;
}

// read_shape_unguarded, first in a child process: a corrupted file that crashes OpenCascade
// becomes an input error naming the file (crash_guard.hpp). Reading twice costs the read time
// of the file again, small beside the conversion of its faces.
TopoDS_Shape read_shape(const std::filesystem::path& file, std::string& file_unit,
                        std::vector<std::string>& warnings) {
  detail::fail_if_it_crashes(file, [&] {
    std::string unit;
    std::vector<std::string> ignored;
    read_shape_unguarded(file, unit, ignored);
  });
  return read_shape_unguarded(file, file_unit, warnings);
}

}  // namespace

TopoDS_Shape detail::read_cad_shape(const std::filesystem::path& file, std::string& file_unit,
                                    std::vector<std::string>* warnings) {
  std::vector<std::string> found;
  TopoDS_Shape shape = read_shape(file, file_unit, found);
  if (warnings) warnings->insert(warnings->end(), found.begin(), found.end());
  return shape;
}

namespace {

CadModel read_cad_unguarded(const std::filesystem::path& file) {
  CadModel model;
  model.file = file;
  TopoDS_Shape shape;
  try {
    shape = read_shape(file, model.file_unit, model.warnings);
  } catch (const Standard_Failure& e) {
    throw InputError(file.string() + ": OpenCascade failed reading it (" + e.GetMessageString() +
                     "); the file is probably corrupt");
  }
  TopTools_IndexedMapOfShape solids, shells, faces, edges;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  TopExp::MapShapes(shape, TopAbs_SHELL, shells);
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  TopExp::MapShapes(shape, TopAbs_EDGE, edges);
  model.solids = solids.Extent();
  model.shells = shells.Extent();
  model.faces = faces.Extent();
  model.edges = edges.Extent();
  if (model.faces == 0)
    throw InputError(file.string() +
                     ": the file holds no faces (points or curves only); a part "
                     "needs surfaces or solids");
  const detail::Corners box = detail::tight_box(shape);
  model.bbox_min = box.lo;
  model.bbox_max = box.hi;
  for (int s = 1; s <= model.solids; ++s) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(solids(s), props, 1e-9);
    model.volume += props.Mass();
  }
  for (int f = 1; f <= model.faces; ++f) {
    const TopoDS_Face face = TopoDS::Face(faces(f));
    CadFace report = detail::describe_face(face, f - 1);
    model.area += report.area;
    try {
      // The first recogniser that makes patches of the face wins (cad_face_recognisers.cpp).
      for (const detail::FaceRecogniser& recogniser : detail::face_recognisers()) {
        const detail::FaceRecognition found = recogniser.recognise(face, report);
        if (!found.recognised) continue;
        auto& patches = found.cut ? model.split_patches : model.face_patches;
        auto& owners = found.cut ? model.split_patch_face : model.patch_face;
        patches.insert(patches.end(), found.patches.begin(), found.patches.end());
        owners.insert(owners.end(), found.patches.size(), report.index);
        break;
      }
    } catch (const Standard_Failure& e) {
      report.note =
          std::string("OpenCascade cannot convert it to NURBS (") + e.GetMessageString() + ")";
    } catch (const std::exception& e) {
      report.note = e.what();
    }
    model.face_reports.push_back(report);
  }
  for (int s = 1; s <= model.solids; ++s) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(solids(s), props, 1e-9);
    const detail::SolidContext context =
        detail::solid_context(solids(s), props.Mass(), model, faces);
    // The first recogniser that builds the solid wins (the list's order is part of the result);
    // otherwise the note says why each failed, or only why the one that knows the solid's kind
    // (final) failed.
    std::string why, remark;
    for (const detail::SolidRecogniser& recogniser : detail::solid_recognisers()) {
      detail::SolidRecognition r = recogniser.recognise(context);
      if (r.recognised) {
        model.volume_patches.insert(model.volume_patches.end(), r.patches.begin(), r.patches.end());
        model.patch_solid.insert(model.patch_solid.end(), r.patches.size(), s - 1);
        why.clear();
        remark = r.remark;
        break;
      }
      if (r.final) {
        why = r.why;
        break;
      }
      if (!r.why.empty()) why += (why.empty() ? "" : "; ") + r.why;
    }
    model.solid_notes.push_back(why);
    model.solid_remarks.push_back(remark);
  }
  return model;
}
}  // namespace

CadModel read_cad(const std::filesystem::path& file) {
  // A corrupted file can make OpenCascade throw (Standard_Failure is no std::exception, so it
  // would end the program) anywhere in the conversion, not only while reading.
  try {
    return read_cad_unguarded(file);
  } catch (const Standard_Failure& e) {
    throw InputError(file.string() + ": OpenCascade failed on it (" + e.GetMessageString() +
                     "); the file is probably corrupted: export it again");
  }
}

namespace {
std::string usability(const CadFace& face) {
  if (face.natural) return "usable patch";
  std::ostringstream out;
  out.precision(3);
  if (face.split > 0) {
    out << "split into " << face.split << " conforming patches (Jacobian min " << face.jacobian_min
        << ", max " << face.jacobian_max << ")";
    return out.str();
  }
  if (!face.coons) return "NOT usable: " + face.note;
  out << "usable Coons patch of its 4 edges (largest distance from the CAD surface "
      << face.coons_deviation << " m)";
  return out.str();
}
}  // namespace

std::string describe(const CadModel& model) {
  std::ostringstream out;
  out.precision(10);
  out << model.file.string() << ": unit in file " << model.file_unit << " (coordinates in m)\n"
      << "  solids " << model.solids << ", shells " << model.shells << ", faces " << model.faces
      << ", edges " << model.edges << "\n"
      << "  bounding box [" << model.bbox_min.transpose() << "] .. [" << model.bbox_max.transpose()
      << "] m\n"
      << "  volume " << model.volume << " m^3, area " << model.area << " m^2\n"
      << "  volume patches (hexahedral solids, quarters of solids of revolution, prisms and "
         "blocks of cut faces): "
      << model.volume_patches.size() << "\n";
  for (size_t s = 0; s < model.solid_notes.size(); ++s) {
    const auto patches = std::count(model.patch_solid.begin(), model.patch_solid.end(), s);
    out << "  solid " << s << ": "
        << (model.solid_notes[s].empty() ? std::to_string(patches) + " volume patch(es)"
                                         : model.solid_notes[s]);
    if (!model.solid_remarks[s].empty()) out << "; " << model.solid_remarks[s];
    out << "\n";
  }
  for (const std::string& warning : model.warnings) out << "  warning: " << warning << "\n";
  for (const auto& f : model.face_reports)
    out << "  face " << f.index << ": " << f.surface_type << ", " << f.wires << " wire(s), "
        << f.edges << " edges, area " << f.area << " m^2, " << usability(f) << "\n";
  return out.str();
}

std::vector<nurbs::Patch> cad_solid_patches(const CadModel& model, const std::vector<int>& solids) {
  const std::string name = model.file.string();
  if (solids.empty()) throw InputError(name + ": solids: give at least one solid index (0-based)");
  std::vector<nurbs::Patch> patches;
  for (size_t k = 0; k < solids.size(); ++k) {
    const int s = solids[k];
    if (s < 0 || s >= model.solids)
      throw InputError(name + ": solids[" + std::to_string(k) + "] = " + std::to_string(s) +
                       " is not a solid of the part (it has " + std::to_string(model.solids) +
                       "; indices are 0-based, listed by `isospring info`)");
    if (std::count(solids.begin(), solids.end(), s) > 1)
      throw InputError(name + ": solids: solid " + std::to_string(s) + " is listed twice");
    if (!model.solid_notes[static_cast<size_t>(s)].empty())
      throw InputError(name + ": solid " + std::to_string(s) +
                       " cannot be a volume patch: " + model.solid_notes[static_cast<size_t>(s)] +
                       "; leave it out of \"solids\" or split it in the CAD program");
    for (size_t p = 0; p < model.volume_patches.size(); ++p)
      if (model.patch_solid[p] == s) patches.push_back(model.volume_patches[p]);
  }
  return patches;
}

namespace {
// Every control point of every surface patch on the plane of the first one.
bool coplanar(const std::vector<nurbs::Patch>& patches) {
  if (patches.empty() || patches.front().param_dim() != 2) return false;
  const nurbs::Patch& first = patches.front();
  const nurbs::PatchDerivatives d =
      first.derivatives({(first.param_min(0) + first.param_max(0)) / 2,
                         (first.param_min(1) + first.param_max(1)) / 2, 0});
  const Eigen::Vector3d normal = d.first.col(0).cross(d.first.col(1)).normalized();
  for (const nurbs::Patch& patch : patches) {
    if (patch.param_dim() != 2) return false;
    for (const Eigen::Vector3d& x : patch.control_points())
      if (std::abs(normal.dot(x - d.point)) > 1e-9) return false;
  }
  return true;
}
}  // namespace

std::vector<nurbs::Patch> cad_patches(const CadModel& model, double thickness,
                                      const std::vector<int>& faces) {
  const std::string name = model.file.string();
  if (!(thickness >= 0.0 && std::isfinite(thickness)))
    throw InputError(name + ": thickness must be a non-negative number");
  if (faces.empty() && thickness == 0.0 && model.solids > 0 &&
      std::all_of(model.solid_notes.begin(), model.solid_notes.end(),
                  [](const std::string& note) { return note.empty(); }))
    return model.volume_patches;
  std::vector<int> chosen = faces;
  if (chosen.empty())
    for (int f = 0; f < model.faces; ++f) chosen.push_back(f);
  std::vector<nurbs::Patch> patches;
  for (int f : chosen) {
    if (f < 0 || f >= model.faces)
      throw InputError(name + ": face " + std::to_string(f) + " does not exist; the part has " +
                       std::to_string(model.faces) + " faces (0-based, see `isospring info`)");
    const CadFace& report = model.face_reports[static_cast<size_t>(f)];
    if (!report.natural && !report.coons && report.split == 0)
      throw InputError(name + ": face " + std::to_string(f) + " (" + report.surface_type +
                       ") cannot be analysed: " + report.note);
    if (thickness > 0.0 && report.surface_type != "plane")
      throw InputError(name + ": face " + std::to_string(f) + " is a " + report.surface_type +
                       "; only planar faces can be extruded exactly along their normal (use a "
                       "solid part instead)");
    for (const nurbs::Patch& patch : detail::model_face_patches(model, f))
      // A face in the plane z = 0 is a 2D region: the analysis needs it right-handed in x-y,
      // so a face facing -z (e.g. the bottom of a plate) has its u direction reversed.
      patches.push_back(thickness == 0.0 && patch.physical_dim() == 2 &&
                                jacobian_range(patch).max < 0.0
                            ? reverse_direction(patch, 0)
                            : patch);
  }
  // Faces of one plane analysed together (a specimen split into faces in the CAD program, or a
  // plate extruded from them) share straight edges that were cut independently: make them
  // conforming so the analysis glues them.
  if (chosen.size() > 1 && coplanar(patches)) patches = conform_shared_sides(patches, 1e-9);
  if (thickness > 0.0)
    for (nurbs::Patch& patch : patches) {
      const nurbs::PatchDerivatives d =
          patch.derivatives({(patch.param_min(0) + patch.param_max(0)) / 2,
                             (patch.param_min(1) + patch.param_max(1)) / 2, 0});
      const Eigen::Vector3d normal = d.first.col(0).cross(d.first.col(1)).normalized();
      patch = extrude(patch, thickness * normal);
    }
  return patches;
}

}  // namespace isospring::geometry
