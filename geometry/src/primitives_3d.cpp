// Solid exact primitives, built from the planar ones by extrusion and revolution.
#include <cmath>

#include "isospring/geometry/construction.hpp"
#include "isospring/geometry/primitives.hpp"
#include "isospring/nurbs/refine.hpp"
#include "parameter_checks.hpp"

namespace isospring::geometry {

using detail::require_less;
using detail::require_positive;
using detail::require_sweep;
using nurbs::KnotVector;
using nurbs::Patch;

namespace {
// Maps the xy plane of a planar profile to the xz half-plane (x = distance from the z axis,
// y -> z), optionally mirrored (z = -y) to choose the orientation of the revolved solid: the
// revolution about z turns a profile whose (rho, z) Jacobian is negative into a right-handed
// solid (det = -rho * det_2D).
Patch to_xz_plane(const Patch& profile, bool mirror) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  A(0, 0) = 1.0;
  A(2, 1) = mirror ? -1.0 : 1.0;
  return transformed(profile, A);
}
}  // namespace

Patches box(double lx, double ly, double lz) {
  require_positive(lz, "box", "size[2]");
  const Patch base = rectangle(lx, ly)[0];
  return {extrude(base, Eigen::Vector3d(0, 0, lz))};
}

Patches tube_sector(double ri, double ro, double length, double start, double sweep) {
  require_positive(length, "tube", "length");
  return {extrude(annulus(ri, ro, start, sweep)[0], Eigen::Vector3d(0, 0, length))};
}

Patches solid_torus(double major_radius, double minor_radius) {
  require_positive(major_radius, "torus", "major_radius");
  require_positive(minor_radius, "torus", "minor_radius");
  require_less(minor_radius, major_radius, "torus", "minor_radius", "major_radius");
  const Patch section = transformed(disk(minor_radius)[0], Eigen::Matrix3d::Identity(),
                                    Eigen::Vector3d(major_radius, 0, 0));
  // The disk is right-handed in (x, y), so its image in (rho, z) must be mirrored.
  return {revolve_about_z(to_xz_plane(section, true), 2 * M_PI)};
}

Patches hollow_sphere_sector(double ri, double ro, double polar_sweep, double azimuth_sweep) {
  require_sweep(polar_sweep, M_PI, "hollow_sphere", "polar_sweep");
  require_sweep(azimuth_sweep, 2 * M_PI, "hollow_sphere", "azimuth_sweep");
  // Profile in (rho, z): the annulus sector from polar angle polar_sweep (standard angle
  // pi/2 - polar_sweep) counter-clockwise up to the +z axis, (u radial, v towards the pole).
  // Reversing v makes it run from the pole (polar angle 0) outwards; its (rho, z) Jacobian is
  // then negative, so the revolved solid (azimuth, radial, polar) is right-handed.
  const Patch profile =
      reverse_direction(annulus(ri, ro, M_PI / 2 - polar_sweep, polar_sweep)[0], 1);
  return {revolve_about_z(to_xz_plane(profile, false), azimuth_sweep)};
}

Patches prolate_spheroid(double half_length, double radius) {
  require_positive(half_length, "spheroid", "half_length");
  require_positive(radius, "spheroid", "radius");
  // Half ellipse from the south pole through (radius, 0) to the north pole: a unit half circle
  // (two quarter arcs) scaled, and the axis segment with the same knots and weights so the ruled
  // profile is linear along each ruling.
  const Patch arc = transformed(circular_arc(Eigen::Vector3d::Zero(), 1.0, -M_PI / 2, M_PI),
                                Eigen::Vector3d(radius, half_length, 1.0).asDiagonal());
  std::vector<Eigen::Vector3d> axis_points;
  for (const auto& p : arc.control_points()) axis_points.emplace_back(0.0, p.y(), 0.0);
  const Patch axis({arc.knots(0)}, axis_points, arc.weights());
  // (v profile, w radial): Jacobian in (rho, z) is negative (tangent +z, radial +rho).
  return {revolve_about_z(to_xz_plane(ruled(axis, arc), false), 2 * M_PI)};
}

Patches coupled_spheroid() {
  const Patch single = nurbs::insert_knot(prolate_spheroid(1.0, 0.5)[0], 2, 0.5);
  return {transformed(single, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 1.0)),
          transformed(single, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 3.0))};
}

Patches thin_plate(const Patches& region, double thickness) {
  require_positive(thickness, "thin_plate", "thickness");
  Patches solids;
  for (size_t i = 0; i < region.size(); ++i) {
    if (region[i].param_dim() != 2 || region[i].physical_dim() != 2)
      throw nurbs::InputError("thin_plate: patch " + std::to_string(i) +
                              " is not a planar (z = 0) surface; only 2D regions can be extruded");
    solids.push_back(extrude(region[i], Eigen::Vector3d(0, 0, thickness)));
  }
  return solids;
}

}  // namespace isospring::geometry
