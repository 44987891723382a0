#pragma once
// Load cases that span a supported object's deformation modes, generated from its supports, for
// calibrating a spring model that must hold on loads it was never fitted to (issue 14).
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
// Training and validation: of the loads of the i-th free side (sides in patch, dir, end order;
// kinds x, y, (z), twist) the kind i mod kinds is validation, rotating through the kinds, and so
// is the self-weight along the first axis; the rest is training. So every side and every kind of
// load appears in both sets (a fixed stride would hold out the same kind on every side), and
// validation cases are never fitted.
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
  /// false: every case is training.
  bool validation = true;
};

struct LoadSuite {
  std::vector<analysis::LoadCase> cases;  // ids: "p0_u1_x", "p0_u1_twist", "gravity_y", ...
  std::vector<std::string> training, validation;  // ids of `cases`
};

/// Generates the suite for `problem`'s patches and supports (its own load cases are ignored).
/// Throws nurbs::InputError when the model has no free side and self-weight is off (nothing to
/// load) or the options are invalid.
LoadSuite generate_load_suite(const analysis::Problem& problem, const LoadSuiteOptions& options);

}  // namespace isospring::fitting
