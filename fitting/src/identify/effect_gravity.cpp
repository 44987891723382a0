// gravity: the self-weight rho * g of the declared density, g fitted (2 or 3 components).
#include <memory>
#include <string>

#include "isospring/fitting/effect.hpp"

namespace isospring::fitting {

namespace {

class Gravity : public Effect {
 public:
  explicit Gravity(const EffectContext& context) : dimension_(context.dimension) {
    for (int c = 0; c < dimension_; ++c) forces_.push_back(unit_gravity_force(context, c));
  }
  std::string name() const override { return "gravity"; }
  std::vector<std::string> parameter_names() const override {
    const char* axes = "xyz";
    std::vector<std::string> names;
    for (int c = 0; c < dimension_; ++c) names.push_back(std::string("g") + axes[c]);
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    return std::vector<std::string>(static_cast<size_t>(dimension_), "m/s^2");
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    for (int c = 0; c < dimension_; ++c)
      terms.loads.push_back({-1, forces_[static_cast<size_t>(c)], linear_coefficient(first + c)});
  }
  std::vector<std::pair<std::string, double>> derived(
      const Eigen::VectorXd& values) const override {
    return {{"|g| [m/s^2]", values.norm()}};
  }

 private:
  int dimension_;
  std::vector<Eigen::VectorXd> forces_;  // load of a unit gravity along each axis
};

}  // namespace

EffectType gravity_effect_type() {
  EffectType type;
  type.name = "gravity";
  type.make = [](const EffectContext& context, std::string* why) -> std::unique_ptr<Effect> {
    if (!(model_density(context) > 0.0)) {
      if (why) *why = "the material has no density (set material.density)";
      return nullptr;
    }
    return std::make_unique<Gravity>(context);
  };
  // The fitted g is added to every load case; the particles get m_i g, which equals the
  // consistent self-weight sum_b M_ab g only for row-sum lumped masses.
  type.carry_over = [](const Eigen::VectorXd& values, SpringModelChanges& changes) {
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (Eigen::Index c = 0; c < values.size() && c < 3; ++c) g[c] = values[c];
    changes.gravity += g;
    changes.lumped_masses = true;
    return CarryOverResult{CarryOver::kModel, "as forces m_i g on every particle, g = (" +
                                                  std::to_string(g.x()) + ", " +
                                                  std::to_string(g.y()) + ", " +
                                                  std::to_string(g.z()) + ") m/s^2"};
  };
  return type;
}

}  // namespace isospring::fitting
