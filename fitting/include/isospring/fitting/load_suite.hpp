#pragma once
// Load cases that span a supported object's deformation modes, generated from its supports, for
// calibrating a spring model that must hold on loads it was never fitted to.
//
// A model fitted to one load case interpolates that case and can be far off on the next: the
// fitted error says nothing about generalisation. The suite loads every free side of the model
// (a side that is neither supported nor inside the model: interfaces, seams, collapsed axes and
// poles are skipped) with a uniform traction along every coordinate axis (tension or compression
// where the axis is the side's normal, shear and bending where it is tangential), twists every
// free side about its own normal (torsion; in-plane moment for membranes), and adds self-weight
// along every axis. Loads of opposite sign give the mirrored response of a linear model, so one
// sign per direction suffices.
//
// Training: all of the above. Validation: loads of a different distribution, so that no
// validation case is a combination of training cases: on every free side a traction along the
// oblique direction (1, 1, 1) (membranes (1, 1)) that grows linearly with the distance from the
// side's centre ("ramp"), and self-weight along the oblique direction. Every mode stays in
// training (holding out, say, the axial pull of the loaded end would test a mode the model never
// saw, not its calibration), and validation cases are never fitted.
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"

namespace isospring::fitting {

struct LoadSuiteOptions {
  /// Traction magnitude [Pa] of the axis and twist cases (twist: at unit distance from the side's
  /// centre) and gravity [m/s^2] of the self-weight cases. The spring model and the reference
  /// are linear and every error is relative to the case's largest displacement, so the value
  /// only sets the printed displacements.
  double traction = 1000.0;
  double gravity = 9.81;
  bool axis_tractions = true;
  bool twists = true;
  bool self_weight = true;
  /// false: no validation cases.
  bool validation = true;
};

struct LoadSuite {
  // ids: "p0_u1_x", "p0_u1_twist", "gravity_y", ...; validation "p0_u1_ramp", "gravity_oblique"
  std::vector<analysis::LoadCase> cases;
  std::vector<std::string> training, validation;  // ids of `cases`
};

/// Generates the suite for `problem`'s patches and supports (its own load cases are ignored).
/// Throws nurbs::InputError when the model has no free side and self-weight is off (nothing to
/// load) or the options are invalid.
LoadSuite generate_load_suite(const analysis::Problem& problem, const LoadSuiteOptions& options);

}  // namespace isospring::fitting
