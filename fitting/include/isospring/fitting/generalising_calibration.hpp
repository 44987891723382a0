#pragma once
// A calibration whose model freedom is chosen by the error on load cases it was not fitted to
//: k-fold cross-validation over the training load cases picks the rest-length
// grouping (gamma) and, optionally, per-spring freedom with the penalty weight pulling log k
// towards the chosen grouped optimum (prior_spring_fit.hpp); the chosen model is then refitted
// on every training case and measured on the validation cases, which no choice has seen.
//
// Why: more freedom always lowers the fitted error (a per-spring model interpolates one load
// case), so the fitted error cannot choose the freedom. The cross-validation score of a
// candidate is the WORST %e_rms over the training cases, each measured by the fit that left it
// out: the model must hold on every load, not on average.
#include <string>
#include <vector>

#include "isospring/fitting/calibration.hpp"

namespace isospring::fitting {

struct GeneralisationOptions {
  /// Grouped candidates (rest-length windows); at least one.
  std::vector<double> gammas = {0.8, 0.5, 0.2, 0.1, 0.01};
  /// Per-spring candidates: penalty weights w of prior_spring_fit.hpp, the prior being the
  /// cross-validated grouping's optimum on the same training cases; empty: grouped only.
  std::vector<double> prior_weights = {1e-2, 1e-3, 1e-4};
  /// Spring topologies (SpringMeshOptions::reach): 1, [S15]'s net cells; 2, also springs two
  /// net steps apart. Every gamma and weight is tried with each.
  std::vector<int> reaches = {1};
  /// Model kinds (SpringMeshOptions::volume_terms): false, plain central springs; true, also a
  /// volume (2D: area) term per net cell (analysis::VolumeTerm), its modulus grouped by rest
  /// volume with the same gamma, or per cell in the per-spring candidates. Every reach, gamma
  /// and weight is tried with each; cross-validation picks plain or richer.
  std::vector<bool> volume_terms = {false};
  /// Shear terms (SpringMeshOptions::shear_terms): false, none; true, also one deviatoric term
  /// per net cell (analysis::CellEnergy::kShear), grouped like the volume terms. Every reach,
  /// volume kind, gamma and weight is tried with each.
  std::vector<bool> shear_terms = {false};
  /// Strain points (SpringMeshOptions::strain_points): 0, none; n > 0, a volume and a shear
  /// strain-point term at n Gauss points per direction of every knot span
  /// (analysis/spring_strain_point.hpp), grouped like the cell terms. Every other kind is tried
  /// with each.
  std::vector<int> strain_points = {0};
  /// Training cases are dealt diagonally (case c to fold (c + c / folds) mod folds) into this many
  /// folds (at least 2, at most the number of training cases).
  int folds = 3;
  /// > 0: a warning when the worst %e_rms over fitted and validation cases exceeds it.
  double target_percent_e_rms = 0.0;
};

struct CandidateScore {
  int reach = 1;
  bool volume_terms = false;
  bool shear_terms = false;
  int strain_points = 0;
  double gamma = 0.0;
  double prior_weight = 0.0;  // 0: the grouped model
  int parameters = 0;
  std::vector<double> percent_e_rms;  // per training case, by the fold fit that left it out
  double worst = 0.0;                 // the score: the largest of percent_e_rms
  double estimated_step_us = 0.0;     // the model's engine step (step_cost.hpp)
  std::string failure;                // non-empty: a fold fit failed (the candidate is out)
};

struct GeneralisationResult {
  /// The chosen candidate refitted on every training case (fit) and evaluated on the
  /// validation cases (holdout).
  CalibrationResult calibration;
  std::vector<CandidateScore> candidates;
  int chosen = 0;                                                  // index into candidates
  double worst_fitted = 0.0, worst_validation = 0.0, worst = 0.0;  // %e_rms, control points
  std::vector<std::string> warnings;  // also appended to calibration.warnings
};

/// `settings.fit_cases` are the training cases (empty: every case not in holdout_cases),
/// `settings.holdout_cases` the validation cases; its grouping fields (gamma, gamma_sweep,
/// per_spring, regularization) are replaced by the candidates. Throws like calibrate(), and
/// nurbs::InputError for bad options or fewer training cases than folds.
GeneralisationResult calibrate_for_generalisation(const analysis::Problem& problem,
                                                  const CalibrationSettings& settings,
                                                  const GeneralisationOptions& options);

}  // namespace isospring::fitting
