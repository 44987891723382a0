// The effect library: the one list of effect types. Each effect_<name>.cpp defines its
// EffectType (name, factory, carry-over into the spring model); adding an effect is that file
// plus its two lines here (declaration and entry).
//
// Why an explicit list and not self-registration by static initialisers: the libraries are
// static (docs/architecture.md), and a linker takes an object file out of a static library only
// when something refers to one of its symbols. A self-registering effect file nothing refers to
// would be left out of every program, silently. The list here refers to every effect, so linking
// the registry links them all.
//
// The order is identify's candidate order (the selection tries candidates in it), so appending
// keeps the results of existing cases.
#include <string>
#include <vector>

#include "isospring/fitting/effect.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

EffectType gravity_effect_type();                 // effect_gravity.cpp
EffectType support_compliance_effect_type();      // effect_support_compliance.cpp
EffectType stiffness_gradient_effect_type();      // effect_stiffness_gradient.cpp
EffectType rigid_offset_effect_type();            // effect_rigid_offset.cpp
EffectType load_scale_effect_type();              // effect_load_scale.cpp
EffectType geometric_nonlinearity_effect_type();  // effect_geometric_nonlinearity.cpp
EffectType rigid_offset_per_load_effect_type();   // effect_rigid_offset.cpp

const std::vector<EffectType>& effect_types() {
  static const std::vector<EffectType> types{
      gravity_effect_type(),
      support_compliance_effect_type(),
      stiffness_gradient_effect_type(),
      rigid_offset_effect_type(),
      load_scale_effect_type(),
      geometric_nonlinearity_effect_type(),
      rigid_offset_per_load_effect_type(),
  };
  return types;
}

std::vector<std::string> effect_names() {
  std::vector<std::string> names;
  for (const EffectType& type : effect_types()) names.push_back(type.name);
  return names;
}

const EffectType& effect_type(const std::string& name) {
  for (const EffectType& type : effect_types())
    if (type.name == name) return type;
  std::string list;
  for (const std::string& n : effect_names()) list += (list.empty() ? "" : ", ") + n;
  throw nurbs::InputError("unknown effect \"" + name + "\"; the library has: " + list);
}

std::unique_ptr<Effect> make_effect(const std::string& name, const EffectContext& context,
                                    std::string* why) {
  const EffectType& type = effect_type(name);
  if (context.loads && context.loads->unavailable) {  // a model without a body-fitted problem
    const std::string reason = context.loads->unavailable(name);
    if (!reason.empty()) {
      if (why) *why = reason;
      return nullptr;
    }
  }
  return type.make(context, why);
}

std::string carry_over(const std::string& name, const Eigen::VectorXd& values,
                       SpringModelChanges& changes) {
  const CarryOverResult result = effect_type(name).carry_over(values, changes);
  // The words that say whether it was carried come from `how`, not from the effect's text, so
  // the note cannot say "carried" for an effect that changed nothing (tests check `how` against
  // the changes).
  const char* how = result.how == CarryOver::kModel       ? "carried "
                    : result.how == CarryOver::kReference ? "carried by the reference "
                                                          : "NOT carried ";
  return name + ": " + how + result.detail;
}

}  // namespace isospring::fitting
