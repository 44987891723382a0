// The discretisation check on an immersed model (identify_immersed_check.hpp): the body-fitted
// check's acceptance rule (discretization_check.cpp) on a ladder of re-immersed background grids.
// Each level is a loop setup of its own (make_immersed_setup), so the level chosen is handed to
// the loop as it is.
#include "isospring/fitting/identify_immersed_check.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "identify/immersed_setup.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace identify_loop {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string format(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// "degree 2, 10 x 5 x 5 cells" of a domain's background grid.
std::string grid_label(const geometry::ImmersedDomain& domain) {
  const nurbs::Patch& grid = domain.background;
  std::string cells;
  for (int d = 0; d < grid.param_dim(); ++d)
    cells += (d ? " x " : "") + std::to_string(grid.knots(d).num_elements());
  return "degree " + std::to_string(grid.degree(0)) + ", " + cells + " cells";
}

long active_dofs(const geometry::ImmersedDomain& domain) {
  long nodes = 0;
  for (bool a : active_control_points(domain)) nodes += a ? 1 : 0;
  return nodes * domain.dimension;
}

struct Difference {
  double rms = 0.0, max = 0.0, rms_after_material = 0.0;
};

// fine - coarse over the first `dim` components; "after material": fine - s coarse with the best
// scale s (a refit of E scales every displacement by the same factor). As the body-fitted check.
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

// The finest level's own error (the Richardson tail), as in discretization_check.cpp.
struct Tail {
  std::vector<Eigen::Vector3d> vector;  // per marker: estimated u_K - u_exact
  double rms = 0.0, max = 0.0;
  double ratio = kNaN;
  std::string how;
};

// One run of the check, as its stages (run()): the levels solved so far are setups of their own
// (null for level 0, the case's) and their predictions at the markers at the nominal fit.
class ImmersedLadderRun {
 public:
  ImmersedLadderRun(const Setup& case_setup, const std::vector<ImmersedCalibrationCase>& cases,
                    const std::vector<Marker>& markers, const Eigen::VectorXd& theta,
                    const DiscretizationOptions& options, const ImmersedLadder& ladder,
                    const std::function<void(const std::string&)>& progress,
                    DiscretizationCheck& check)
      : case_setup_(case_setup),
        cases_(cases),
        markers_(markers),
        theta_(theta),
        options_(options),
        ladder_(ladder),
        progress_(progress),
        check_(check) {}

  std::unique_ptr<Setup> run(const geometry::ImmersedDomain& domain) {
    say("discretisation check: the case's grid (" + grid_label(domain) + ")");
    add_level(nullptr, "the case's grid (" + grid_label(domain) + ")", 0.0);
    climb();
    estimate_against_finest();
    settle();
    try_intermediate();
    check_.done = true;
    return std::move(setups_[static_cast<size_t>(check_.chosen)]);
  }

 private:
  void say(const std::string& s) const {
    if (progress_) progress_(s);
  }
  const Setup& setup_of(size_t k) const { return setups_[k] ? *setups_[k] : case_setup_; }
  void add_level(std::unique_ptr<Setup> setup, const std::string& description, double seconds);
  bool solve_next(int level);
  bool solve_level(ImmersedLevel level, std::chrono::steady_clock::time_point start);
  Tail tail_of(size_t finest) const;
  std::vector<Eigen::Vector3d> estimate(size_t k, size_t finest, const Tail& tail,
                                        DiscretizationLevel& row) const;
  void climb();
  void estimate_against_finest();
  void settle();
  void try_intermediate();

  const Setup& case_setup_;
  const std::vector<ImmersedCalibrationCase>& cases_;
  const std::vector<Marker>& markers_;
  const Eigen::VectorXd& theta_;
  const DiscretizationOptions& options_;
  const ImmersedLadder& ladder_;
  const std::function<void(const std::string&)>& progress_;
  DiscretizationCheck& check_;
  std::vector<std::unique_ptr<Setup>> setups_;  // per level; null: the case's setup
  std::vector<std::vector<Eigen::Vector3d>> predictions_;
  size_t finest_ = 0;
  int chosen_ = -1;
};

// Appends a level's row and its predictions at the markers (the nominal fit's theta).
void ImmersedLadderRun::add_level(std::unique_ptr<Setup> setup, const std::string& description,
                                  double seconds) {
  const auto start = std::chrono::steady_clock::now();
  const Setup& s = setup ? *setup : case_setup_;
  {
    const Model model = build_model(s, {}, Eigen::VectorXd());
    predictions_.push_back(marker_predictions(s, model, theta_, markers_.size()));
  }
  // The loop factorises the chosen level again; the others' factors would only hold memory.
  if (setup) setup->factorizations = make_factorization_cache();
  DiscretizationLevel row;
  row.level = static_cast<int>(check_.levels.size());
  row.description = description;
  row.dofs = s.num_dofs;
  row.error_rms = row.error_max = row.error_rms_after_material = kNaN;
  row.seconds = seconds + seconds_since(start);
  check_.levels.push_back(row);
  setups_.push_back(std::move(setup));
}

// Builds and solves an immersed level: false (with the note) when its markers leave the part.
bool ImmersedLadderRun::solve_level(ImmersedLevel level,
                                    std::chrono::steady_clock::time_point start) {
  const std::vector<int> outside = immersed_markers_outside(level.domain, markers_);
  if (!outside.empty()) {
    check_.note = std::to_string(outside.size()) + " marker(s) lie in no cell of the part on " +
                  level.description + " (the first: row " +
                  std::to_string(markers_[static_cast<size_t>(outside.front())].row) +
                  "); the ladder stops before it";
    return false;
  }
  auto setup = std::make_unique<Setup>();
  make_immersed_setup(*setup, level.domain, cases_, markers_, false, {});
  setup->context.threads = case_setup_.context.threads;
  setup->component_weight = case_setup_.component_weight;
  const double seconds = seconds_since(start);
  add_level(std::move(setup),
            level.description + " (immersed in " + format(level.immersion_seconds) + " s)",
            seconds);
  return true;
}

// Ladder level `level` unless there is none, or it exceeds the budget or max_levels.
bool ImmersedLadderRun::solve_next(int level) {
  if (level > options_.max_levels) {
    check_.note = "max_levels (" + std::to_string(options_.max_levels) + ") reached";
    return false;
  }
  const auto start = std::chrono::steady_clock::now();
  // A level whose bound is beyond the budget is not immersed (its immersion is the costly part).
  const std::optional<long> bound = ladder_.dofs_bound ? ladder_.dofs_bound(level) : std::nullopt;
  std::optional<ImmersedLevel> next;
  long dofs = 0;
  std::string description;
  if (bound && *bound > options_.max_dofs) {
    dofs = *bound;
    description = "level " + std::to_string(level) + ", by the bound on its active functions";
  } else {
    next = ladder_.level(level);
    if (!next) {
      check_.note = "no finer background grid after level " + std::to_string(level - 1);
      return false;
    }
    dofs = active_dofs(next->domain);
    description = next->description;
  }
  if (dofs > options_.max_dofs && level == 1)
    throw nurbs::InputError(
        "the DOF budget (max_dofs " + std::to_string(options_.max_dofs) +
        ") allows no finer background grid: the first (" + description + ") has " +
        std::to_string(dofs) +
        " DOFs, so the grid's discretisation error cannot be estimated; raise max_dofs "
        "(measurements.max_dofs or --max-dofs) to at least " +
        std::to_string(dofs) +
        ", or turn the check off (measurements.discretization_check false or "
        "--no-discretization-check) if the grid is known to be fine enough");
  if (dofs > options_.max_dofs) {
    check_.budget_exhausted = true;
    check_.note = "the next level (" + description + ", " + std::to_string(dofs) +
                  " DOFs) exceeds the DOF budget of " + std::to_string(options_.max_dofs);
    return false;
  }
  say("discretisation check: level " + std::to_string(level) + " (" + description + ", " +
      std::to_string(dofs) + " DOFs)");
  return solve_level(std::move(*next), start);
}

Tail ImmersedLadderRun::tail_of(size_t finest) const {
  Tail t;
  const int dim = case_setup_.dim;
  t.vector.assign(markers_.size(), Eigen::Vector3d::Zero());
  if (finest == 0) return t;
  const Difference last = difference(predictions_[finest], predictions_[finest - 1], dim);
  double scale = 1.0;
  t.how = "no convergence ratio: its error taken as the last difference";
  if (finest >= 2 && static_cast<int>(finest) - 2 >= options_.ratio_from_level) {
    const Difference before = difference(predictions_[finest - 1], predictions_[finest - 2], dim);
    t.ratio = before.rms > 0.0 ? last.rms / before.rms : kNaN;
    if (t.ratio > 0.0 && t.ratio < 1.0) {
      scale = t.ratio / (1.0 - t.ratio);
      t.how = "its error extrapolated with ratio " + format(t.ratio);
    } else if (t.ratio >= 1.0) {
      t.how =
          "not converging (ratio " + format(t.ratio) + "): its error taken as the last difference";
    }
  }
  for (size_t m = 0; m < markers_.size(); ++m)
    t.vector[m] = scale * (predictions_[finest][m] - predictions_[finest - 1][m]);
  t.rms = scale * last.rms;
  t.max = scale * last.max;
  return t;
}

// u_k - u_exact ~ (u_k - u_K) + tail; its size by the triangle inequality (an upper bound).
std::vector<Eigen::Vector3d> ImmersedLadderRun::estimate(size_t k, size_t finest, const Tail& tail,
                                                         DiscretizationLevel& row) const {
  const Difference to_finest = difference(predictions_[finest], predictions_[k], case_setup_.dim);
  row.error_rms = to_finest.rms + tail.rms;
  row.error_max = to_finest.max + tail.max;
  row.error_rms_after_material = to_finest.rms_after_material + tail.rms;
  row.estimate = k == finest
                     ? "finest level solved, " + tail.how
                     : "difference to level " + std::to_string(finest) + " (" + tail.how + ")";
  std::vector<Eigen::Vector3d> error(markers_.size());
  for (size_t m = 0; m < markers_.size(); ++m)
    error[m] = predictions_[k][m] - predictions_[finest][m] + tail.vector[m];
  return error;
}

// Up the ladder until a level is chosen or the ladder ends; a level is chosen only with a
// convergence ratio behind its estimate (two finer levels, or one whose own error is
// extrapolated from a ratio < 1), and the finest on its extrapolated error alone when that is at
// most half the target (the body-fitted check's rule and reasons).
void ImmersedLadderRun::climb() {
  constexpr double kRichardsonMargin = 0.5;
  while (chosen_ < 0 && solve_next(static_cast<int>(finest_) + 1)) {
    ++finest_;
    const Tail tail = tail_of(finest_);
    const bool ratio_known = tail.ratio > 0.0 && tail.ratio < 1.0;
    const size_t candidates = ratio_known ? finest_ : finest_ - 1;
    for (size_t k = 0; k < candidates && chosen_ < 0; ++k) {
      DiscretizationLevel row;
      estimate(k, finest_, tail, row);
      if (row.error_rms <= check_.target) chosen_ = static_cast<int>(k);
    }
    if (chosen_ < 0 && ratio_known && tail.rms <= kRichardsonMargin * check_.target)
      chosen_ = static_cast<int>(finest_);
    say("discretisation check: the case's grid off by " +
        format(difference(predictions_[finest_], predictions_[0], case_setup_.dim).rms) +
        " m rms against level " + std::to_string(finest_) + " (noise " + format(check_.noise) +
        " m)");
  }
}

void ImmersedLadderRun::estimate_against_finest() {
  if (finest_ == 0) {
    check_.levels[0].estimate = "none: no finer grid could be solved";
    return;
  }
  const Tail tail = tail_of(finest_);
  for (size_t k = 0; k <= finest_; ++k) {
    std::vector<Eigen::Vector3d> error = estimate(k, finest_, tail, check_.levels[k]);
    if (chosen_ < 0 && k < finest_ && check_.levels[k].error_rms <= check_.target)
      chosen_ = static_cast<int>(k);
    if (static_cast<int>(k) == chosen_ || (chosen_ < 0 && k == finest_))
      check_.marker_error = std::move(error);
  }
}

void ImmersedLadderRun::settle() {
  check_.within_target = chosen_ >= 0;
  check_.chosen = chosen_ >= 0 ? chosen_ : static_cast<int>(finest_);
  if (chosen_ < 0 && finest_ > 0 && check_.levels[finest_].error_rms <= check_.target) {
    check_.within_target = true;
    check_.note += "; the finest level's extrapolated error is in target";
  }
  if (check_.within_target) check_.budget_exhausted = false;
  if (!check_.within_target)
    check_.note = "no background grid within the DOF budget (max_dofs " +
                  std::to_string(options_.max_dofs) + ") brings the error at the markers below " +
                  format(options_.target_fraction) + " x the noise; the finest solved (" +
                  check_.levels[static_cast<size_t>(check_.chosen)].description +
                  ") is used and every F-test is widened by its estimated error (" +
                  (check_.note.empty() ? std::string("the ladder ended") : check_.note) +
                  "). Raise --max-dofs or give the case a finer grid (geometry.cells)";
}

void ImmersedLadderRun::try_intermediate() {
  if (!(check_.within_target && check_.chosen >= 1 && ladder_.intermediate)) return;
  const int above = check_.chosen;
  const auto start = std::chrono::steady_clock::now();
  std::optional<ImmersedLevel> between = ladder_.intermediate(above);
  if (!between) return;
  const long dofs = active_dofs(between->domain);
  if (!(dofs < check_.levels[static_cast<size_t>(above)].dofs && dofs <= options_.max_dofs)) return;
  between->description +=
      " (between levels " + std::to_string(above - 1) + " and " + std::to_string(above) + ")";
  say("discretisation check: " + between->description + ", " + std::to_string(dofs) + " DOFs");
  if (!solve_level(std::move(*between), start)) return;
  const size_t k = check_.levels.size() - 1;
  std::vector<Eigen::Vector3d> error = estimate(k, finest_, tail_of(finest_), check_.levels[k]);
  if (check_.levels[k].error_rms <= check_.target) {
    check_.chosen = static_cast<int>(k);
    check_.marker_error = std::move(error);
  }
}

}  // namespace

std::unique_ptr<Setup> run_immersed_check(
    const Setup& case_setup, const geometry::ImmersedDomain& domain,
    const std::vector<ImmersedCalibrationCase>& cases, const std::vector<Marker>& markers,
    const Eigen::VectorXd& theta, double noise, const DiscretizationOptions& options,
    const ImmersedLadder& ladder, const std::function<void(const std::string&)>& progress,
    DiscretizationCheck& check) {
  check = DiscretizationCheck();
  check.noise = noise;
  check.target = options.target_fraction * noise;
  check.volumetric_rule = "displacement formulation (the immersed assembly has no B-bar)";
  if (!options.enabled) {
    check.note = "turned off";
    return nullptr;
  }
  if (!ladder.level) {
    check.note = "not done: no ladder of background grids was given";
    return nullptr;
  }
  return ImmersedLadderRun(case_setup, cases, markers, theta, options, ladder, progress, check)
      .run(domain);
}

}  // namespace identify_loop

DiscretizationCheck check_immersed_discretization(
    const geometry::ImmersedDomain& domain, const std::vector<ImmersedCalibrationCase>& cases,
    const std::vector<Marker>& markers, double modulus_ratio, double noise,
    const DiscretizationOptions& options, const ImmersedLadder& ladder,
    const std::function<void(const std::string&)>& progress) {
  using namespace identify_loop;
  Setup setup;
  make_immersed_setup(setup, domain, cases, markers, false, {});
  DiscretizationCheck check;
  run_immersed_check(setup, domain, cases, markers, Eigen::VectorXd::Constant(1, modulus_ratio),
                     noise, options, ladder, progress, check);
  return check;
}

}  // namespace isospring::fitting
