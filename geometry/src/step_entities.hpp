#pragma once
// Entities of a STEP file that OpenCascade could not read: a misspelled or unsupported type
// (CARTESIAN_POINTX) is kept as an undefined entity, and whatever refers to it is then silently
// left out or, in the transfer, dereferenced as null. Such a file is corrupted; it is reported
// before any transfer instead of becoming a part with missing geometry (or a crash).
#include <Interface_InterfaceModel.hxx>
#include <string>

namespace isospring::geometry::detail {

/// "" when every entity of the model was read; otherwise how many were not, with the labels and
/// types of the first three and OpenCascade's complaint about each.
std::string unreadable_step_entities(const Handle(Interface_InterfaceModel) & model);

}  // namespace isospring::geometry::detail
