#pragma once
// Immersed (finite cell / CutIGA) linear elasticity: the B-spline background grid of a
// geometry::ImmersedDomain discretises the displacement, integrals run over the domain's cell
// quadrature (the part only), and supports act on the part's faces by Nitsche's method.
//
// - DOFs: the background basis functions whose support meets the part (those of inside and cut
//   cells); the others do not exist.
// - Supports (symmetric Nitsche): a(u, v) - int_G (P sigma(u) n).v - int_G (P sigma(v) n).u +
//   int_G beta P u.v on each supported face G, with P the projector on the held components
//   (fixed axes, or n n^T for a symmetry face); a traction on the same face acts through I - P.
//   The penalty is per cell K holding support points: beta_K = nitsche_factor * C_K, with C_K the
//   largest generalised eigenvalue of int_{G in K} |P sigma(v) n|^2 <= C_K A_K(v, v), where A_K
//   is the stabilised energy (bulk stiffness over the part plus the ghost penalty) of the 3^d
//   block of active cells around a cut K (K alone when the part fills it), over the block's
//   basis (reduced to K's DOFs by the Schur complement). By Young's inequality the form is
//   coercive for beta_K > 2 m C_K, m the number of blocks a cell or face belongs to (m <= 3^d);
//   that bound is pessimistic (it assumes every block is at its worst at once), and
//   nitsche_factor = 4 (twice the single-cell bound 2) was positive definite on every cut tried,
//   slivers of 1e-6 cells included. Cholesky's failure names the option when it is not.
// - Stabilisation (ghost penalty): gamma (lambda + 2 mu) h^(2p-1) / (p!)^2 int_F [d^p u/dn^p].
//   [d^p v/dn^p] on every grid face F of a badly cut cell (its share of the part below
//   ghost_fraction of the cell) shared with another active cell. The
//   background splines are C^(p-1), so only the p-th normal derivative jumps and the penalty
//   vanishes exactly when the spline is one polynomial across F: it extends control from the
//   neighbours into cells with a tiny share of the part, which keeps the condition number, CG
//   iterations and the penalty C_K bounded however the cells are cut, and it is weakly
//   consistent (it vanishes for polynomial fields; O(h^p) in energy otherwise, the method's own
//   rate, but it is an error: on the Nutils plate below, penalising every cut cell's faces with
//   gamma = 0.1 triples the L2 error at 4 x 4 cells, so well-cut cells are left alone, where the
//   basis is stable by itself). Why not a fictitious stiffness alpha on the outside parts: the
//   condition number then grows like 1/alpha, and the Nitsche penalty of a sliver cell has no
//   bound.
// - Loads: tractions and pressures on faces, body force and gravity over the part.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/geometry/immersed_domain.hpp"

namespace isospring::analysis {

/// Displacement held on a face: components with fixed[c] equal value[c] (or value_function(x));
/// symmetry holds the normal component at zero instead.
struct ImmersedSupport {
  int face = -1;
  std::array<bool, 3> fixed{false, false, false};
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> value_function;  // overrides value
  bool symmetry = false;
};

/// Traction [Pa] on a face: constant, or a function of position and outward normal.
struct ImmersedTraction {
  int face = -1;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  std::function<Eigen::Vector3d(const Eigen::Vector3d& x, const Eigen::Vector3d& n)> function;
};

/// Normal pressure [Pa] on a face, positive pushing into the part (traction -p n).
struct ImmersedPressure {
  int face = -1;
  double value = 0.0;
};

struct ImmersedOptions {
  Formulation formulation = Formulation::kSolid;  // plane stress/strain for 2D domains
  Material material;
  std::vector<ImmersedSupport> supports;
  std::vector<ImmersedTraction> tractions;
  std::vector<ImmersedPressure> pressures;
  Eigen::Vector3d body_force = Eigen::Vector3d::Zero();  // [N/m^3]
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();     // [m/s^2], times the density
  double nitsche_factor = 4.0;   // beta_K = nitsche_factor * C_K (see above), > 2
  double ghost_penalty = 0.01;   // gamma; 0 switches the stabilisation off
  double ghost_fraction = 0.02;  // penalise the faces of cut cells with less of the part than this
  /// kBbar: the volumetric strain is its mean over each cell's part (mean-dilatation B-bar,
  /// analysis/src/immersed_bbar.hpp), for nearly incompressible parts at p = 2; solids and plane
  /// strain. The strain energy is then B-bar's; immersed_stress stays the displacement's.
  Volumetric volumetric = Volumetric::kDisplacement;
  SolverOptions::Method method = SolverOptions::Method::kCholesky;  // kAuto: choose_solver
  double cg_tolerance = 1e-10;
};

/// The assembled system on the active DOFs (DOF = node * dim + component).
struct ImmersedSystem {
  int dim = 2;
  std::vector<int> node_of_control_point;  // -1 for inactive control points
  std::vector<int> control_point_of_node;
  Eigen::SparseMatrix<double> stiffness;  // upper triangle (as assemble_stiffness), with the
                                          // Nitsche and ghost-penalty terms
  Eigen::VectorXd force;
  double max_nitsche_penalty = 0;  // largest beta_K / (lambda + 2 mu) * h, dimensionless
  int ghost_faces = 0;
  std::map<int, double> nitsche_penalties;  // beta_K per supported background element (flat)
  ImmersedOptions options;                  // it was assembled with
};

/// Checks the input (faces, material, a support that leaves a rigid-body motion free: the same
/// nurbs::InputError as the body-fitted solver) and assembles the system.
ImmersedSystem assemble_immersed(const geometry::ImmersedDomain& domain,
                                 const ImmersedOptions& options);

/// Assembles the system of `options` and hands it to `factorise`, which returns false when the
/// stiffness is not positive definite (a basis function left with a sliver of its support in the
/// part although no cell's share lies below ghost_fraction). Then the ghost penalty is extended
/// to more cut cells (ghost_fraction doubled, up to 0.16), a warning appended to `warnings` and
/// the system assembled again; the system returned carries the options it was assembled with
/// (`system.options.ghost_fraction`). Throws std::runtime_error, beginning with `who` and naming
/// ghost_fraction, ghost_penalty and moving the grid, when the penalty is off or 0.16 does not
/// do. solve_immersed, the immersed calibration's reference and the identification stabilise
/// through it, so the same options give the same system everywhere.
ImmersedSystem assemble_stabilised_immersed(
    const geometry::ImmersedDomain& domain, const ImmersedOptions& options,
    const std::function<bool(const ImmersedSystem&)>& factorise, std::vector<std::string>& warnings,
    const std::string& who = "immersed analysis");

/// The right-hand side alone of `options` on `system`'s DOFs, as assemble_immersed would give it
/// (the same sums in the same order, so the same vector to the last bit): body force and
/// gravity, tractions and pressures, and the Nitsche terms of support values with the system's
/// penalties. For several load cases of one model: the stiffness and its penalties' eigenvalue
/// problems are assembled once. Throws nurbs::InputError when the supports (faces and held
/// components), the material or nitsche_factor differ from the system's, or the domain is
/// another one.
Eigen::VectorXd assemble_immersed_loads(const geometry::ImmersedDomain& domain,
                                        const ImmersedOptions& options,
                                        const ImmersedSystem& system);

struct ImmersedResult {
  int dim = 2;
  std::vector<Eigen::Vector3d> control_displacements;  // every background control point (0 when
                                                       // inactive)
  std::vector<bool> active;                            // control point carries DOFs
  int dofs = 0;
  double strain_energy = 0;  // 1/2 int_part sigma : eps (times the thickness in 2D)
  SolverOptions::Method method = SolverOptions::Method::kCholesky;
  int iterations = 0;  // CG iterations (0 for the direct solver)
  double relative_residual = 0;
  double assembly_seconds = 0, solve_seconds = 0;
  double max_nitsche_penalty = 0;
  int ghost_faces = 0;
  /// The ghost_fraction the solution was stabilised with: the options' own, or larger where the
  /// stiffness was not positive definite with it (then `warnings` says so).
  double ghost_fraction = 0;
  std::vector<std::string> warnings;
};

/// Assembles and solves. Where the Cholesky factorisation finds the stiffness not positive
/// definite (a basis function left with a sliver of its support in the part although no cell's
/// share lies below ghost_fraction), the ghost penalty is extended to more cut cells
/// (ghost_fraction doubled, up to 0.16) and the system solved again, with a warning in the
/// result; the same options then reproduce the result with its `ghost_fraction`. Throws
/// nurbs::InputError for bad input and std::runtime_error when the factorisation fails even so,
/// or CG fails.
ImmersedResult solve_immersed(const geometry::ImmersedDomain& domain,
                              const ImmersedOptions& options);

/// Displacement and its gradient (du_i/dx_j, zero beyond the dimension) at a physical point of
/// the background box (InputError outside it). Outside the part the value is the spline's
/// extension (basis functions that are no DOF count as zero): meaningful only on the part.
struct ImmersedPointValue {
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  Eigen::Matrix3d gradient = Eigen::Matrix3d::Zero();
};
ImmersedPointValue evaluate_immersed(const geometry::ImmersedDomain& domain,
                                     const ImmersedResult& result, const Eigen::Vector3d& x);
/// Stress (full 3x3, as stress_from_strain) at a physical point.
Eigen::Matrix3d immersed_stress(const geometry::ImmersedDomain& domain,
                                const ImmersedResult& result, const ImmersedOptions& options,
                                const Eigen::Vector3d& x);

}  // namespace isospring::analysis

namespace isospring::analysis {

/// The force the supports exert on the part, the consistent ("weak") reaction, as the body-fitted
/// solver's K u - f summed over the supported DOFs: a(u, psi e_c) - l(psi e_c) for each component
/// c, with psi the sum of the background basis functions that do not vanish in the cells holding
/// support points (so psi = 1 on those cells) and l the loads (body force, gravity, tractions,
/// pressures). For the exact solution it is the integral of sigma n over the supports. For the
/// discrete one, psi's gradient vanishes on the supports, so it equals minus the total load up
/// to the ghost penalty's share a_g(u, psi e_c): it checks the load's quadrature and the solve,
/// not the stress at the support (integrating the computed traction there converges only about
/// like h, because the stress is least accurate where a support meets a free surface).
Eigen::Vector3d immersed_reaction(const geometry::ImmersedDomain& domain,
                                  const ImmersedResult& result, const ImmersedOptions& options);

}  // namespace isospring::analysis
