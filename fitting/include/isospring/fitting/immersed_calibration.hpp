#pragma once
// The NMSM calibration of an immersed part (a CAD solid in a B-spline background grid,
// analysis/immersed.hpp), the same fit as calibrate() on a body-fitted model:
//
// - Particles: the ACTIVE control points of the background grid, those whose basis function's
//   support meets the part (the DOFs of analysis::assemble_immersed, in its node order). The
//   stabilisation (ghost penalty) removes no DOF, so these are the control points the solve
//   keeps. A spring model needs a particle wherever the IGA field has a coefficient: the
//   reference is compared coefficient by coefficient, as on body-fitted models.
// - Springs: those of the body-fitted kinds (edges, face and body diagonals of every net cell;
//   with reach 2 every pair of every 3 x 3 x 3 block) on the background net, of the cells (and
//   blocks) whose corners are all active. Each active point lies in a complete cell (its own
//   element's (p + 1)^d block of control points is active), so no particle is left unconnected.
//   Volume and shear terms on the same complete cells.
// - Masses: the consistent mass integrated over the part only (the domain's cell quadrature),
//   lumped by row sums as the body-fitted path lumps it: m_a = rho int_part N_a
//   (analysis::immersed_lumped_mass); the masses sum to rho times the part's volume.
// - Supports: the reference holds a supported face weakly (Nitsche); the spring model holds the
//   particles of the control points whose basis functions reach that face (1e-3 of their peak or
//   more, analysis::immersed_face_control_points; on a face lying on the grid's boundary, that
//   side's layer of the net, as body-fitted; on a cut face, the control points of the cells it
//   crosses whose functions reach it). Fixed components are held; a symmetry face holds the
//   component of its normal, which must be a coordinate axis (the spring model holds components,
//   not directions). Support values must be zero.
// - Loads: the consistent load vector of each case (tractions and pressures on the part's faces,
//   body force and gravity over the part), assemble_immersed's right-hand side, per particle.
// - Reference: the immersed IGA solution's control-point displacements at the active control
//   points (solve_immersed's system and Cholesky solve; the system is assembled and factorised
//   once, and each further case's load alone, analysis::assemble_immersed_loads); the fit and the
//   control-point metrics compare these coefficients with the particles' displacements, as
//   calibrate() compares the body-fitted coefficients. Because the reference holds its supports
//   weakly, its coefficients at held particles are small but not zero.
// - Metrics: control points as calibrate(); "field" and "surface" are the spline fields of both
//   coefficient sets over the part: volume-weighted over the cells' quadrature points, and
//   area-weighted over the boundary quadrature points (percent_e_rms = 100 sqrt(int |e|^2 /
//   int 1) / o_max, percent_e_max and o_max over the same points).
//
// Not for immersed models (each a nurbs::InputError naming the setting): the matrix approach and
// the stiffness upper bounds (they need a body-fitted IGA stiffness and net cells), net-cell
// masses, strain-point terms and given reference displacements.
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/fitting/calibration.hpp"

namespace isospring::fitting {

/// One load case of an immersed model: its id and the solver options of that case (material,
/// supports and its loads), as io::immersed_options gives them. Every case must have the same
/// material and supports.
struct ImmersedCalibrationCase {
  std::string id;
  analysis::ImmersedOptions options;
};

struct ImmersedCalibrationResult {
  /// As calibrate()'s: the calibrated mesh (mesh.particle[0][cp] is the particle of background
  /// control point cp, -1 when inactive), the errors per fitted and held-out case, the sweep,
  /// the particle loads.
  CalibrationResult calibration;
  /// The background control point of each particle.
  std::vector<int> control_point_of_particle;
  /// Per load case (the order of `cases`): the immersed IGA solution, the reference (as
  /// solve_immersed gives it, without strain_energy and the timings).
  std::vector<analysis::ImmersedResult> reference;
  /// Per load case: the spring model's particle displacements under its load, evaluated on the
  /// background's control points (zero where inactive), for the spline field of the model.
  std::vector<std::vector<Eigen::Vector3d>> model_control_displacements;
  int held_particles = 0;         // particles with at least one held component
  double assembly_seconds = 0.0;  // assemble_immersed once and the further cases' loads
                                  // (reference_seconds: the solves)
};

/// Calibrates the spring model of `domain` against its immersed solutions. Throws
/// nurbs::InputError for bad settings (unknown case ids, settings without an immersed form, a
/// non-zero support value, a symmetry face not normal to an axis, cases whose supports differ)
/// and std::runtime_error as calibrate() (a failed solve or fit).
ImmersedCalibrationResult calibrate_immersed(const geometry::ImmersedDomain& domain,
                                             const std::vector<ImmersedCalibrationCase>& cases,
                                             const CalibrationSettings& settings);

}  // namespace isospring::fitting
