#pragma once
// What a spring model of an immersed part takes from the background basis (fitting's immersed
// calibration, fitting/immersed_calibration.hpp): the lumped mass of each background control
// point over the part, the control points a supported face holds, and the spline field of any
// control-point values at physical points (to compare two sets of coefficients on the part).
#include <Eigen/Core>
#include <vector>

#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::analysis {

/// Per background control point a: density * thickness * int_part N_a dV over the domain's cell
/// quadrature. The background splines sum to one, so this is the row sum of the consistent mass
/// matrix integrated over the part only (the body-fitted path's row-sum lumping, lumped_mass):
/// every entry >= 0 and the sum is density * thickness * the part's volume. Zero for control
/// points whose support misses the part. Throws nurbs::InputError for a bad domain.
std::vector<double> immersed_lumped_mass(const geometry::ImmersedDomain& domain, double density,
                                         double thickness = 1.0);

/// The background control points whose basis function reaches 1e-3 or more (of its peak 1) at
/// one or more of the domain's boundary quadrature points on `face`, in increasing order. On a
/// face that lies on the background box's boundary these are the control points of that side of
/// the net (open knot vectors: one layer; the 1e-3 keeps the next layer out when OpenCascade's
/// box, enlarged by the edges' tolerance, puts the face a round-off distance inside the first
/// cell); on a face that cuts cells, every control point of the cells the face crosses whose
/// function reaches it. Throws nurbs::InputError when no boundary point lies on the face.
std::vector<int> immersed_face_control_points(const geometry::ImmersedDomain& domain, int face);

/// The spline field sum_a N_a(x) values[a] at each point (values: one per background control
/// point; points inside the background box). As evaluate_immersed, with the basis built once.
std::vector<Eigen::Vector3d> evaluate_immersed_field(const geometry::ImmersedDomain& domain,
                                                     const std::vector<Eigen::Vector3d>& values,
                                                     const std::vector<Eigen::Vector3d>& points);

}  // namespace isospring::analysis
