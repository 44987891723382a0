// Richardson extrapolation from three refinement levels.
#include "isospring/analysis/richardson.hpp"

#include <cmath>
#include <stdexcept>

#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

Richardson richardson_extrapolation(double q_coarse, double q_middle, double q_fine, double ratio,
                                    double round_off) {
  if (!(ratio > 1.0) || !std::isfinite(ratio))
    throw nurbs::InputError("Richardson extrapolation: the refinement ratio must exceed 1, got " +
                            std::to_string(ratio));
  if (!std::isfinite(q_coarse) || !std::isfinite(q_middle) || !std::isfinite(q_fine))
    throw std::runtime_error("Richardson extrapolation: a level's value is not finite");
  Richardson r;
  const double d1 = q_middle - q_coarse, d2 = q_fine - q_middle;
  r.value = q_fine;
  r.order = NAN;
  r.error_estimate = std::abs(d2);
  if (std::abs(d2) <= round_off * std::abs(q_fine)) {
    r.status = Richardson::Status::kConverged;
    return r;
  }
  if (d1 * d2 <= 0.0) {  // d1 == 0 with d2 != 0 is no convergence either
    r.status = d1 == 0.0 ? Richardson::Status::kDiverging : Richardson::Status::kOscillating;
    return r;
  }
  const double order = std::log(d1 / d2) / std::log(ratio);
  if (!(order > 0.0)) {
    r.status = Richardson::Status::kDiverging;
    return r;
  }
  r.status = Richardson::Status::kExtrapolated;
  r.order = order;
  r.value = q_fine + d2 / (std::pow(ratio, order) - 1.0);
  r.error_estimate = std::abs(q_fine - r.value);
  return r;
}

std::string status_name(Richardson::Status status) {
  switch (status) {
    case Richardson::Status::kExtrapolated:
      return "extrapolated";
    case Richardson::Status::kConverged:
      return "converged";
    case Richardson::Status::kOscillating:
      return "oscillating";
    case Richardson::Status::kDiverging:
      return "diverging";
  }
  return "unknown";
}

}  // namespace isospring::analysis
