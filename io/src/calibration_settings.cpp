// Parsing of the case file's "calibration" object; see isospring/io/calibration_settings.hpp.
#include "isospring/io/calibration_settings.hpp"

#include <cmath>
#include <set>

#include "case_file_json.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

// The "calibration" object's fields: type and range checks are case_json::Field's (the one
// wording of every io reader); what is specific here is the defaults and the hints.
class Fields {
 public:
  explicit Fields(case_json::Field field) : field_(std::move(field)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw nurbs::InputError(field_.where() + "." + key + ": " + message);
  }

  void expect_only(std::initializer_list<const char*> known) const { field_.expect_object(known); }

  bool has(const std::string& key) const { return field_.has(key); }
  case_json::Field at(const std::string& key) const { return field_.at(key); }

  double number(const std::string& key, double fallback, double minimum, bool open) const {
    return has(key) ? at(key).at_least(minimum, open) : fallback;
  }

  int integer(const std::string& key, int fallback, int minimum) const {
    return has(key) ? at(key).integer_at_least(minimum) : fallback;
  }

  bool boolean(const std::string& key, bool fallback) const {
    return has(key) ? at(key).boolean() : fallback;
  }

  std::vector<std::string> strings(const std::string& key) const {
    if (!has(key)) return {};
    if (!at(key).json().is_array())
      fail(key, "must be a list of load-case ids, e.g. [\"L1\", \"L2\"]");
    return at(key).strings();
  }

  const case_json::Field& field() const { return field_; }

 private:
  case_json::Field field_;
};

void parse_grouping(const case_json::Field& field, fitting::CalibrationSettings& settings) {
  const nlohmann::json& grouping = field.json();
  const std::string where = field.where();
  if (grouping.is_string()) {
    if (grouping.get<std::string>() != "per_spring")
      throw nurbs::InputError(where + ": unknown grouping " + grouping.dump() +
                              "; use \"per_spring\" or an object {\"gamma\": 0.01}");
    settings.per_spring = true;
    return;
  }
  if (!grouping.is_object())
    throw nurbs::InputError(where + ": must be \"per_spring\" or an object {\"gamma\": 0.01}");
  const Fields f(field);
  f.expect_only({"gamma", "gamma_sweep", "per_spring"});
  if (f.has("gamma") && f.has("gamma_sweep"))
    f.fail("gamma_sweep", "give either gamma or gamma_sweep, not both");
  // A relative rest-length window: below 1.
  if (f.has("gamma")) settings.gamma = f.at("gamma").within(0.0, 1.0, false, true);
  if (f.has("gamma_sweep"))
    for (const case_json::Field& g : f.at("gamma_sweep").elements(false))
      settings.gamma_sweep.push_back(g.within(0.0, 1.0, false, true));
  settings.per_spring = f.boolean("per_spring", false);
}

std::vector<double> numbers(const Fields& f, const std::string& field, double lo, double hi) {
  return f.at(field).numbers_within(lo, hi);
}

void parse_generalisation(const case_json::Field& g, bool fit_given, CalibrationRequest& request) {
  const Fields f(g);
  f.expect_only({"load_suite", "gammas", "prior_weights", "reaches", "volume_terms", "shear_terms",
                 "strain_points", "folds", "prior_iterations"});
  fitting::GeneralisationOptions o;
  request.load_suite = f.boolean("load_suite", !fit_given);
  if (f.has("gammas")) o.gammas = numbers(f, "gammas", 0.0, 0.999);
  if (f.has("prior_weights")) {
    o.prior_weights.clear();
    if (!f.at("prior_weights").json().empty())
      o.prior_weights = numbers(f, "prior_weights", 1e-12, 1e6);
  }
  if (f.has("reaches")) {
    o.reaches.clear();
    for (double r : numbers(f, "reaches", 1, 2)) {
      if (r != 1.0 && r != 2.0) f.fail("reaches", "entries must be 1 or 2");
      o.reaches.push_back(static_cast<int>(r));
    }
  }
  // Model kinds: lists of booleans, cross-validation picks; default: the calibration's own.
  auto kinds = [&f](const char* key, bool fallback) {
    return f.has(key) ? f.at(key).booleans() : std::vector<bool>{fallback};
  };
  o.volume_terms = kinds("volume_terms", request.settings.mesh.volume_terms);
  o.shear_terms = kinds("shear_terms", request.settings.mesh.shear_terms);
  o.strain_points = {request.settings.mesh.strain_points};
  if (f.has("strain_points")) {
    o.strain_points.clear();
    for (double n : numbers(f, "strain_points", 0, 4)) {
      if (n != std::floor(n)) f.fail("strain_points", "entries must be whole numbers 0 .. 4");
      o.strain_points.push_back(static_cast<int>(n));
    }
  }
  o.folds = f.integer("folds", o.folds, 2);
  request.settings.prior_max_iterations =
      f.integer("prior_iterations", request.settings.prior_max_iterations, 1);
  request.generalisation = o;
}

// "amplitudes": a list of %eps_G, each > 0 and larger than the one before, or {"max": m,
// "steps": n} for m / n, 2 m / n, ..., m.
std::vector<double> parse_amplitudes(const case_json::Field& field) {
  std::vector<double> amplitudes;
  if (field.json().is_object()) {
    const Fields f(field);
    f.expect_only({"max", "steps"});
    if (!f.has("max")) f.fail("max", "is required: the largest %eps_G, e.g. 20");
    const double max = f.at("max").within(0.0, 100.0, false, false);
    const int steps = f.integer("steps", 1, 1);
    for (int k = 1; k <= steps; ++k) amplitudes.push_back(max * k / steps);
    return amplitudes;
  }
  if (!field.json().is_array() || field.json().empty())
    throw nurbs::InputError(field.where() +
                            ": must be a list of %eps_G in percent, e.g. [5, 20], or "
                            "{\"max\": 20, \"steps\": 4}");
  amplitudes = field.numbers_within(0.0, 100.0);
  for (size_t i = 0; i < amplitudes.size(); ++i) {
    if (!(amplitudes[i] > 0.0))
      throw nurbs::InputError(field.where() + "[" + std::to_string(i) +
                              "]: must be > 0 (a target %eps_G in percent)");
    if (i > 0 && !(amplitudes[i] > amplitudes[i - 1]))
      throw nurbs::InputError(field.where() + "[" + std::to_string(i) +
                              "]: must be larger than the one before (the fit continues from "
                              "each amplitude to the next)");
  }
  return amplitudes;
}

}  // namespace

CalibrationRequest read_calibration_settings(const nlohmann::json& calibration,
                                             const std::string& file) {
  CalibrationRequest request;
  fitting::CalibrationSettings& s = request.settings;
  if (calibration.is_null()) return request;
  const Fields f(case_json::Field(calibration, file, "calibration"));
  f.expect_only({"fit_load_cases",
                 "holdout_load_cases",
                 "grouping",
                 "regularization",
                 "mass",
                 "damping_alpha",
                 "damping_ratio",
                 "upper_bounds",
                 "merge_coincident",
                 "max_iterations",
                 "field_samples",
                 "matrix_approach",
                 "acceleration_objective",
                 "target_percent_e_rms",
                 "generalisation",
                 "volume_terms",
                 "shear_terms",
                 "strain_points",
                 "max_step_us",
                 "amplitudes"});
  s.fit_cases = f.strings("fit_load_cases");
  s.holdout_cases = f.strings("holdout_load_cases");
  for (const auto& id : s.holdout_cases)
    for (const auto& fit : s.fit_cases)
      if (id == fit)
        f.fail("holdout_load_cases",
               "'" + id + "' is also in fit_load_cases; a held-out case must not be fitted");
  if (f.has("grouping")) parse_grouping(f.at("grouping"), s);
  s.regularization = f.number("regularization", 0.0, 0.0, false);
  if (s.regularization > 0.0 && !s.per_spring)
    f.fail("regularization", "only applies to per-spring fits (\"grouping\": \"per_spring\")");
  if (f.has("mass")) {
    const auto& m = f.at("mass").json();
    if (m == "lumped")
      s.mass_model = fitting::MassModel::kLumpedIga;
    else if (m == "net_cells")
      s.mass_model = fitting::MassModel::kNetCells;
    else
      f.fail("mass", "must be \"lumped\" or \"net_cells\" (got " + m.dump() + ")");
  }
  s.damping_alpha = f.number("damping_alpha", 0.0, 0.0, true);
  s.damping_ratio = f.number("damping_ratio", 0.0, 0.0, true);
  if (f.has("damping_alpha") && f.has("damping_ratio"))
    f.fail("damping_ratio",
           "give damping_alpha ([S15 4.18]) or damping_ratio (fraction of critical), not both");
  s.upper_bounds = f.boolean("upper_bounds", false);
  s.mesh.merge_coincident = f.boolean("merge_coincident", false);
  s.mesh.volume_terms = f.boolean("volume_terms", false);
  s.mesh.shear_terms = f.boolean("shear_terms", false);
  // Points per direction.
  s.mesh.strain_points = f.has("strain_points") ? f.at("strain_points").integer_within(0, 4) : 0;
  s.max_iterations = f.integer("max_iterations", s.max_iterations, 1);
  s.field_samples = f.integer("field_samples", s.field_samples, 2);
  // The matrix approach fits central springs only: off by default with cell terms.
  const bool cell_terms = s.mesh.volume_terms || s.mesh.shear_terms || s.mesh.strain_points > 0;
  request.matrix_approach = f.boolean("matrix_approach", !cell_terms);
  if (request.matrix_approach && cell_terms)
    f.fail("matrix_approach",
           "fits central springs only and cannot compare a model with volume_terms, "
           "shear_terms or strain_points; set it to false");
  request.matrix_approach_given = f.has("matrix_approach");
  request.acceleration_objective = f.boolean("acceleration_objective", true);
  request.acceleration_objective_given = f.has("acceleration_objective");
  if (f.has("amplitudes")) request.amplitudes = parse_amplitudes(f.at("amplitudes"));
  request.target_percent_e_rms = f.number("target_percent_e_rms", 0.0, 0.0, false);
  // A budget per engine step [us]: the most accurate model kind within it (step_cost.hpp).
  s.max_step_us = f.number("max_step_us", 0.0, 0.0, false);
  if (f.has("generalisation")) {
    if (s.per_spring || !s.gamma_sweep.empty())
      f.fail("generalisation",
             "chooses the grouping itself; remove grouping.per_spring and "
             "grouping.gamma_sweep");
    parse_generalisation(f.at("generalisation"), !s.fit_cases.empty(), request);
    request.generalisation->target_percent_e_rms = request.target_percent_e_rms;
  }
  return request;
}

}  // namespace isospring::io
