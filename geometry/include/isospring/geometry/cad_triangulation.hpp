#pragma once
// Triangulations of CAD faces for display, trimmed ones included (holes, L-shapes, disks: the
// faces that cannot become analysis patches), so a user sees the whole part next to the patches
// that were made of it. OpenCascade's BRepMesh meshes every face within a chordal deflection;
// triangles are oriented like the face (outward for a solid's faces).
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <vector>

namespace isospring::geometry {

struct CadTriangulation {
  std::vector<Eigen::Vector3d> points;        // m
  std::vector<std::array<int, 3>> triangles;  // indices into points
  std::vector<int> triangle_face;             // face index (as in CadModel::face_reports)
};

/// Meshes every face of a STEP/IGES part. `relative_deflection`: largest distance between a
/// triangle and its face, as a fraction of the part's bounding-box diagonal (> 0). Throws
/// nurbs::InputError for a bad file or deflection, std::runtime_error when meshing fails.
CadTriangulation triangulate_cad(const std::filesystem::path& file,
                                 double relative_deflection = 1e-3);

}  // namespace isospring::geometry
