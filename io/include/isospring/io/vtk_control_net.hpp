#pragma once
// Control nets as VTK poly data (.vtp): every control point of every patch (patches one after
// the other, first parametric direction fastest) with point data "weight", "patch" and the
// control fields (e.g. control point displacements), and the net lines along each parametric
// direction with cell data "patch" and "direction".
#include <filesystem>
#include <vector>

#include "isospring/io/vtk_fields.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

void write_control_net_vtp(const std::filesystem::path& path,
                           const std::vector<nurbs::Patch>& patches,
                           const std::vector<ControlField>& fields = {});

}  // namespace isospring::io
