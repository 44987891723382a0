// What the load effects read of a model: assembled from the body-fitted problem, or given with a
// model that has none (an immersed part, whose loads the immersed assembly integrates).
#include <stdexcept>

#include "isospring/analysis/assembly.hpp"
#include "isospring/fitting/effect.hpp"

namespace isospring::fitting {

std::vector<std::string> load_case_ids(const EffectContext& context) {
  if (context.loads) return context.loads->case_ids;
  std::vector<std::string> ids;
  for (const auto& load : context.problem->load_cases) ids.push_back(load.id);
  return ids;
}

Eigen::VectorXd load_case_force(const EffectContext& context, size_t l) {
  if (context.loads) return context.loads->case_forces.at(l);
  return analysis::assemble_load(*context.problem, *context.dofs,
                                 context.problem->load_cases.at(l));
}

Eigen::VectorXd unit_gravity_force(const EffectContext& context, int c) {
  if (context.loads) return context.loads->unit_gravity.at(static_cast<size_t>(c));
  analysis::LoadCase unit;
  unit.gravity[c] = 1.0;
  return analysis::assemble_load(*context.problem, *context.dofs, unit);
}

double model_density(const EffectContext& context) {
  return context.loads ? context.loads->density : context.problem->material.density;
}

}  // namespace isospring::fitting
