// The discretisation ladder of the measured-data loop (discretization_check.hpp).
#include "isospring/fitting/discretization_check.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"
#include "ladder_rule.hpp"

namespace isospring::fitting {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using ladder_rule::format;

// Marker m's displacement from the solution of the load case it belongs to.
std::vector<Eigen::Vector3d> at_markers(const analysis::Problem& problem,
                                        const analysis::StaticResult& solution,
                                        const std::vector<Marker>& markers,
                                        const std::vector<MarkerPlacement>& placements,
                                        const std::map<std::string, size_t>& case_index) {
  std::vector<Eigen::Vector3d> out(markers.size(), Eigen::Vector3d::Zero());
  for (size_t m = 0; m < markers.size(); ++m) {
    const MarkerPlacement& place = placements[m];
    const auto& control =
        solution.load_cases[case_index.at(markers[m].load_case)].control_displacements;
    const nurbs::RationalBasis basis =
        problem.patches[static_cast<size_t>(place.patch)].basis(place.param, 0);
    for (size_t a = 0; a < basis.indices.size(); ++a)
      out[m] += basis.values[static_cast<Eigen::Index>(a)] *
                control[static_cast<size_t>(place.patch)][static_cast<size_t>(basis.indices[a])];
  }
  return out;
}

// A corner of the control net: the only control points that interpolate the geometry, so the
// only ones whose support or point load means the same on every level.
bool is_net_corner(const nurbs::Patch& patch, int index) {
  const std::array<int, 3> ijk = patch.net_position(index);
  for (int d = 0; d < patch.param_dim(); ++d)
    if (ijk[static_cast<size_t>(d)] != 0 && ijk[static_cast<size_t>(d)] != patch.num_points(d) - 1)
      return false;
  return true;
}

// The same corner on a refined net.
int same_corner(const nurbs::Patch& coarse, const nurbs::Patch& fine, int index) {
  std::array<int, 3> ijk = coarse.net_position(index);
  for (int d = 0; d < coarse.param_dim(); ++d)
    if (ijk[static_cast<size_t>(d)] != 0) ijk[static_cast<size_t>(d)] = fine.num_points(d) - 1;
  return fine.index(ijk[0], ijk[1], ijk[2]);
}

// Supports and point loads on single control points must be the same physical condition on
// every level: net corners at the same place.
void check_same_point_conditions(const analysis::Problem& base, const analysis::Problem& level,
                                 const std::string& description) {
  auto same = [&](int patch, int coarse_index, int fine_index, const std::string& what) {
    const auto& c = base.patches[static_cast<size_t>(patch)];
    const auto& f = level.patches[static_cast<size_t>(patch)];
    if (!is_net_corner(c, coarse_index))
      throw nurbs::InputError(
          "discretisation check: " + what + " is on control point " + std::to_string(coarse_index) +
          " of patch " + std::to_string(patch) +
          ", not a corner of the net: it has no counterpart on a refined net. Support or load "
          "whole sides, or turn the check off (\"discretization_check\": false)");
    if (fine_index < 0 || fine_index >= f.num_points() ||
        (f.control_points()[static_cast<size_t>(fine_index)] -
         c.control_points()[static_cast<size_t>(coarse_index)])
                .norm() >
            1e-12 * (1.0 + c.control_points()[static_cast<size_t>(coarse_index)].norm()))
      throw nurbs::InputError(
          "discretisation check: level \"" + description + "\" puts the " + what +
          " on another point; give corner control points as net positions counted from the "
          "end, e.g. [0, -1] for the last point along v, so that refinement keeps them");
  };
  if (level.supports.size() != base.supports.size())
    throw nurbs::InputError("discretisation ladder: level \"" + description +
                            "\" has other supports than the model");
  for (size_t s = 0; s < base.supports.size(); ++s)
    if (base.supports[s].control_point)
      same(base.supports[s].side.patch, *base.supports[s].control_point,
           level.supports[s].control_point.value_or(-1), "support " + std::to_string(s + 1));
  for (size_t l = 0; l < base.load_cases.size() && l < level.load_cases.size(); ++l) {
    const auto& coarse = base.load_cases[l].point_loads;
    const auto& fine = level.load_cases[l].point_loads;
    for (size_t k = 0; k < coarse.size(); ++k)
      same(coarse[k].patch, coarse[k].control_point, k < fine.size() ? fine[k].control_point : -1,
           "point load " + std::to_string(k + 1) + " of load case " + base.load_cases[l].id);
  }
}

void check_same_geometry(const analysis::Problem& base, const analysis::Problem& level,
                         const std::vector<MarkerPlacement>& placements, double size,
                         const std::string& description) {
  if (level.patches.size() != base.patches.size())
    throw nurbs::InputError("discretisation ladder: level \"" + description + "\" has " +
                            std::to_string(level.patches.size()) + " patches, the model " +
                            std::to_string(base.patches.size()));
  for (const MarkerPlacement& place : placements) {
    const auto p = static_cast<size_t>(place.patch);
    const double moved =
        (level.patches[p].point(place.param) - base.patches[p].point(place.param)).norm();
    if (moved > 1e-9 * size)
      throw nurbs::InputError("discretisation ladder: level \"" + description +
                              "\" changes the geometry or its parametrisation (a marker point "
                              "moves by " +
                              format(moved) + " m); refinement must be geometry-exact");
  }
}

// The problem with every knot span of every patch split in `splits`.
analysis::Problem split_every_span(const analysis::Problem& problem, int splits) {
  analysis::Problem refined = problem;
  for (auto& patch : refined.patches) patch = nurbs::refine_uniform(patch, splits);
  // Conditions on single control points follow their corner (check_same_point_conditions
  // refuses the others).
  auto follow = [&](int patch, int& index) {
    const auto p = static_cast<size_t>(patch);
    if (is_net_corner(problem.patches[p], index))
      index = same_corner(problem.patches[p], refined.patches[p], index);
  };
  for (auto& support : refined.supports)
    if (support.control_point) follow(support.side.patch, *support.control_point);
  for (auto& load : refined.load_cases)
    for (auto& point : load.point_loads) follow(point.patch, point.control_point);
  return refined;
}

}  // namespace

DiscretizationLadder knot_insertion_ladder(const analysis::Problem& problem) {
  return [problem](int level, std::string* description) -> std::optional<analysis::Problem> {
    if (level < 1 || level > 10) return std::nullopt;
    const int splits = 1 << level;
    if (description)
      *description = "case's net with every knot span split in " + std::to_string(splits);
    return split_every_span(problem, splits);
  };
}

DiscretizationLadder knot_insertion_intermediate(const analysis::Problem& problem) {
  return [problem](int level, std::string* description) -> std::optional<analysis::Problem> {
    if (level < 2 || level > 10) return std::nullopt;
    const int splits = 3 << (level - 2);
    if (description)
      *description = "case's net with every knot span split in " + std::to_string(splits);
    return split_every_span(problem, splits);
  };
}

namespace {

// The formulation of every level (DiscretizationOptions::bbar_from_poisson), recorded in `check`.
analysis::Volumetric volumetric_rule(const analysis::Problem& problem, double poisson_ratio,
                                     const DiscretizationOptions& options,
                                     DiscretizationCheck& check) {
  const std::string threshold = format(options.bbar_from_poisson);
  analysis::Volumetric volumetric = problem.volumetric;
  if (problem.volumetric == analysis::Volumetric::kBbar) {
    check.volumetric_rule = "B-bar, as the case asks";
  } else if (problem.formulation == analysis::Formulation::kPlaneStress) {
    check.volumetric_rule = "displacement formulation: plane stress does not lock";
  } else if (poisson_ratio >= options.bbar_from_poisson) {
    volumetric = analysis::Volumetric::kBbar;
    check.volumetric_rule = "B-bar: nu = " + format(poisson_ratio) + " >= " + threshold +
                            ", where the displacement formulation locks";
  } else {
    check.volumetric_rule = "displacement formulation: nu = " + format(poisson_ratio) + " < " +
                            threshold + " (B-bar from " + threshold + ")";
  }
  check.volumetric = volumetric == analysis::Volumetric::kBbar ? "bbar" : "displacement";
  return volumetric;
}

// One run of the check as its stages (run()). The stages share the levels solved so far (their
// problems and predictions at the markers, in check_.levels order), the finest level solved and
// the level chosen so far (-1: none).
class LadderRun {
 public:
  LadderRun(const analysis::Problem& problem, const std::vector<Marker>& markers,
            const std::vector<MarkerPlacement>& placements, double youngs_modulus,
            double poisson_ratio, const DiscretizationOptions& options,
            const std::function<void(const std::string&)>& progress, DiscretizationCheck check)
      : problem_(problem),
        markers_(markers),
        placements_(placements),
        youngs_modulus_(youngs_modulus),
        poisson_ratio_(poisson_ratio),
        options_(options),
        progress_(progress),
        ladder_(options.ladder ? options.ladder : knot_insertion_ladder(problem)),
        intermediate_(options.intermediate ? options.intermediate
                      : options.ladder     ? DiscretizationLadder()
                                           : knot_insertion_intermediate(problem)),
        dim_(problem.formulation == analysis::Formulation::kSolid ? 3 : 2),
        volumetric_(volumetric_rule(problem, poisson_ratio, options, check)),
        check_(std::move(check)) {
    for (size_t l = 0; l < problem.load_cases.size(); ++l)
      case_index_[problem.load_cases[l].id] = l;
    for (const auto& patch : problem.patches) {
      const auto [lo, hi] = patch.control_bounds();
      size_ = std::max(size_, (hi - lo).norm());
    }
  }

  DiscretizationCheck run() {
    say("discretisation check: solving the case's own discretisation");
    solve(problem_, "the case's discretisation");
    climb();
    // When the ladder ended before a level met the target with two finer levels behind it, one
    // finer level has to do.
    rule_.estimate_against_finest(finest_, chosen_, "none: no finer level could be solved");
    rule_.settle(finest_, chosen_);
    try_intermediate();
    if (check_.chosen > 0 || volumetric_ != problem_.volumetric)
      check_.chosen_problem = std::move(solved_problems_[static_cast<size_t>(check_.chosen)]);
    return std::move(check_);
  }

 private:
  void say(const std::string& s) const {
    if (progress_) progress_(s);
  }
  void solve(analysis::Problem level_problem, const std::string& description);
  void check_level(const analysis::Problem& level, const std::string& description) const {
    check_same_geometry(problem_, level, placements_, size_, description);
    check_same_point_conditions(problem_, level, description);
  }
  bool solve_next(int level);
  void climb();
  void try_intermediate();

  const analysis::Problem& problem_;
  const std::vector<Marker>& markers_;
  const std::vector<MarkerPlacement>& placements_;
  const double youngs_modulus_, poisson_ratio_;
  const DiscretizationOptions& options_;
  const std::function<void(const std::string&)>& progress_;
  const DiscretizationLadder ladder_, intermediate_;
  const int dim_;
  const analysis::Volumetric volumetric_;  // of every level (volumetric_rule)
  std::map<std::string, size_t> case_index_;
  double size_ = 0.0;  // the model's size, the scale of the geometry check's tolerance
  DiscretizationCheck check_;
  std::vector<analysis::Problem> solved_problems_;
  ladder_rule::LadderRule rule_{options_, dim_, check_};  // the levels' predictions and the rule
  size_t finest_ = 0;
  int chosen_ = -1;
};

// Solves a level at the fitted material and appends its row and its predictions at the markers.
void LadderRun::solve(analysis::Problem level_problem, const std::string& description) {
  const auto start = std::chrono::steady_clock::now();
  level_problem.material.youngs_modulus = youngs_modulus_;
  level_problem.material.poisson_ratio = poisson_ratio_;
  level_problem.volumetric = volumetric_;
  const analysis::StaticResult solution = analysis::solve_static(level_problem);
  level_problem.material = problem_.material;  // the chosen problem keeps the case's prior
  DiscretizationLevel row;
  row.level = static_cast<int>(check_.levels.size());
  row.description = description;
  row.dofs = solution.dofs;
  row.error_rms = row.error_max = row.error_rms_after_material = kNaN;
  rule_.add(at_markers(level_problem, solution, markers_, placements_, case_index_));
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  check_.levels.push_back(row);
  solved_problems_.push_back(std::move(level_problem));
}

// Solves ladder level `level` unless there is none, it exceeds the budget or max_levels.
bool LadderRun::solve_next(int level) {
  if (level > options_.max_levels) {
    check_.note = "max_levels (" + std::to_string(options_.max_levels) + ") reached";
    return false;
  }
  std::string description;
  std::optional<analysis::Problem> next = ladder_(level, &description);
  if (!next) {
    check_.note = "no finer discretisation after level " + std::to_string(level - 1);
    return false;
  }
  check_level(*next, description);
  const int dofs = analysis::DofMap(*next).num_dofs();
  if (!rule_.within_budget(level, dofs, description,
                           {"no refinement of the case: its first refinement", "its",
                            "the case is known to be converged"}))
    return false;
  say("discretisation check: level " + std::to_string(level) + " (" + description + ", " +
      std::to_string(dofs) + " DOFs)");
  solve(std::move(*next), description);
  return true;
}

// Up the ladder until a level is chosen or the ladder ends. While the ladder goes on, a level
// is only chosen with a convergence ratio behind its estimate (at least two finer levels, or one
// finer level whose own error is extrapolated from a ratio < 1): a ladder's first steps can be
// pre-asymptotic (degree elevation on one element through a thickness stalls), and one
// difference alone then underestimates the error.
void LadderRun::climb() {
  while (chosen_ < 0 && solve_next(static_cast<int>(finest_) + 1)) {
    ++finest_;
    chosen_ = rule_.choose_after(finest_);
    say("discretisation check: level 0 off by " + format(rule_.case_error_rms(finest_)) +
        " m rms against level " + std::to_string(finest_) + " (noise " + format(check_.noise) +
        " m)");
  }
}

// A level between the chosen one and the one before it (DiscretizationOptions::intermediate),
// estimated against the finest level like the others; it replaces the chosen level when it is
// within the target too.
void LadderRun::try_intermediate() {
  if (!(check_.within_target && check_.chosen >= 1 && intermediate_)) return;
  const int above = check_.chosen;
  std::string description;
  std::optional<analysis::Problem> between = intermediate_(above, &description);
  const int dofs = between ? analysis::DofMap(*between).num_dofs() : 0;
  if (!(between && dofs < check_.levels[static_cast<size_t>(above)].dofs &&
        dofs <= options_.max_dofs))
    return;
  description +=
      " (between levels " + std::to_string(above - 1) + " and " + std::to_string(above) + ")";
  check_level(*between, description);
  say("discretisation check: " + description + ", " + std::to_string(dofs) + " DOFs");
  solve(std::move(*between), description);
  rule_.consider_intermediate(finest_);
}

}  // namespace

DiscretizationCheck check_discretization(const analysis::Problem& problem,
                                         const std::vector<Marker>& markers,
                                         const std::vector<MarkerPlacement>& placements,
                                         double youngs_modulus, double poisson_ratio, double noise,
                                         const DiscretizationOptions& options,
                                         const std::function<void(const std::string&)>& progress) {
  DiscretizationCheck check;
  check.noise = noise;
  check.target = options.target_fraction * noise;
  if (!options.enabled) {
    check.note = "turned off";
    return check;
  }
  if (markers.size() != placements.size())
    throw std::invalid_argument("check_discretization: one placement per marker expected");
  return LadderRun(problem, markers, placements, youngs_modulus, poisson_ratio, options, progress,
                   std::move(check))
      .run();
}

}  // namespace isospring::fitting
