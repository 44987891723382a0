// The discretisation check's acceptance rule (ladder_rule.hpp).
#include "ladder_rule.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "isospring/nurbs/error.hpp"

namespace isospring::fitting::ladder_rule {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::string format(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

Difference difference(const std::vector<Eigen::Vector3d>& fine,
                      const std::vector<Eigen::Vector3d>& coarse, int dim) {
  Difference d;
  double sum = 0.0, fc = 0.0, cc = 0.0, ff = 0.0;
  for (size_t m = 0; m < fine.size(); ++m)
    for (int c = 0; c < dim; ++c) {
      const double e = fine[m][c] - coarse[m][c];
      sum += e * e;
      d.max = std::max(d.max, std::abs(e));
      fc += fine[m][c] * coarse[m][c];
      cc += coarse[m][c] * coarse[m][c];
      ff += fine[m][c] * fine[m][c];
    }
  const double n = std::max<double>(1.0, static_cast<double>(fine.size() * dim));
  d.rms = std::sqrt(sum / n);
  const double projected = cc > 0.0 ? std::max(0.0, ff - fc * fc / cc) : ff;
  d.rms_after_material = std::sqrt(projected / n);
  return d;
}

Tail LadderRule::tail_of(size_t finest) const {
  Tail t;
  t.ratio = kNaN;
  const size_t markers = predictions_[finest].size();
  t.vector.assign(markers, Eigen::Vector3d::Zero());
  if (finest == 0) return t;
  const Difference last = difference(predictions_[finest], predictions_[finest - 1], dim_);
  double scale = 1.0;
  t.how = "no convergence ratio: its error taken as the last difference";
  if (finest >= 2 && static_cast<int>(finest) - 2 >= options_.ratio_from_level) {
    const Difference before = difference(predictions_[finest - 1], predictions_[finest - 2], dim_);
    t.ratio = before.rms > 0.0 ? last.rms / before.rms : kNaN;
    if (t.ratio_known()) {
      scale = t.ratio / (1.0 - t.ratio);
      t.how = "its error extrapolated with ratio " + format(t.ratio);
    } else if (t.ratio >= 1.0) {
      t.how =
          "not converging (ratio " + format(t.ratio) + "): its error taken as the last difference";
    }
  }
  for (size_t m = 0; m < markers; ++m)
    t.vector[m] = scale * (predictions_[finest][m] - predictions_[finest - 1][m]);
  t.rms = scale * last.rms;
  t.max = scale * last.max;
  return t;
}

// u_k - u_exact ~ (u_k - u_K) + tail, as a per-marker vector; its size by the triangle
// inequality (rms and max of |u_k - u_K| plus those of the tail), an upper-bound estimate.
std::vector<Eigen::Vector3d> LadderRule::estimate(size_t k, size_t finest, const Tail& tail,
                                                  DiscretizationLevel& row) const {
  const Difference to_finest = difference(predictions_[finest], predictions_[k], dim_);
  row.error_rms = to_finest.rms + tail.rms;
  row.error_max = to_finest.max + tail.max;
  row.error_rms_after_material = to_finest.rms_after_material + tail.rms;
  row.estimate = k == finest
                     ? "finest level solved, " + tail.how
                     : "difference to level " + std::to_string(finest) + " (" + tail.how + ")";
  std::vector<Eigen::Vector3d> error(predictions_[k].size());
  for (size_t m = 0; m < error.size(); ++m)
    error[m] = predictions_[k][m] - predictions_[finest][m] + tail.vector[m];
  return error;
}

// A ladder's first steps can be pre-asymptotic (degree elevation on one element through a
// thickness stalls), and one difference alone then underestimates the error; hence a ratio
// behind every choice. The finest level on its extrapolated error alone (Richardson:
// r |D| / (1 - r)) when that is at most half the target: the factor 2 covers a ratio that is
// still pre-asymptotic, and the next level, the ladder's largest solve by far (a degree-3 solid
// grows 4.6x per step), is not needed to certify it.
int LadderRule::choose_after(size_t finest) const {
  constexpr double kRichardsonMargin = 0.5;
  const Tail tail = tail_of(finest);
  // Candidates: every level with two finer ones; level finest - 1 too when the finest level's
  // own error comes from a convergence ratio.
  const size_t candidates = tail.ratio_known() ? finest : finest - 1;  // levels 0 .. candidates-1
  for (size_t k = 0; k < candidates; ++k) {
    DiscretizationLevel row;
    estimate(k, finest, tail, row);
    if (row.error_rms <= check_.target) return static_cast<int>(k);
  }
  if (tail.ratio_known() && tail.rms <= kRichardsonMargin * check_.target)
    return static_cast<int>(finest);
  return -1;
}

void LadderRule::estimate_against_finest(size_t finest, int& chosen, const std::string& none) {
  if (finest == 0) {
    check_.levels[0].estimate = none;  // errors stay NaN
    return;
  }
  const Tail tail = tail_of(finest);
  for (size_t k = 0; k <= finest; ++k) {
    std::vector<Eigen::Vector3d> error = estimate(k, finest, tail, check_.levels[k]);
    if (chosen < 0 && k < finest && check_.levels[k].error_rms <= check_.target)
      chosen = static_cast<int>(k);
    if (static_cast<int>(k) == chosen || (chosen < 0 && k == finest))
      check_.marker_error = std::move(error);
  }
}

void LadderRule::settle(size_t finest, int chosen) {
  check_.done = true;
  check_.within_target = chosen >= 0;
  check_.chosen = chosen >= 0 ? chosen : static_cast<int>(finest);
  if (chosen < 0 && finest > 0 &&
      check_.levels[finest].error_rms <= check_.target) {  // only the extrapolated tail is in
    check_.within_target = true;
    check_.note += "; the finest level's extrapolated error is in target";
  }
  if (check_.within_target) check_.budget_exhausted = false;  // the budget did not matter
}

bool LadderRule::within_budget(int level, long dofs, const std::string& description,
                               const BudgetWording& wording) {
  if (dofs <= options_.max_dofs) return true;
  if (level == 1)
    throw nurbs::InputError("the DOF budget (max_dofs " + std::to_string(options_.max_dofs) +
                            ") allows " + wording.first + " (" + description + ") has " +
                            std::to_string(dofs) + " DOFs, so " + wording.whose +
                            " discretisation error cannot be estimated; raise max_dofs "
                            "(measurements.max_dofs or --max-dofs) to at least " +
                            std::to_string(dofs) +
                            ", or turn the check off (measurements.discretization_check false or "
                            "--no-discretization-check) if " +
                            wording.fine_when);
  check_.budget_exhausted = true;
  check_.note = "the next level (" + description + ", " + std::to_string(dofs) +
                " DOFs) exceeds the DOF budget of " + std::to_string(options_.max_dofs);
  return false;
}

void LadderRule::consider_intermediate(size_t finest) {
  const size_t k = check_.levels.size() - 1;
  std::vector<Eigen::Vector3d> error = estimate(k, finest, tail_of(finest), check_.levels[k]);
  if (check_.levels[k].error_rms <= check_.target) {
    check_.chosen = static_cast<int>(k);
    check_.marker_error = std::move(error);
  }
}

}  // namespace isospring::fitting::ladder_rule
