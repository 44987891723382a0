#pragma once
// One row of the [S15] chapter-5 tables of `isospring thesis` (thesis_command.hpp): the gamma
// sweep of Algorithm 5.1 on one object with its baselines (per-spring fits, the acceleration
// objective, the matrix approach), and its report.json entry. Internal to io.
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "isospring/fitting/acceleration_fit.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows::thesis {

// The gamma values every grouped fit sweeps (Algorithm 5.1, coarse to fine): S15's Table 5.5
// values (0.8 0.7 0.6 0.5 0.2 0.1 0.05 0.01 0.001) so that every published row has a partner.
extern const std::vector<double> kGammaSweep;
// --quick: the coarse sweep for the torus and the spheroid (thesis_sweep.cpp says why).
extern const std::vector<double> kGammaSweepCoarse;

struct Row {
  fitting::ThesisObject object;
  std::string fit_case;
  int net = 0, degree = 2;
  /// The best grouped fit of the sweep; grouped.sweep has every gamma (fitting::SweepEntry).
  fitting::CalibrationResult grouped;
  std::optional<fitting::CalibrationResult> per_spring;
  std::string per_spring_failure;
  // Per-spring starts tried (the gamma of the grouped optimum each started from) and their
  // %e_rms on the fitted case (NAN: that start failed).
  std::vector<std::pair<double, double>> per_spring_starts;
  std::optional<fitting::MatrixComparison> acceleration;
  double fit_seconds = 0.0, per_spring_seconds = 0.0;
};

struct RunOptions {
  bool matrix = false, per_spring = false, acceleration = false;
  const std::vector<double>* gammas = &kGammaSweep;
  /// Per-spring fits start from the grouped optima of this many sweep groupings, best grouped
  /// error first, and keep the best end point: the per-spring objective is not convex, and on
  /// the curved membranes the best end point does not come from the best grouped start
  /// (ellipse: from gamma 0.1's 15 groups 1.80 %e_rms, from the best grouping's 29 groups 2.51).
  int per_spring_starts = 1;
};

/// Algorithm 5.1 on `object` with the baselines `what` asks for.
Row run_object(fitting::ThesisObject object, int net, int degree, const std::string& fit_case,
               const RunOptions& what, const io::Progress& progress);

nlohmann::json row_json(const Row& r);

/// Table cells: 3 significant digits ("-" for NaN), "a / b", held-out %e_rms list.
std::string num(double x);
std::string pair(double a, double b);
std::string holdout_cell(const std::vector<fitting::CaseErrors>& cases);
double seconds_since(std::chrono::steady_clock::time_point start);

}  // namespace isospring::workflows::thesis
