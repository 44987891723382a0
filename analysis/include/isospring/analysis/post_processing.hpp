#pragma once
// Fields of a solution anywhere in the parameter domain, and error norms against exact fields.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::analysis {

/// Control displacements [patch][control point], as in LoadCaseResult.
using ControlDisplacements = std::vector<std::vector<Eigen::Vector3d>>;

struct FieldPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();         // X(u)
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // u(X(u))
  Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();  // 2D: in-plane, ezz for plane stress/B-bar
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();  // 2D: szz = nu (sxx + syy) in plane strain
  double von_mises = 0.0;
};

/// Displacement, strain and stress at parameter u of a patch. Under Volumetric::kBbar strain is
/// the B-bar strain eps + (theta_bar - tr eps) / 3 I (its trace is the projected volumetric
/// strain theta_bar; in plane strain it has a zz component) and stress its Hooke stress; this
/// function then projects the whole solution on every call: use FieldEvaluator for many points.
FieldPoint evaluate_field(const Problem& problem, const ControlDisplacements& displacements,
                          int patch, const nurbs::Param& u);

/// evaluate_field for many points of one solution: what does not depend on the point (the
/// projected volumetric strain under B-bar) is computed once. Keeps references to both inputs.
class FieldEvaluator {
 public:
  FieldEvaluator(const Problem& problem, const ControlDisplacements& displacements);
  ~FieldEvaluator();
  FieldEvaluator(FieldEvaluator&&) noexcept;
  FieldPoint operator()(int patch, const nurbs::Param& u) const;

 private:
  struct Projection;
  const Problem* problem_;
  const ControlDisplacements* displacements_;
  std::unique_ptr<const Projection> projection_;  // null for the displacement formulation
};

/// Integrated errors: L2 norm of u - u_h and energy norm sqrt(int (s - s_h) : C^-1 (s - s_h))
/// (2D: in-plane stress, times the thickness), with the norms of the exact fields for relative
/// errors. Quadrature: `quadrature_points` Gauss points per direction and element (0: degree + 3,
/// enough for the norms to converge; degree + 1 reproduces protocols that under-integrate).
struct ErrorNorms {
  double l2_error = 0.0;
  double l2_norm = 0.0;
  double energy_error = 0.0;
  double energy_norm = 0.0;
  double relative_l2() const { return l2_error / l2_norm; }
  double relative_energy() const { return energy_error / energy_norm; }
};
ErrorNorms error_norms(const Problem& problem, const ControlDisplacements& displacements,
                       const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& exact_u,
                       const std::function<Eigen::Matrix3d(const Eigen::Vector3d&)>& exact_stress,
                       int quadrature_points = 0);

/// Strain energy 1/2 int s : e of a discrete field (equals 1/2 u^T K u).
double strain_energy(const Problem& problem, const ControlDisplacements& displacements);

}  // namespace isospring::analysis
