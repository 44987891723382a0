#pragma once
// The measured-data loop (identify.hpp) on an immersed part: a CAD solid in a B-spline
// background grid (analysis/immersed.hpp). The loop, its statistics and its reports are the
// body-fitted ones; only the forward model's parts come from the immersed assembly:
//
// - Stiffness: assemble_immersed's K (bulk over the part, symmetric Nitsche terms of the held
//   faces, ghost penalty) at the prior modulus, K(theta) = theta[0] K. Every part of it scales
//   with E at a fixed nu: the bulk and the Nitsche consistency terms are linear in the Lame
//   parameters, the ghost penalty in lambda + 2 mu, and the Nitsche penalty beta_K is a
//   generalised eigenvalue of a form quadratic in sigma over one linear in it. The Poisson ratio
//   is therefore not fitted (the penalty is not linear in lambda and mu apart): fit_poisson is an
//   InputError.
// - Supports: Nitsche's, inside K (no DOF is prescribed). Support values must be zero, so that
//   each case's right-hand side is its load alone (load_scale scales it).
// - Loads: each case's right-hand side of assemble_immersed (tractions and pressures on the
//   exact faces, body force and gravity over the part); the self-weight of a unit gravity per
//   axis for the gravity effect, the same assembly with g = e_c.
// - Observations: the background B-spline basis at each marker (the part's own field; basis
//   functions that are no DOF, outside the part, count as zero as in evaluate_immersed). A
//   marker must lie in a background cell the part meets (otherwise the field there is the
//   extension of the spline, not the part's): immersed_markers_outside lists those that do not.
//
// Effects with an immersed form: gravity, rigid_offset, load_scale, rigid_offset_per_load.
// support_compliance, stiffness_gradient and geometric_nonlinearity are listed as unavailable
// with the reason (immersed_unavailable_effect). The discretisation check runs on a ladder of
// background grids (identify_immersed_check.hpp); without one, the result's discretization.note
// says it was not done.
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/immersed_calibration.hpp"

namespace isospring::fitting {

/// Why `effect` has no immersed form; empty when it has one.
std::string immersed_unavailable_effect(const std::string& effect);

/// Indices of the markers that do not lie in a background cell the part meets (or lie outside
/// the background grid).
std::vector<int> immersed_markers_outside(const geometry::ImmersedDomain& domain,
                                          const std::vector<Marker>& markers);

/// Runs the loop on the immersed model: `cases` as calibrate_immersed takes them (one per load
/// case, the same material and supports in each, support values zero). Throws nurbs::InputError
/// for markers off the part, an unknown load case id, differing supports or materials,
/// fit_poisson, and the errors of identify().
IdentifyResult identify_immersed(const geometry::ImmersedDomain& domain,
                                 const std::vector<ImmersedCalibrationCase>& cases,
                                 const std::vector<Marker>& markers,
                                 const IdentifyOptions& options = {});

/// The model displacement at every marker with the cases' material and the given effects at the
/// given values (simulate_markers for an immersed model): for synthetic data and checks.
std::vector<Eigen::Vector3d> simulate_immersed_markers(
    const geometry::ImmersedDomain& domain, const std::vector<ImmersedCalibrationCase>& cases,
    const std::vector<Marker>& markers,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects);

}  // namespace isospring::fitting
