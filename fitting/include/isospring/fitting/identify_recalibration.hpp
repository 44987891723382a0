#pragma once
// Carrying an identification through to the spring model: recalibrate the NMSM (calibration.hpp)
// against the corrected reference: the identified model with the identified E (and nu when
// fitted), and each added effect carried over by its own EffectType::carry_over (effect.hpp;
// fitting/src/identify/effect_<name>.cpp), which also writes the note of what it did:
//   gravity             g applied to every load case (the spring model's particles get m_i g;
//                       with row-sum lumped masses that is exactly the consistent IGA load)
//   load_scale          every load of case l scaled by (1 + s_l)
//   stiffness_gradient  carried by the reference: the springs are fitted to the displacements of
//                       E(x) = E (1 + a . (x - x_c) / L) (the identification's forward model)
//   rigid_offset(_per_load)  a measurement-frame effect: not part of the model
//   support_compliance  NOT carried: the spring model holds its supported particles fixed, so the
//                       support motion of the reference shows up in the reported %e_rms
//   geometric_nonlinearity  NOT carried: the springs are calibrated with the linear solver
// The reference displacements are the identification's (IdentifyResult::corrected_displacements),
// which for material, gravity and load factors equal analysis::solve_static of `corrected`.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/identify.hpp"

namespace isospring::fitting {

struct Recalibration {
  analysis::Problem corrected;  // identified material, gravity in every case, scaled loads
  CalibrationResult calibration;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // carried gravity [m/s^2]
  std::vector<double> load_factors;                   // per load case (1 for the first)
  /// Per load case: the corrected external load without gravity as forces on the particles
  /// (flat, particle * dimension + component) [N]; the gravity load is m_i * gravity.
  std::vector<Eigen::VectorXd> particle_loads;
  std::vector<std::string> notes;  // per added effect (carry_over's note), then the fit's own
  double percent_e_rms = 0.0;      // control points, root mean square over the load cases
  double percent_e_max = 0.0;      // control points, largest over the load cases
};

/// Recalibrates against the corrected reference. `settings` are used as given except that every
/// load case is fitted (no hold-out) and, when gravity is carried, the masses are row-sum lumped
/// (MassModel::kLumpedIga) so that m_i g is the self-weight the springs were fitted under.
/// Throws like fitting::calibrate.
Recalibration recalibrate_identified(const analysis::Problem& prior, const IdentifyResult& result,
                                     CalibrationSettings settings = {});

}  // namespace isospring::fitting
