// Generalisation table of `isospring thesis` (header).
#include "thesis_generalisation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/generalising_calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

std::string num(double x) {
  return std::isfinite(x) ? format_number(x, 3) : "-";
}

// Candidates per object. Membranes (110 springs; 350 with reach 2) are cheap: both topologies,
// three weights, long L-BFGS runs. The solids (1600 to 2000 springs, 19 to 23 training cases)
// cost seconds per fit: reach 1, two weights, the gammas around [S15]'s and our best.
fitting::GeneralisationOptions candidates(const fitting::ThesisObject& object, bool quick,
                                          int& prior_iterations) {
  fitting::GeneralisationOptions options;
  const bool solid = object.problem.formulation == analysis::Formulation::kSolid;
  if (solid) {
    // The torus's gamma 0.1 (19 groups) costs ~20 s over 23 cases and lost to 0.2 when run.
    options.gammas = object.name == "cube"    ? std::vector<double>{0.8, 0.5}
                     : object.name == "torus" ? std::vector<double>{0.5, 0.2}
                                              : std::vector<double>{0.5, 0.2, 0.1};
    if (quick) options.gammas.resize(2);
    options.prior_weights = {1e-2, 1e-4};
    options.reaches = {1};
    // L-BFGS iterations of the per-spring fits: the cube's worst (fitted) case falls from 2.66
    // (200 iterations) to 1.91 (800) and ~1.85 (1500 to 3000, 200-300 s for the cube); the torus,
    // met with 200, costs 4-5x the cube per iteration.
    prior_iterations = quick ? 100 : object.name == "torus" ? 200 : 800;
  } else {
    options.gammas = {0.8, 0.5, 0.2, 0.1, 0.01};
    options.prior_weights = {1e-2, 1e-3, 1e-4};
    options.reaches = {1, 2};
    prior_iterations = quick ? 300 : 1500;
  }
  // Solids: springs with a volume term per net cell, with and without a shear term per net cell;
  // cross-validation picks (docs/calibration.md, "Richer spring models"). A central-spring
  // lattice has nu = 1/4, the objects nu = 1/3: plain springs lost to the volume terms on every
  // solid when offered (cross-validated worst: cube 4.75 / 3.16, torus 8.41 / 5.68, spheroid
  // 23.1 / 15.5), so they are no longer run here (4 model kinds would double the solids' time).
  // Membranes: plain springs only; a 2D net already has nu = 1/3 in plane stress and a cell's 6
  // springs already span its 5 deformation modes, so cell terms only add freedom the 3-fold
  // cross-validation over 11 cases cannot judge (measured: it chose area terms for the circle,
  // worst 5.26 -> 12.9, and shear terms for the circle, 5.26 -> 6.58, and the ellipse,
  // 3.68 -> 3.29).
  options.volume_terms = solid ? std::vector<bool>{true} : std::vector<bool>{false};
  options.shear_terms = solid ? std::vector<bool>{false, true} : std::vector<bool>{false};
  // Strain points (analysis/spring_strain_point.hpp): the membranes' error sits at the free
  // corners, which no cell term reaches; a strain point couples a knot span's 9 control points
  // through the basis gradients. 1 (reduced) or 2 points per direction, cross-validated.
  // The spheroid's error sits next to its held poles, where half of the net cells are flat and
  // carry no cell term; a strain point lies inside a knot span, where det J > 0. The cube and
  // the torus meet their targets with cell terms and are not offered strain points (each kind
  // costs them minutes).
  if (!solid) options.strain_points = {0, 1, 2};
  // The spheroid: 2 points per direction, or 3, the analysis' own Gauss rule, at which the
  // points can carry the IGA stiffness exactly (a single 3-point candidate measured worst 1.43
  // against [S15]'s 5.37). 0 and 1 points lost to 2 by far when offered (best cross-validated
  // worst 13.3 / 13.2 / 3.75 with 0 / 1 / 2 points) and are no longer run: each kind costs the
  // spheroid minutes.
  // The strain points carry a shear modulus per point, which makes the cells' shear terms
  // redundant: with 2 points the best cross-validated worst is 3.78 without them against 3.75
  // with them, and the 3-point single candidate was 1.53 without against 2.33 with. So the
  // spheroid runs without cell shear terms (each 3-point kind costs it tens of minutes).
  if (object.name == "coupled_spheroid") {
    options.strain_points = {2, 3};
    options.shear_terms = {false};
  }
  options.folds = 3;
  options.target_percent_e_rms = object.published_e_rms;
  return options;
}

long count_cells(const analysis::SpringNetwork& network, analysis::CellEnergy kind,
                 bool points = false) {
  return std::count_if(network.volumes.begin(), network.volumes.end(),
                       [&](const auto& t) { return t.kind == kind && t.points.empty() != points; });
}

// " + 125 volume terms + 125 shear terms" (empty for plain springs).
std::string cell_terms_text(const analysis::SpringNetwork& network) {
  std::string text;
  for (auto kind : {analysis::CellEnergy::kVolume, analysis::CellEnergy::kShear}) {
    const long count = count_cells(network, kind);
    if (count > 0)
      text += " + " + std::to_string(count) +
              (kind == analysis::CellEnergy::kVolume ? " volume terms" : " shear terms");
  }
  // A strain point carries a volume and a shear term.
  const long points = count_cells(network, analysis::CellEnergy::kShear, true);
  if (points > 0) text += " + " + std::to_string(points) + " strain points";
  return text;
}

}  // namespace

void thesis_generalisation(bool quick, const std::vector<std::string>& objects,
                           nlohmann::json& report, MarkdownReport& md, const Progress& progress) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string name :
       {"square", "circle", "ellipse", "cube", "torus", "coupled_spheroid"}) {
    if (!objects.empty() && std::find(objects.begin(), objects.end(), name) == objects.end())
      continue;
    const auto start = std::chrono::steady_clock::now();
    const fitting::ThesisObject object = fitting::thesis_object(name);
    const fitting::ThesisSuite suite = fitting::thesis_load_suite(object);
    fitting::CalibrationSettings settings;
    settings.fit_cases = suite.training;
    settings.holdout_cases = suite.validation;
    settings.max_iterations = 3000;
    settings.field_metrics = false;
    const fitting::GeneralisationOptions options =
        candidates(object, quick, settings.prior_max_iterations);
    settings.progress = [&progress, &name](const std::string& line) {
      progress(name + ": " + line);
    };
    progress(name + ": generalisation, " + std::to_string(suite.training.size()) +
             " training and " + std::to_string(suite.validation.size()) + " validation cases");
    const fitting::GeneralisationResult g =
        fitting::calibrate_for_generalisation(suite.problem, settings, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const fitting::CandidateScore& chosen = g.candidates[static_cast<size_t>(g.chosen)];
    const fitting::CalibrationResult& r = g.calibration;

    nlohmann::json j = {
        {"object", name},
        {"training_cases", suite.training},
        {"validation_cases", suite.validation},
        {"reach", chosen.reach},
        {"volume_terms", chosen.volume_terms},
        {"shear_terms", chosen.shear_terms},
        {"strain_points_per_direction", chosen.strain_points},
        {"strain_point_count", count_cells(r.mesh.network, analysis::CellEnergy::kShear, true)},
        {"springs", r.mesh.network.springs.size()},
        {"volume_term_count", count_cells(r.mesh.network, analysis::CellEnergy::kVolume)},
        {"shear_term_count", count_cells(r.mesh.network, analysis::CellEnergy::kShear)},
        {"gamma", chosen.gamma},
        {"prior_weight", chosen.prior_weight},
        {"parameters", r.parameters},
        {"cross_validation_worst", chosen.worst},
        {"worst_fitted", g.worst_fitted},
        {"worst_validation", g.worst_validation},
        {"worst", g.worst},
        {"published_percent_e_rms", object.published_e_rms},
        {"meets_published", g.worst <= object.published_e_rms},
        {"warnings", g.warnings},
        {"seconds", seconds}};
    for (const auto* cases : {&r.fit, &r.holdout})
      for (const auto& e : *cases)
        j[cases == &r.fit ? "fitted" : "validation"].push_back(
            {{"id", e.id},
             {"percent_e_rms", e.control.percent_e_rms},
             {"percent_e_max", e.control.percent_e_max}});
    for (const auto& c : g.candidates)
      j["candidates"].push_back({{"reach", c.reach},
                                 {"volume_terms", c.volume_terms},
                                 {"shear_terms", c.shear_terms},
                                 {"strain_points", c.strain_points},
                                 {"gamma", c.gamma},
                                 {"prior_weight", c.prior_weight},
                                 {"parameters", c.parameters},
                                 {"cross_validation_worst", c.worst},
                                 {"failure", c.failure}});
    report["generalisation"].push_back(j);
    for (const auto& w : g.warnings) progress.warn(name + ": " + w);

    std::string s15_cases, suite_cases;
    for (const auto& e : r.holdout) {
      const bool own =
          std::any_of(object.problem.load_cases.begin(), object.problem.load_cases.end(),
                      [&](const auto& lc) { return lc.id == e.id; });
      std::string& cell = own ? s15_cases : suite_cases;
      cell += (cell.empty() ? "" : ", ") + e.id + " " + num(e.control.percent_e_rms);
    }
    rows.push_back(
        {name,
         std::to_string(r.mesh.network.springs.size()) + " springs (reach " +
             std::to_string(chosen.reach) + ")" + cell_terms_text(r.mesh.network) + ", " +
             (chosen.prior_weight > 0.0
                  ? "per spring, w " + num(chosen.prior_weight) + " (gamma " + num(chosen.gamma) +
                        ")"
                  : std::to_string(r.parameters) + " groups (gamma " + num(chosen.gamma) + ")"),
         num(g.worst_fitted) + " (" + std::to_string(r.fit.size()) + ")", s15_cases, suite_cases,
         num(g.worst), num(object.published_e_rms),
         g.worst <= object.published_e_rms ? "yes" : "**no**", num(seconds)});
  }
  md.heading(2, "Generalisation: worst error over fitted and held-out load cases");
  md.paragraph(
      "Training: the load suite of fitting/load_suite.hpp (uniform traction along every axis and "
      "a twist on every free side, self-weight along every axis). Validation, never fitted: a "
      "ramp traction along the oblique direction on every free side, oblique self-weight, and "
      "all of [S15]'s load cases of the object (its fitted case fit_points included). The "
      "model's freedom (spring reach 1 or 2 for the membranes; for the solids central "
      "springs plus a volume term per net cell, with or without a shear term per net cell "
      "(the spheroid: without); for the membranes also strain points, a volume and a shear "
      "term on the NURBS strain at 0, 1 or 2 Gauss points per direction of every knot span, "
      "for the spheroid at 2 or 3 (3: the analysis' own Gauss rule) (docs/calibration.md); "
      "gamma; per spring with the penalty weight w pulling log k (and log kappa, log mu) "
      "towards the grouped optimum) is chosen by 3-fold "
      "cross-validation over the training cases: lowest worst held-out %e_rms. %e_rms on the "
      "control points; fitted: worst over the training cases (their number in brackets); worst: "
      "over fitted and validation cases. Loads are not scaled to %eps_G = 10 (linear: the errors "
      "do not depend on the scale).");
  md.table({"object", "model", "fitted (worst)", "[S15] cases (held out)", "suite validation",
            "worst", "published (fitted)", "meets", "time [s]"},
           rows);
}

}  // namespace isospring::workflows
