#pragma once
// The fields of an IGA solution for VTK output, one set per load case `<id>`:
//
//   displacement_<id>           control field (3): exact on the sampled grid, the Bezier cells
//                               and the control net (the control-point displacements)
//   stress_<id>                 evaluated (9, row-major Cauchy stress; 2D: szz = 0 in plane
//                               stress, nu (sxx + syy) in plane strain)
//   von_mises_<id>              evaluated (1)
//   strain_energy_density_<id>  evaluated (1): 1/2 sigma : epsilon [J/m^3]
//
// Evaluated fields come from analysis::evaluate_field at the sampled parameters, so they are
// the library's own post-processing values (written on the sampled geometry only). At a
// degenerate point of the parametrisation (det J = 0, e.g. the collapsed corner of the 1-patch
// plate with a hole) stress, von Mises and energy density are NaN: undefined there.
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/vtk_fields.hpp"

namespace isospring::io {

/// The problem is copied into the callbacks, which may outlive the caller's objects.
PatchFields solution_fields(const analysis::Problem& problem,
                            const std::vector<analysis::LoadCaseResult>& load_cases);

}  // namespace isospring::io
