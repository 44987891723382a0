// The engine step estimate (step_cost.hpp): the runtime's per-term costs summed over a model.
#include "isospring/fitting/step_cost.hpp"

#include <cstdio>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

double estimated_step_us(const analysis::SpringNetwork& network, const StepCosts& costs) {
  double us = costs.spring * static_cast<double>(network.springs.size());
  const bool plane = network.dimension == 2;
  for (const analysis::VolumeTerm& t : network.volumes) {
    if (!t.points.empty())
      us += costs.point_particle * static_cast<double>(t.points.size());
    else if (t.kind == analysis::CellEnergy::kShear)
      us += plane ? costs.cell_shear_2d : costs.cell_shear;
    else
      us += plane ? costs.cell_area_2d : costs.cell_volume;
  }
  return us;
}

void check_step_budget(const analysis::SpringNetwork& network, double max_step_us) {
  if (!(max_step_us > 0.0)) return;
  const double us = estimated_step_us(network);
  if (us <= max_step_us) return;
  char text[300];
  std::snprintf(text, sizeof(text),
                "max_step_us: the model (%zu springs, %zu volume, shear and strain-point terms) "
                "needs an estimated %.4g us per engine step, over the budget of %.4g us; offer "
                "cheaper model kinds (\"generalisation\": volume_terms, shear_terms, "
                "strain_points) or raise the budget",
                network.springs.size(), network.volumes.size(), us, max_step_us);
  throw nurbs::InputError(text);
}

}  // namespace isospring::fitting
