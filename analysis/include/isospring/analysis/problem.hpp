#pragma once
// The linear-elasticity problem as the analysis sees it: patches, material, supports, load cases.
// Case files (io module) are translated into this; nothing here knows about JSON.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::analysis {

enum class Formulation { kPlaneStress, kPlaneStrain, kSolid };

/// How the volumetric strain enters the stiffness and the stresses. kDisplacement: the strain of
/// the displacement field everywhere (locks at low degree as nu -> 0.5). kBbar: the volumetric
/// strain projected onto splines of one degree lower on the same knots (B-bar, volumetric_
/// projection.hpp); plane strain and solids only (plane stress does not lock).
enum class Volumetric { kDisplacement, kBbar };

struct Material {
  double youngs_modulus = 0.0;  // E [Pa]
  double poisson_ratio = 0.0;   // nu, in (-1, 0.5)
  double density = 0.0;         // rho [kg/m^3]
  double thickness = 1.0;       // plane stress/strain: out-of-plane thickness [m]
};

/// A parametric side of a patch: dir 0/1/2 (u/v/w), end 0 (at the first knot) or 1 (last knot).
/// Names: u0 u1 v0 v1 w0 w1.
struct Side {
  int patch = 0;
  int dir = 0;
  int end = 0;
};
/// "u0" -> {patch, 0, 0} ... "w1" -> {patch, 2, 1}; throws nurbs::InputError for other names.
Side parse_side(const std::string& name, int patch = 0);
std::string side_name(const Side& side);

/// Displacement constraint on every control point of a side (or on one control point).
/// Components with fixed[c] get value[c] (or value_function(x)[c] at the control point).
/// symmetry: the normal component of the side is fixed to zero (a straight side along an axis).
struct Support {
  Side side;
  std::optional<int> control_point;  // when set, only this control point of side.patch
  std::array<bool, 3> fixed{false, false, false};
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> value_function;  // overrides value
  bool symmetry = false;
};

/// Traction [Pa] on a side: constant vector, or a function of position x and outward normal n.
struct Traction {
  Side side;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  std::function<Eigen::Vector3d(const Eigen::Vector3d& x, const Eigen::Vector3d& n)> function;
};

/// Normal pressure [Pa] on a side, positive pushing into the body (traction = -p n).
struct Pressure {
  Side side;
  double value = 0.0;
};

/// Force [N] on one control point.
struct PointLoad {
  int patch = 0;
  int control_point = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

struct LoadCase {
  std::string id;
  std::vector<Traction> tractions;
  std::vector<Pressure> pressures;
  std::vector<PointLoad> point_loads;
  Eigen::Vector3d body_force = Eigen::Vector3d::Zero();  // [N/m^3]
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();     // [m/s^2], times the density
};

struct Problem {
  std::vector<nurbs::Patch> patches;
  Formulation formulation = Formulation::kSolid;
  Volumetric volumetric = Volumetric::kDisplacement;
  Material material;
  std::vector<Support> supports;
  std::vector<LoadCase> load_cases;
  int quadrature_points = 0;  // per direction; 0 means degree + 1
  /// Glue coincident sides of the SAME patch (the seam of a closed revolved patch, e.g. a torus).
  /// false leaves the seam open (a cut body), as the unmerged control nets of [S15] ch. 5 have it
  /// (its torus has 2000 springs only without merging); interfaces between patches stay glued.
  bool glue_patch_seams = true;
};

}  // namespace isospring::analysis
