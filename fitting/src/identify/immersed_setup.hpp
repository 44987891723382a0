#pragma once
// The loop's setup of an immersed model (identify_immersed.cpp), shared with the immersed
// discretisation check (identify_immersed_check.cpp), which builds one per background grid.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "identify/loop_state.hpp"
#include "isospring/fitting/identify_immersed.hpp"
#include "isospring/fitting/identify_immersed_check.hpp"

namespace isospring::fitting::identify_loop {

/// Everything that stays fixed while effects come and go, from the immersed assembly of
/// `domain` (the domain is only read while the setup is made).
void make_immersed_setup(Setup& setup, const geometry::ImmersedDomain& domain,
                         const std::vector<ImmersedCalibrationCase>& cases,
                         const std::vector<Marker>& markers, bool fit_poisson,
                         const std::function<void(const std::string&)>& say);

/// The background control points whose functions reach a cell of the part (the active ones, as
/// the immersed assembly numbers them).
std::vector<bool> active_control_points(const geometry::ImmersedDomain& domain);

/// The discretisation check on `ladder` (identify_immersed_check.hpp) at the nominal fit's
/// parameters `theta`: fills `check` and returns the setup of the level chosen (null: the
/// case's own, `case_setup`, made from `domain`).
std::unique_ptr<Setup> run_immersed_check(
    const Setup& case_setup, const geometry::ImmersedDomain& domain,
    const std::vector<ImmersedCalibrationCase>& cases, const std::vector<Marker>& markers,
    const Eigen::VectorXd& theta, double noise, const DiscretizationOptions& options,
    const ImmersedLadder& ladder, const std::function<void(const std::string&)>& progress,
    DiscretizationCheck& check);

}  // namespace isospring::fitting::identify_loop
