#pragma once
// The "geometry" object of a case file: an exact primitive, a patch file or a CAD part.
// Lengths in m, angles in degrees; [brackets] = optional with its default.
//
// clang-format off
// type              fields                                      patches, parametric directions
// ----------------  ------------------------------------------  -------------------------------
// rectangle         size [lx, ly]                               1, 2D, u along x (u0: x = 0)
// square            size L                                      as rectangle
// disk              radius [patches 1|5 = 1]                    1 (3x3 rational, 4 singular
//                   [inner_fraction 0.5] (5 patches only)         corners) or 5 (no singularity)
// ellipse           radii [a, b] (a along x)                    1, 2D
// annulus           inner_radius outer_radius                   1, 2D, u radial, v counter-
//                   [start_angle 0] [sweep_angle 90, <= 360]      clockwise
// plate_with_hole   hole_radius half_width [patches 1|2 = 1]    quarter plate x <= 0, y >= 0
// plate_with_central_hole                                       6 conforming (4 ring patches
//                   size [length, width] hole_radius              around the hole, 2 rectangles)
// box               size [lx, ly, lz]                           1, u along x, v y, w z
// cube              size L                                      as box
// tube              inner_radius outer_radius length            1, u radial, v around, w along z
//                   [start_angle 0] [sweep_angle 90]
// torus             major_radius minor_radius, or               1, u around z, (v, w) section
//                   inner_radius outer_radius (= R -+ r, [S15])   disk
// hollow_sphere     inner_radius outer_radius                   1, u azimuth, v radial, w polar
//                   [polar_angle 90, <= 180] [azimuth_angle 90]
// spheroid          half_length (along z) radius                1, u around z, v pole to pole,
//                                                                 w radial
// coupled_spheroid  (none): [S15] Table 5.1, see primitives.hpp 2 spheroids, z in [0, 4]
// thin_plate        region (a 2D geometry object) thickness     the region's, w along +z
// patches           file (patch file, relative to the case)     as in the file
// cad               file (.step/.stp/.iges/.igs)                hexahedral solids as volumes,
//                   [thickness 0: extrude planar faces]           else one per untrimmed face
//                   [faces: 0-based indices to keep]
// clang-format on
//
// Every problem is a nurbs::InputError starting with the case file's name and the field, e.g.
//   "case.json: geometry.size must have 3 numbers for a box, got 2".
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

/// Builds the exact patches of a case file's "geometry" object; relative file names are resolved
/// against `case_dir`; `case_file_name` prefixes messages.
std::vector<nurbs::Patch> build_case_geometry(const nlohmann::json& geometry,
                                              const std::filesystem::path& case_dir,
                                              const std::string& case_file_name);

/// The table above as plain text (for `--help`).
std::string geometry_types_help();

}  // namespace isospring::io
