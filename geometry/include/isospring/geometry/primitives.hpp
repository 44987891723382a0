#pragma once
// Exact NURBS primitives. Every function returns the patches of one part, right-handed (positive
// Jacobian: det(dX/du, dX/dv) > 0 in 2D, det(dX/du, dX/dv, dX/dw) > 0 in 3D; collapsed
// edges/points where det = 0 are stated), with the coarsest exact knot vectors (refine with
// nurbs/refine.hpp). Multi-patch parts are conforming: shared sides have identical knots, weights
// and coincident control points, which is what the analysis glues. Lengths in metres, angles in
// radians. Invalid parameters throw nurbs::InputError naming the parameter.
#include <Eigen/Core>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry {

using Patches = std::vector<nurbs::Patch>;

// ---- 2D (z = 0) ---------------------------------------------------------------------------

/// [0, lx] x [0, ly], bilinear: u along x (u0 is x = 0), v along y.
Patches rectangle(double lx, double ly);

/// Disk of radius r centred at the origin as ONE rational biquadratic 3x3 patch whose four sides
/// are the four quarter arcs (corners at 45, 135, 225, 315 degrees). The Jacobian vanishes at the
/// four corners (the boundary is smooth there) and is positive elsewhere.
Patches disk(double radius);

/// Disk of radius r as 5 patches without singular points: an inner square of half-width
/// `inner_fraction * r / sqrt(2)` (3x3, rational so its sides match the neighbours; u along x,
/// v along y) and four ruled patches (u clockwise, v radial outward) up to the quarter arcs.
Patches disk_five_patch(double radius, double inner_fraction = 0.5);

/// Ellipse with semi-axes a (along x) and b (along y): the single-patch disk scaled.
Patches ellipse(double a, double b);

/// Annulus sector between radii ri < ro from angle `start` sweeping `sweep` (<= 2 pi; a full
/// ring has coincident seam points): u radial (degree 1), v counter-clockwise (degree 2). The
/// quarter ring with ri = 1, ro = 2 is the Lame benchmark patch of benchmarks.md.
Patches annulus(double ri, double ro, double start = 0.0, double sweep = M_PI / 2);

/// Quarter of a square plate [-L, L]^2 with a central hole of radius R (upper-left quadrant,
/// x <= 0, y >= 0): the exact 12-point NURBS of benchmarks.md for R = 1, L = 4 (middle row scaled
/// with R + L in general). Degrees (2, 2), u from the x axis around the hole to the y axis, v from
/// the hole outward. The repeated control point (-L, L) makes (u, v) = (0.5, 1) singular.
Patches plate_with_hole_quarter(double hole_radius, double half_width);

/// The same quarter plate as 2 patches split at u = 0.5 (the plate's corner is now a patch
/// corner, no singular point); the patches share the diagonal side.
Patches plate_with_hole_quarter_two_patch(double hole_radius, double half_width);

// ---- 3D ----------------------------------------------------------------------------------

/// [0, lx] x [0, ly] x [0, lz], trilinear: u along x, v along y, w along z.
Patches box(double lx, double ly, double lz);

/// Thick cylinder (tube) sector: annulus(ri, ro, start, sweep) extruded over z in [0, length].
/// u radial, v circumferential, w axial.
Patches tube_sector(double ri, double ro, double length, double start = 0.0,
                    double sweep = M_PI / 2);

/// Solid torus about the z axis: tube (minor) radius r, centre-line (major) radius R > r. u is
/// the revolution (9 points, 4 arcs, coincident seam), (v, w) the cross-section disk (the 3x3
/// single-patch disk, so the section has the disk's 4 singular corners).
/// [S15]'s torus "inner radius 0.5, outer 1.25" is read as R - r = 0.5, R + r = 1.25.
Patches solid_torus(double major_radius, double minor_radius);

/// Hollow sphere sector: ri <= |x| <= ro, polar angle (from +z) in [0, polar_sweep], azimuth in
/// [0, azimuth_sweep]. u azimuth, v radial, w polar. The polar axis (polar angle 0) is a collapsed
/// edge. polar_sweep = azimuth_sweep = pi/2 is the octant of the Lame hollow-sphere benchmark.
Patches hollow_sphere_sector(double ri, double ro, double polar_sweep = M_PI / 2,
                             double azimuth_sweep = M_PI / 2);

/// Solid prolate spheroid x^2/b^2 + y^2/b^2 + z^2/a^2 <= 1 (a = half_length along z, b = radius,
/// centred at the origin): the half-ellipse region revolved about z. u revolution (9 points),
/// v along the profile from the south to the north pole (5 points), w from the axis to the
/// surface (degree 1, 2 points). The axis and the poles are collapsed.
Patches prolate_spheroid(double half_length, double radius);

/// [S15] Table 5.1 "coupled spheroid: length 4, radius 0.5, net 9x10x3, degrees (2,2,1)". The
/// source gives no construction. Our reading: two prolate spheroids of length 2 (half-length 1)
/// and radius 0.5 placed end to end along z (z in [0, 2] and [2, 4], touching at a pole, total
/// length 4), each with the net 9 x 5 x 3 of prolate_spheroid after one radial knot insertion
/// (degrees (2, 2, 1)). Stacking the two nets along the profile gives the 9 x 10 x 3 net whose
/// spring count (2315) [S15] reports.
Patches coupled_spheroid();

/// A planar (z = 0) region extruded along +z by `thickness`: w is the thickness direction, so
/// right-handed 2D patches give right-handed volumes.
Patches thin_plate(const Patches& region, double thickness);

}  // namespace isospring::geometry
