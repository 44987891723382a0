#pragma once
// The OpenCascade shape of a STEP/IGES file in metres, with the file's declared unit: the reader
// behind read_cad(), shared with the display triangulation (cad_triangulation.cpp).
#include <TopoDS_Shape.hxx>

#include <filesystem>
#include <string>
#include <vector>

namespace isospring::geometry::detail {

/// Throws nurbs::InputError naming the file when it is missing, empty, not STEP/IGES or
/// unreadable. What the reader skipped without harm (see CadModel::warnings) is appended to
/// `warnings` when given.
TopoDS_Shape read_cad_shape(const std::filesystem::path& file, std::string& file_unit,
                            std::vector<std::string>* warnings = nullptr);

}  // namespace isospring::geometry::detail
