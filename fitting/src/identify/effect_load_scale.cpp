// load_scale: the actual load factor (1 + s_l) of every load case but the first (the first one's
// is not separable from E).
#include <memory>
#include <string>

#include "isospring/fitting/effect.hpp"

namespace isospring::fitting {

namespace {

class LoadScale : public Effect {
 public:
  explicit LoadScale(const EffectContext& context) {
    const std::vector<std::string> ids = load_case_ids(context);
    for (size_t l = 1; l < ids.size(); ++l) {
      ids_.push_back(ids[l]);
      forces_.push_back(load_case_force(context, l));
    }
  }
  std::string name() const override { return "load_scale"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (const std::string& id : ids_) names.push_back(id + ".s");
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    return std::vector<std::string>(ids_.size(), "1");
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    for (size_t k = 0; k < ids_.size(); ++k)
      terms.loads.push_back(
          {static_cast<int>(k + 1), forces_[k], linear_coefficient(first + static_cast<int>(k))});
  }

 private:
  std::vector<std::string> ids_;
  std::vector<Eigen::VectorXd> forces_;  // nominal load of load cases 2..L
};

}  // namespace

EffectType load_scale_effect_type() {
  EffectType type;
  type.name = "load_scale";
  type.make = [](const EffectContext& context, std::string* why) -> std::unique_ptr<Effect> {
    if (load_case_ids(context).size() < 2) {
      if (why) *why = "one load case: its load factor cannot be told apart from E";
      return nullptr;
    }
    return std::make_unique<LoadScale>(context);
  };
  // The springs are fitted under the loads that were actually applied: s_l belongs to load case
  // l + 1 (the first case's factor is 1, absorbed in E).
  type.carry_over = [](const Eigen::VectorXd& values, SpringModelChanges& changes) {
    const auto needed = static_cast<size_t>(values.size()) + 1;
    if (changes.load_factors.size() < needed) changes.load_factors.resize(needed, 1.0);
    std::string factors;
    for (Eigen::Index k = 0; k < values.size(); ++k) {
      changes.load_factors[static_cast<size_t>(k) + 1] *= 1.0 + values[k];
      factors += (factors.empty() ? "" : ", ") + std::to_string(1.0 + values[k]);
    }
    return CarryOverResult{CarryOver::kModel, "as scaled loads of the load cases (factors " +
                                                  factors + " for the load cases after the first)"};
  };
  return type;
}

}  // namespace isospring::fitting
