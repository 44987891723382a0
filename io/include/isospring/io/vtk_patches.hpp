#pragma once
// NURBS patch geometry and fields as VTK unstructured grids (.vtu), in two forms:
//
//  - sampled: every element split into `samples_per_element` linear sub-cells per direction
//    (VTK_LINE / VTK_QUAD / VTK_HEXAHEDRON) at exact points of the patch; point data are the
//    control fields and the evaluated fields, plus "parameter" (u, v, w); cell data "patch".
//  - Bezier: one VTK_BEZIER_CURVE (75) / VTK_BEZIER_QUADRILATERAL (77) / VTK_BEZIER_HEXAHEDRON
//    (79) cell per element, from Bezier extraction in homogeneous coordinates, with point data
//    "RationalWeights" and cell data "HigherOrderDegrees". The geometry is exact (up to rounding)
//    and so are control fields, which VTK interpolates with the same rational basis. Bezier
//    points shared by neighbouring elements are shared in the grid, so ParaView sees a
//    connected mesh. Evaluated fields are not written here (see vtk_fields.hpp). In ParaView,
//    raise "Nonlinear Subdivision Level" to see the curvature.
#include <filesystem>
#include <vector>

#include "isospring/io/vtk_fields.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

/// Throws std::invalid_argument when a control field does not match the patches (a caller bug)
/// and nurbs::InputError when the file cannot be written. samples_per_element >= 1.
void write_patches_sampled_vtu(const std::filesystem::path& path,
                               const std::vector<nurbs::Patch>& patches, const PatchFields& fields,
                               int samples_per_element = 4);

void write_patches_bezier_vtu(const std::filesystem::path& path,
                              const std::vector<nurbs::Patch>& patches,
                              const std::vector<ControlField>& fields = {});

}  // namespace isospring::io
