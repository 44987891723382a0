#pragma once
// Validation of primitive parameters: every failure is an InputError naming the parameter.
#include <cmath>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::geometry::detail {

inline void require_positive(double value, const char* primitive, const char* name) {
  if (!(std::isfinite(value) && value > 0.0))
    throw nurbs::InputError(std::string(primitive) + ": " + name +
                            " must be a positive number, got " + std::to_string(value));
}

inline void require_less(double smaller, double larger, const char* primitive,
                         const char* smaller_name, const char* larger_name) {
  if (!(smaller < larger))
    throw nurbs::InputError(std::string(primitive) + ": " + smaller_name + " (" +
                            std::to_string(smaller) + ") must be smaller than " + larger_name +
                            " (" + std::to_string(larger) + ")");
}

inline void require_sweep(double sweep, double max, const char* primitive, const char* name) {
  if (!(std::isfinite(sweep) && sweep > 0.0 && sweep <= max + 1e-12))
    throw nurbs::InputError(std::string(primitive) + ": " + name + " must be in (0, " +
                            std::to_string(max) + "] radians, got " + std::to_string(sweep));
}

}  // namespace isospring::geometry::detail
