// Recalibration of the spring model against the identified (corrected) model.
#include "isospring/fitting/identify_recalibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/fitting/effect.hpp"
#include "quiet_solver_warnings.hpp"

namespace isospring::fitting {

namespace {

// Every declared load of the case times `factor` (load_scale scales the whole nominal load).
void scale_load_case(analysis::LoadCase& load, double factor) {
  for (auto& traction : load.tractions) {
    traction.value *= factor;
    if (traction.function) {
      auto nominal = traction.function;
      traction.function = [nominal, factor](const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
        return Eigen::Vector3d(factor * nominal(x, n));
      };
    }
  }
  for (auto& pressure : load.pressures) pressure.value *= factor;
  for (auto& point : load.point_loads) point.force *= factor;
  load.body_force *= factor;
  load.gravity *= factor;
}

}  // namespace

Recalibration recalibrate_identified(const analysis::Problem& prior, const IdentifyResult& result,
                                     CalibrationSettings settings) {
  // The spring fits' trial steps that leave the physical range are rejected and shortened, as
  // in identify: not news for the user (they reached the terminal as glog warnings).
  const QuietSolverWarnings quiet;
  if (result.corrected_displacements.size() != prior.load_cases.size())
    throw std::invalid_argument(
        "recalibrate_identified: the identification has no corrected "
        "reference for every load case");
  Recalibration out;
  out.corrected = prior;
  out.corrected.material.youngs_modulus = result.youngs_modulus;
  out.corrected.material.poisson_ratio = result.poisson_ratio;
  // Each effect carries itself over (its EffectType, effect_<name>.cpp); its note is the one
  // identify printed for it.
  SpringModelChanges changes;
  for (const auto& [name, values] : result.effect_values)
    out.notes.push_back(carry_over(name, values, changes));
  if (changes.load_factors.size() > prior.load_cases.size())
    throw std::invalid_argument("recalibrate_identified: load factors for " +
                                std::to_string(changes.load_factors.size()) +
                                " load cases, the "
                                "problem has " +
                                std::to_string(prior.load_cases.size()));
  out.gravity = changes.gravity;
  out.load_factors.assign(prior.load_cases.size(), 1.0);
  std::copy(changes.load_factors.begin(), changes.load_factors.end(), out.load_factors.begin());
  for (size_t l = 0; l < out.corrected.load_cases.size(); ++l) {
    scale_load_case(out.corrected.load_cases[l], out.load_factors[l]);
    out.corrected.load_cases[l].gravity += out.gravity;
  }

  settings.reference_displacements = result.corrected_displacements;
  settings.fit_cases.clear();
  settings.holdout_cases.clear();
  if (changes.lumped_masses) settings.mass_model = MassModel::kLumpedIga;
  // A carry-through that fails only because the grouped fit did not converge within its
  // iterations degrades to coarser groupings (fewer stiffnesses: larger gamma), saying so,
  // before giving up: the identification's result should reach model.json on routine cases.
  std::vector<double> gammas{settings.gamma};
  for (const double g : {10 * settings.gamma, 0.1, 0.3, 0.5})
    if (g > gammas.back() && g <= 0.5) gammas.push_back(g);
  for (size_t k = 0; k < gammas.size(); ++k) {
    CalibrationSettings attempt = settings;
    if (k > 0) {
      attempt.gamma = gammas[k];
      attempt.gamma_sweep.clear();
    }
    try {
      out.calibration = calibrate(out.corrected, attempt);
      if (k > 0)
        out.notes.push_back("recalibration: the grouped fit did not converge with gamma " +
                            std::to_string(gammas[k - 1]) +
                            "; recalibrated with the coarser grouping gamma " +
                            std::to_string(gammas[k]) + " (fewer spring stiffnesses)");
      break;
    } catch (const std::runtime_error& e) {
      if (k + 1 == gammas.size() ||
          std::string(e.what()).find("did not converge") == std::string::npos)
        throw;
    }
  }

  // The corrected loads without the carried gravity, on the particles (as calibrate builds them).
  const analysis::DofMap dofs(out.corrected);
  const int dim = dofs.dofs_per_node();
  const std::vector<int> particle = particle_of_node(out.corrected, out.calibration.mesh);
  const auto num_particles =
      static_cast<Eigen::Index>(out.calibration.mesh.network.positions.size());
  for (const auto& load : out.corrected.load_cases) {
    analysis::LoadCase without_gravity = load;
    without_gravity.gravity -= out.gravity;
    const Eigen::VectorXd nodal = analysis::assemble_load(out.corrected, dofs, without_gravity);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(num_particles * dim);
    for (size_t a = 0; a < particle.size(); ++a)
      f.segment(static_cast<Eigen::Index>(particle[a]) * dim, dim) +=
          nodal.segment(static_cast<Eigen::Index>(a) * dim, dim);
    out.particle_loads.push_back(f);
  }
  double sum = 0.0;
  for (const CaseErrors& e : out.calibration.fit) {
    sum += e.control.percent_e_rms * e.control.percent_e_rms;
    out.percent_e_max = std::max(out.percent_e_max, e.control.percent_e_max);
  }
  out.percent_e_rms =
      out.calibration.fit.empty() ? 0.0 : std::sqrt(sum / out.calibration.fit.size());
  return out;
}

}  // namespace isospring::fitting
