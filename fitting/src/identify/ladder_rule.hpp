// The discretisation check's acceptance rule, shared by the body-fitted ladder
// (discretization_check.cpp) and the immersed one (identify_immersed_check.cpp): given each
// level's predictions at the markers, the error estimates of the levels and which one is chosen.
// The ladders differ only in how a level is made and solved.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/fitting/discretization_check.hpp"

namespace isospring::fitting::ladder_rule {

/// "%.3g" of a value, for the check's notes and progress lines.
std::string format(double value);

struct Difference {
  double rms = 0.0, max = 0.0, rms_after_material = 0.0;
};

/// fine - coarse over the first `dim` components; "after material": fine - s coarse with the best
/// scale s (a refit of E scales every displacement by the same factor).
Difference difference(const std::vector<Eigen::Vector3d>& fine,
                      const std::vector<Eigen::Vector3d>& coarse, int dim);

/// The finest level's own error: from the last two differences D = u_{j+1} - u_j as a geometric
/// series, r |D_{K-1}| / (1 - r) with r = |D_{K-1}| / |D_{K-2}|, or |D_{K-1}| itself when there is
/// no such ratio, as when the last three levels are not all of one family
/// (DiscretizationOptions::ratio_from_level).
struct Tail {
  std::vector<Eigen::Vector3d> vector;  // per marker: estimated u_K - u_exact
  double rms = 0.0, max = 0.0;          // of `vector`
  double ratio = 0.0;                   // NaN when there is none
  std::string how;
  bool ratio_known() const { return ratio > 0.0 && ratio < 1.0; }
};

/// The levels' predictions at the markers (in check.levels order) and the rule applied to them.
class LadderRule {
 public:
  LadderRule(const DiscretizationOptions& options, int dim, DiscretizationCheck& check)
      : options_(options), dim_(dim), check_(check) {}

  /// Records a level's predictions (the caller appends its row to check.levels).
  void add(std::vector<Eigen::Vector3d> predictions) {
    predictions_.push_back(std::move(predictions));
  }

  /// Level 0 (the case's) against `finest`, rms.
  double case_error_rms(size_t finest) const {
    return difference(predictions_[finest], predictions_[0], dim_).rms;
  }

  /// The level chosen once `finest` is solved, or -1. A level is chosen only with a convergence
  /// ratio behind its estimate (two finer levels, or one whose own error is extrapolated from a
  /// ratio < 1); the finest on its extrapolated error alone when that is at most half the target.
  int choose_after(size_t finest) const;

  /// Every level's estimate against the finest; sets `chosen` when the ladder ended before a
  /// level met the target with two finer levels behind it (one finer level has to do), and the
  /// chosen level's per-marker error.
  void estimate_against_finest(size_t finest, int& chosen, const std::string& none);

  /// The outcome: the chosen level (the finest when none met the target), within target or not.
  void settle(size_t finest, int chosen);

  /// How a ladder names its first refinement in the budget's error: e.g. "no refinement of the
  /// case: its first refinement", "its", "the case is known to be converged".
  struct BudgetWording {
    std::string first, whose, fine_when;
  };

  /// Whether ladder level `level` with `dofs` DOFs fits DiscretizationOptions::max_dofs. Beyond
  /// it the check notes so and the ladder stops; for level 1 it is an input error, since without
  /// one finer level there is no estimate at all, and nothing to widen the F-tests by: running on
  /// would silently treat the case as converged.
  bool within_budget(int level, long dofs, const std::string& description,
                     const BudgetWording& wording);

  /// A level just added between the chosen one and the one before it: it replaces the chosen
  /// level when it is within the target too.
  void consider_intermediate(size_t finest);

 private:
  Tail tail_of(size_t finest) const;
  std::vector<Eigen::Vector3d> estimate(size_t k, size_t finest, const Tail& tail,
                                        DiscretizationLevel& row) const;

  const DiscretizationOptions& options_;
  const int dim_;
  DiscretizationCheck& check_;
  std::vector<std::vector<Eigen::Vector3d>> predictions_;
};

}  // namespace isospring::fitting::ladder_rule
