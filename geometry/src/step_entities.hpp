#pragma once
// Entities of a STEP file that OpenCascade could not read: a misspelled or unsupported type
// (CARTESIAN_POINTX) is kept as an undefined entity, and whatever refers to it is then silently
// left out or, in the transfer, dereferenced as null. When such an entity belongs to the geometry
// (a point, a curve, a face, the length unit) the file is corrupted and is reported before any
// transfer instead of becoming a part with missing geometry (or a crash). Exporters also write
// entities outside the geometry that OpenCascade does not know (a POINT_STYLE of a presentation
// layer, a VALUE_RANGE in validation properties, a unit with an unusual parameter count): the
// shape does not depend on them, so they are only worth a warning.
#include <Interface_InterfaceModel.hxx>
#include <filesystem>
#include <string>

namespace isospring::geometry::detail {

/// "" when every entity of the model was read; otherwise how many were not, with the labels and
/// types of the first three and OpenCascade's complaint about each.
std::string unreadable_step_entities(const Handle(Interface_InterfaceModel) & model);

/// True when the model has unreadable entities and none of them is part of the geometry: no
/// geometric or topological representation item (point, curve, surface, vertex, edge, face,
/// shell, solid) refers to any of them, directly or through other entities, and none is a length
/// unit. References are read from the file's text (`file`, the file the model was read from),
/// because OpenCascade drops a reference to an entity it could not read.
bool unreadable_entities_outside_geometry(const Handle(Interface_InterfaceModel) & model,
                                          const std::filesystem::path& file);

}  // namespace isospring::geometry::detail
