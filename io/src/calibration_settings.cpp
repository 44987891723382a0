// Parsing of the case file's "calibration" object; see isospring/io/calibration_settings.hpp.
#include "isospring/io/calibration_settings.hpp"

#include <cmath>
#include <set>

#include "case_file_json.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

class Fields {
 public:
  Fields(const nlohmann::json& object, std::string where)
      : object_(object), where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw nurbs::InputError(where_ + "." + field + ": " + message);
  }

  void expect_only(const std::set<std::string>& known) const {
    case_json::reject_unknown_fields(object_, std::vector<std::string>(known.begin(), known.end()),
                                     where_ + ".");
  }

  bool has(const std::string& field) const { return object_.contains(field); }

  double number(const std::string& field, double fallback, double minimum, bool open) const {
    if (!has(field)) return fallback;
    const auto& v = object_.at(field);
    if (!v.is_number()) fail(field, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < minimum || (open && x == minimum))
      fail(field, std::string("must be a finite number ") + (open ? "> " : ">= ") +
                      std::to_string(minimum) + " (got " + v.dump() + ")");
    return x;
  }

  int integer(const std::string& field, int fallback, int minimum) const {
    if (!has(field)) return fallback;
    const auto& v = object_.at(field);
    if (!v.is_number_integer() || v.get<long>() < minimum)
      fail(field, "must be an integer >= " + std::to_string(minimum) + " (got " + v.dump() + ")");
    return v.get<int>();
  }

  bool boolean(const std::string& field, bool fallback) const {
    if (!has(field)) return fallback;
    if (!object_.at(field).is_boolean()) fail(field, "must be true or false");
    return object_.at(field).get<bool>();
  }

  std::vector<std::string> strings(const std::string& field) const {
    std::vector<std::string> out;
    if (!has(field)) return out;
    const auto& v = object_.at(field);
    if (!v.is_array()) fail(field, "must be a list of load-case ids, e.g. [\"L1\", \"L2\"]");
    for (const auto& item : v) {
      if (!item.is_string()) fail(field, "must be a list of load-case ids (strings)");
      out.push_back(item.get<std::string>());
    }
    return out;
  }

  const nlohmann::json& at(const std::string& field) const { return object_.at(field); }
  const std::string& where() const { return where_; }

 private:
  const nlohmann::json& object_;
  std::string where_;
};

void parse_grouping(const nlohmann::json& grouping, const std::string& where,
                    fitting::CalibrationSettings& settings) {
  if (grouping.is_string()) {
    if (grouping.get<std::string>() != "per_spring")
      throw nurbs::InputError(where + ": unknown grouping " + grouping.dump() +
                              "; use \"per_spring\" or an object {\"gamma\": 0.01}");
    settings.per_spring = true;
    return;
  }
  if (!grouping.is_object())
    throw nurbs::InputError(where + ": must be \"per_spring\" or an object {\"gamma\": 0.01}");
  const Fields f(grouping, where);
  f.expect_only({"gamma", "gamma_sweep", "per_spring"});
  if (f.has("gamma") && f.has("gamma_sweep"))
    f.fail("gamma_sweep", "give either gamma or gamma_sweep, not both");
  settings.gamma = f.number("gamma", settings.gamma, 0.0, false);
  if (settings.gamma >= 1.0) f.fail("gamma", "must be below 1 (a relative rest-length window)");
  if (f.has("gamma_sweep")) {
    const auto& sweep = f.at("gamma_sweep");
    if (!sweep.is_array() || sweep.empty())
      f.fail("gamma_sweep", "must be a non-empty list of numbers in [0, 1)");
    for (const auto& g : sweep) {
      if (!g.is_number() || !(g.get<double>() >= 0.0 && g.get<double>() < 1.0))
        f.fail("gamma_sweep", "every entry must be a number in [0, 1) (got " + g.dump() + ")");
      settings.gamma_sweep.push_back(g.get<double>());
    }
  }
  settings.per_spring = f.boolean("per_spring", false);
}

std::vector<double> numbers(const Fields& f, const std::string& field, double lo, double hi) {
  const auto& v = f.at(field);
  if (!v.is_array() || v.empty()) f.fail(field, "must be a non-empty list of numbers");
  std::vector<double> out;
  for (const auto& x : v) {
    if (!x.is_number() || !(x.get<double>() >= lo && x.get<double>() <= hi))
      f.fail(field, "every entry must be a number in [" + format_number(lo) + ", " +
                        format_number(hi) + "] (got " + x.dump() + ")");
    out.push_back(x.get<double>());
  }
  return out;
}

void parse_generalisation(const nlohmann::json& g, const std::string& where, bool fit_given,
                          CalibrationRequest& request) {
  if (!g.is_object()) throw nurbs::InputError(where + ": must be an object {...}");
  const Fields f(g, where);
  f.expect_only({"load_suite", "gammas", "prior_weights", "reaches", "volume_terms", "shear_terms",
                 "strain_points", "folds", "prior_iterations"});
  fitting::GeneralisationOptions o;
  request.load_suite = f.boolean("load_suite", !fit_given);
  if (f.has("gammas")) o.gammas = numbers(f, "gammas", 0.0, 0.999);
  if (f.has("prior_weights")) {
    o.prior_weights.clear();
    if (!f.at("prior_weights").empty()) o.prior_weights = numbers(f, "prior_weights", 1e-12, 1e6);
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
    if (!f.has(key)) return std::vector<bool>{fallback};
    const auto& v = f.at(key);
    if (!v.is_array() || v.empty()) f.fail(key, "must be a non-empty list of booleans");
    std::vector<bool> out;
    for (const auto& x : v) {
      if (!x.is_boolean()) f.fail(key, "entries must be true or false (got " + x.dump() + ")");
      out.push_back(x.get<bool>());
    }
    return out;
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

}  // namespace

CalibrationRequest read_calibration_settings(const nlohmann::json& calibration,
                                             const std::string& file) {
  CalibrationRequest request;
  fitting::CalibrationSettings& s = request.settings;
  if (calibration.is_null()) return request;
  const std::string where = file + ": calibration";
  if (!calibration.is_object()) throw nurbs::InputError(where + ": must be an object {...}");
  const Fields f(calibration, where);
  f.expect_only({"fit_load_cases", "holdout_load_cases", "grouping", "regularization", "mass",
                 "damping_alpha", "damping_ratio", "upper_bounds", "merge_coincident",
                 "max_iterations", "field_samples", "matrix_approach", "acceleration_objective",
                 "target_percent_e_rms", "generalisation", "volume_terms", "shear_terms",
                 "strain_points"});
  s.fit_cases = f.strings("fit_load_cases");
  s.holdout_cases = f.strings("holdout_load_cases");
  for (const auto& id : s.holdout_cases)
    for (const auto& fit : s.fit_cases)
      if (id == fit)
        f.fail("holdout_load_cases",
               "'" + id + "' is also in fit_load_cases; a held-out case must not be fitted");
  if (f.has("grouping")) parse_grouping(f.at("grouping"), where + ".grouping", s);
  s.regularization = f.number("regularization", 0.0, 0.0, false);
  if (s.regularization > 0.0 && !s.per_spring)
    f.fail("regularization", "only applies to per-spring fits (\"grouping\": \"per_spring\")");
  if (f.has("mass")) {
    const auto& m = f.at("mass");
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
  s.mesh.strain_points = f.integer("strain_points", 0, 0);
  if (s.mesh.strain_points > 4) f.fail("strain_points", "must be 0 .. 4 points per direction");
  s.max_iterations = f.integer("max_iterations", s.max_iterations, 1);
  s.field_samples = f.integer("field_samples", s.field_samples, 2);
  // The matrix approach fits central springs only: off by default with cell terms.
  const bool cell_terms = s.mesh.volume_terms || s.mesh.shear_terms || s.mesh.strain_points > 0;
  request.matrix_approach = f.boolean("matrix_approach", !cell_terms);
  if (request.matrix_approach && cell_terms)
    f.fail("matrix_approach",
           "fits central springs only and cannot compare a model with volume_terms, "
           "shear_terms or strain_points; set it to false");
  request.acceleration_objective = f.boolean("acceleration_objective", true);
  request.target_percent_e_rms = f.number("target_percent_e_rms", 0.0, 0.0, false);
  if (f.has("generalisation")) {
    if (s.per_spring || !s.gamma_sweep.empty())
      f.fail("generalisation",
             "chooses the grouping itself; remove grouping.per_spring and "
             "grouping.gamma_sweep");
    parse_generalisation(f.at("generalisation"), where + ".generalisation", !s.fit_cases.empty(),
                         request);
    request.generalisation->target_percent_e_rms = request.target_percent_e_rms;
  }
  return request;
}

}  // namespace isospring::io
