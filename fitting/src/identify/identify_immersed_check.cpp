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
#include "identify/ladder_rule.hpp"

namespace isospring::fitting {

namespace identify_loop {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using ladder_rule::format;

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
    rule_.estimate_against_finest(finest_, chosen_, "none: no finer grid could be solved");
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
  void climb();
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
  ladder_rule::LadderRule rule_{options_, case_setup_.dim, check_};  // predictions, the rule
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
    rule_.add(marker_predictions(s, model, theta_, markers_.size()));
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
  if (!rule_.within_budget(level, dofs, description,
                           {"no finer background grid: the first", "the grid's",
                            "the grid is known to be fine enough"}))
    return false;
  say("discretisation check: level " + std::to_string(level) + " (" + description + ", " +
      std::to_string(dofs) + " DOFs)");
  return solve_level(std::move(*next), start);
}

// Up the ladder until a level is chosen or the ladder ends; a level is chosen only with a
// convergence ratio behind its estimate (two finer levels, or one whose own error is
// extrapolated from a ratio < 1), and the finest on its extrapolated error alone when that is at
// most half the target (the body-fitted check's rule and reasons).
void ImmersedLadderRun::climb() {
  while (chosen_ < 0 && solve_next(static_cast<int>(finest_) + 1)) {
    ++finest_;
    chosen_ = rule_.choose_after(finest_);
    say("discretisation check: the case's grid off by " + format(rule_.case_error_rms(finest_)) +
        " m rms against level " + std::to_string(finest_) + " (noise " + format(check_.noise) +
        " m)");
  }
}

// The body-fitted outcome, and when no level is within the target, what to do about it.
void ImmersedLadderRun::settle() {
  rule_.settle(finest_, chosen_);
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
  rule_.consider_intermediate(finest_);
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
  const bool bbar =
      !cases.empty() && cases.front().options.volumetric == analysis::Volumetric::kBbar;
  check.volumetric = bbar ? "bbar" : "displacement";
  check.volumetric_rule = bbar ? "B-bar (mean dilatation per cell), as the case asks"
                               : "displacement formulation, as the case asks";
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
