#pragma once
// The geometric_nonlinearity effect (effect_geometric_nonlinearity.cpp).
#include <memory>

#include "isospring/fitting/effect.hpp"

namespace isospring::fitting {

std::unique_ptr<Effect> make_geometric_nonlinearity(const EffectContext& context);

}  // namespace isospring::fitting
