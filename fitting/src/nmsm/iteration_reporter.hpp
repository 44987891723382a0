#pragma once
// Forwards Ceres' per-iteration summary (iteration, cost) to a caller's progress function; shared
// by the displacement fits, linear and nonlinear.
#include <ceres/ceres.h>

#include <functional>

namespace isospring::fitting::detail {

class IterationReporter : public ceres::IterationCallback {
 public:
  explicit IterationReporter(const std::function<void(int, double)>& report) : report_(report) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    report_(summary.iteration, summary.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(int, double)>& report_;
};

}  // namespace isospring::fitting::detail
