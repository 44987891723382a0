#pragma once
// The OpenCascade shape of a STEP/IGES file in metres, with the file's declared unit: the reader
// behind read_cad(), shared with the display triangulation (cad_triangulation.cpp).
#include <TopoDS_Shape.hxx>

#include <filesystem>
#include <string>

namespace isospring::geometry::detail {

/// Throws nurbs::InputError naming the file when it is missing, empty, not STEP/IGES or
/// unreadable.
TopoDS_Shape read_cad_shape(const std::filesystem::path& file, std::string& file_unit);

}  // namespace isospring::geometry::detail
