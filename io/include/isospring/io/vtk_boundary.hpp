#pragma once
// The outer surface of a solid model for ParaView, sampled: what a person looks at, at a size
// that grows with the model's surface rather than its volume. Each outer side of a patch (one
// parameter at an end; not glued to another patch, not collapsed: analysis::inner_sides) is
// sampled `samples_per_element` x `samples_per_element` per element face with linear
// quadrilaterals at exact points; point data as write_patches_sampled_vtu ("parameter" holds the
// patch's (u, v, w) on the side, so evaluated fields are the volume's at the surface), cell data
// "patch" and "side" (2 * direction + end: 0 = u0, 1 = u1, 2 = v0, ... 5 = w1).
#include <filesystem>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/io/vtk_fields.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

struct PatchSide {
  int patch = 0;
  int dir = 0;  // parametric direction held at an end
  int end = 0;  // 0: its first parameter, 1: its last
};

/// The outer sides of the problem's solid (3-parameter) patches, by patch, direction and end.
std::vector<PatchSide> outer_sides(const analysis::Problem& problem);

/// Samples per element and direction for the boundary of `sides`: the largest of 1..`most` whose
/// sampled points stay within `points_per_control_point` x the model's control points or
/// `small_model_points`, whichever is larger, so a large model's file stays in proportion to it
/// while a small one is drawn smoothly (1 when even that exceeds the budget).
int boundary_samples(const std::vector<nurbs::Patch>& patches, const std::vector<PatchSide>& sides,
                     int most = 4, double points_per_control_point = 2.0,
                     double small_model_points = 50000.0);

/// Throws std::invalid_argument for a side that the patch does not have, a control field that
/// does not match the patches or samples_per_element < 1, nurbs::InputError when the file cannot
/// be written.
void write_boundary_sampled_vtu(const std::filesystem::path& path,
                                const std::vector<nurbs::Patch>& patches,
                                const std::vector<PatchSide>& sides, const PatchFields& fields,
                                int samples_per_element);

}  // namespace isospring::io
