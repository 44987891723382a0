#pragma once
// Fields attached to NURBS patches for VTK output, in the two forms the callers have:
//
//  - ControlField: coefficients at the control points, mapped through the rational basis,
//    u(xi) = sum_i R_i(xi) u_i. This is exactly how IGA displacements are represented, so the
//    sampled output is the solution itself and the Bezier output reproduces it exactly.
//  - PatchField: a callback evaluated at parametric points (stress, von Mises, strain energy
//    density, errors against a closed form). Written on the sampled geometry only, because a
//    field that is discontinuous between elements has no exact Bezier-node representation.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

struct ControlField {
  std::string name;
  int components = 3;
  /// One matrix per patch, components x num_points (control point order of the patch).
  std::vector<Eigen::MatrixXd> coefficients;
};

struct PatchField {
  std::string name;
  int components = 1;
  std::function<Eigen::VectorXd(int patch, const nurbs::Param& u)> evaluate;
  /// True when `evaluate` may run on several threads at once; the sampled writers evaluate in
  /// parallel only when every field says so.
  bool thread_safe = false;
};

struct PatchFields {
  std::vector<ControlField> control;
  std::vector<PatchField> evaluated;
};

/// A vector field from [patch][control point] displacements (the LoadCaseResult layout).
ControlField control_vector_field(const std::string& name,
                                  const std::vector<std::vector<Eigen::Vector3d>>& values);

/// reference - model per control point ("error" fields). Throws std::invalid_argument when the
/// two do not have the same patches and sizes.
ControlField control_field_difference(const std::string& name, const ControlField& reference,
                                      const ControlField& model);

/// |u(xi)| of a vector control field, as an evaluated field named `name`.
PatchField magnitude_field(const std::string& name, const std::vector<nurbs::Patch>& patches,
                           const ControlField& field);

/// Cauchy stress from a callback: 9 components row-major (xx xy xz yx ... zz), as ParaView
/// expects for tensors.
PatchField stress_tensor_field(const std::string& name,
                               std::function<Eigen::Matrix3d(int, const nurbs::Param&)> stress);

/// von Mises equivalent stress sqrt(3/2 s:s), s the deviator, from the same callback.
PatchField von_mises_field(const std::string& name,
                           std::function<Eigen::Matrix3d(int, const nurbs::Param&)> stress);
double von_mises(const Eigen::Matrix3d& stress);

/// The value of a control field on patch `patch` at parameter u (through the rational basis).
Eigen::VectorXd evaluate_control_field(const nurbs::Patch& patch, const Eigen::MatrixXd& values,
                                       const nurbs::Param& u);

}  // namespace isospring::io
