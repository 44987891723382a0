// The frontier's report.json, report.md and figure (frontier.hpp).
#include <algorithm>
#include <cmath>

#include <fstream>
#include <sstream>

#include "frontier_stages.hpp"
#include "isospring/fitting/pareto.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/plot.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/frontier.hpp"

namespace isospring::workflows {

namespace {

constexpr const char* kFigure = "frontier.png";

std::string num(double x) {
  return std::isfinite(x) ? io::format_number(x, 3) : "-";
}

// JSON has no NaN: a missing number is null.
nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

nlohmann::json row_json(const FrontierRow& r) {
  return {{"kind", r.kind.name},
          {"volume_terms", r.kind.volume_terms},
          {"shear_terms", r.kind.shear_terms},
          {"strain_points_per_direction", r.kind.strain_points},
          {"reduced", r.kind.reduced},
          {"failure", r.failure},
          {"model", r.model},
          {"reach", r.reach},
          {"gamma", r.gamma},
          {"prior_weight", r.prior_weight},
          {"parameters", r.parameters},
          {"springs", r.springs},
          {"cell_volume_terms", r.cell_volume_terms},
          {"cell_shear_terms", r.cell_shear_terms},
          {"strain_point_count", r.strain_point_terms},
          {"reduced_basis", r.reduced_basis},
          {"reduced_of", r.reduced_of},
          {"cross_validation_worst", number_or_null(r.cross_validation_worst)},
          {"worst_validation", number_or_null(r.worst_validation)},
          {"worst_validation_case", r.worst_case},
          {"worst_fitted", number_or_null(r.worst_fitted)},
          {"measured_step_us", number_or_null(r.measured_step_us)},
          {"measured_step_us_min", number_or_null(r.measured_min_us)},
          {"measured_step_us_max", number_or_null(r.measured_max_us)},
          {"estimated_step_us", number_or_null(r.estimated_step_us)},
          {"measured_over_estimated", number_or_null(r.measured_step_us / r.estimated_step_us)},
          {"engines", r.engines},
          {"pareto", r.pareto},
          {"seconds", r.seconds}};
}

std::string engines_cell(const std::vector<std::string>& engines) {
  std::string text;
  for (const std::string& e : engines) text += (text.empty() ? "" : ", ") + e;
  return text.empty() ? "-" : text;
}

// The numbers row_json writes as null when not finite come back as NaN.
double number_of(const nlohmann::json& j, const char* key) {
  return j.at(key).is_null() ? NAN : j.at(key).get<double>();
}

FrontierRow row_from_json(const nlohmann::json& j) {
  FrontierRow r;
  r.kind = {j.at("kind").get<std::string>(), j.at("volume_terms").get<bool>(),
            j.at("shear_terms").get<bool>(), j.at("strain_points_per_direction").get<int>(),
            j.at("reduced").get<bool>()};
  r.failure = j.at("failure").get<std::string>();
  r.model = j.at("model").get<std::string>();
  r.reach = j.at("reach").get<int>();
  r.gamma = j.at("gamma").get<double>();
  r.prior_weight = j.at("prior_weight").get<double>();
  r.parameters = j.at("parameters").get<int>();
  r.springs = j.at("springs").get<size_t>();
  r.cell_volume_terms = j.at("cell_volume_terms").get<size_t>();
  r.cell_shear_terms = j.at("cell_shear_terms").get<size_t>();
  r.strain_point_terms = j.at("strain_point_count").get<size_t>();
  r.reduced_basis = j.at("reduced_basis").get<int>();
  r.reduced_of = j.at("reduced_of").get<std::string>();
  r.cross_validation_worst = number_of(j, "cross_validation_worst");
  r.worst_validation = number_of(j, "worst_validation");
  r.worst_case = j.at("worst_validation_case").get<std::string>();
  r.worst_fitted = number_of(j, "worst_fitted");
  r.measured_step_us = number_of(j, "measured_step_us");
  r.measured_min_us = number_of(j, "measured_step_us_min");
  r.measured_max_us = number_of(j, "measured_step_us_max");
  r.estimated_step_us = number_of(j, "estimated_step_us");
  r.engines = j.at("engines").get<std::vector<std::string>>();
  r.pareto = j.at("pareto").get<bool>();
  r.seconds = j.at("seconds").get<double>();
  return r;
}

}  // namespace

FrontierResult frontier_result_from_json(const nlohmann::json& report, const std::string& source) {
  try {
    const nlohmann::json& frontier = report.at("frontier");
    FrontierResult result;
    result.machine = frontier.at("machine").get<std::string>();
    for (const nlohmann::json& o : frontier.at("objects")) {
      FrontierObject object;
      object.name = o.at("object").get<std::string>();
      object.training_cases = o.at("training_cases").get<size_t>();
      object.validation_cases = o.at("validation_cases").get<size_t>();
      object.published_e_rms = o.at("published_percent_e_rms").get<double>();
      object.seconds = o.at("seconds").get<double>();
      object.complete = o.at("complete").get<bool>();
      for (const nlohmann::json& r : o.at("rows")) object.rows.push_back(row_from_json(r));
      result.objects.push_back(std::move(object));
    }
    return result;
  } catch (const nlohmann::json::exception& e) {
    throw nurbs::InputError(source + ": not a report.json of `isospring thesis --frontier` (" +
                            e.what() + "); give the report.json a frontier run wrote");
  }
}

FrontierResult read_frontier_report(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw nurbs::InputError(path.string() + ": cannot be read; check the path");
  std::stringstream text;
  text << in.rdbuf();
  return frontier_result_from_json(
      io::parse_json_text(text.str(), path.string(), "frontier report.json"), path.string());
}

FrontierResult combine_frontier_results(const std::vector<FrontierResult>& results) {
  const std::vector<FrontierKind> kinds = frontier_kinds();
  auto order = [&](const FrontierRow& row) {
    const auto k = std::find_if(kinds.begin(), kinds.end(), [&](const FrontierKind& kind) {
      return kind.name == row.kind.name;
    });
    return k - kinds.begin();  // unknown kinds last
  };
  FrontierResult combined;
  for (const FrontierResult& r : results) {
    combined.machine += (combined.machine.empty() ? "" : " | ") + r.machine;
    for (const FrontierObject& o : r.objects) {
      auto same = std::find_if(combined.objects.begin(), combined.objects.end(),
                               [&](const FrontierObject& c) { return c.name == o.name; });
      if (same == combined.objects.end()) {
        combined.objects.push_back(o);
        continue;
      }
      // The later run's rows replace the earlier run's of the same kind (runs of single kinds
      // complete an object), in frontier_kinds() order; the Pareto set is of the merged rows.
      FrontierObject merged = o;
      for (const FrontierRow& earlier : same->rows)
        if (std::none_of(o.rows.begin(), o.rows.end(), [&](const FrontierRow& row) {
              return row.kind.name == earlier.kind.name;
            }))
          merged.rows.push_back(earlier);
      std::stable_sort(
          merged.rows.begin(), merged.rows.end(),
          [&](const FrontierRow& a, const FrontierRow& b) { return order(a) < order(b); });
      merged.seconds += same->seconds;
      const bool every_kind =
          std::all_of(kinds.begin(), kinds.end(), [&](const FrontierKind& kind) {
            return std::any_of(merged.rows.begin(), merged.rows.end(),
                               [&](const FrontierRow& row) { return row.kind.name == kind.name; });
          });
      merged.complete = (o.complete && same->complete) || (o.complete && every_kind);
      frontier::mark_pareto(merged);
      *same = std::move(merged);
    }
  }
  return combined;
}

nlohmann::json frontier_report_json(const FrontierResult& result) {
  nlohmann::json report = io::report_header("thesis", io::isospring_version(), "");
  nlohmann::json& frontier = report["frontier"];
  frontier["machine"] = result.machine;
  frontier["objects"] = nlohmann::json::array();
  for (const FrontierObject& o : result.objects) {
    nlohmann::json j = {{"object", o.name},
                        {"training_cases", o.training_cases},
                        {"validation_cases", o.validation_cases},
                        {"published_percent_e_rms", o.published_e_rms},
                        {"seconds", o.seconds},
                        {"complete", o.complete},
                        {"rows", nlohmann::json::array()}};
    for (const FrontierRow& r : o.rows) j["rows"].push_back(row_json(r));
    frontier["objects"].push_back(j);
  }
  return report;
}

io::MarkdownReport frontier_report_markdown(const FrontierResult& result,
                                            const std::string& figure) {
  io::MarkdownReport md;
  md.heading(1, "isospring thesis --frontier: cost against accuracy, per object");
  md.paragraph(
      "Per [S15] object and model kind: the model calibrated for generalisation within the kind "
      "(3-fold cross-validation over the load suite's training cases chooses reach, gamma and "
      "per-spring weight; the choice refitted on all training cases), its worst held-out "
      "%e_rms on the control points over the validation cases (never fitted; [S15]'s own cases "
      "among them), the worst over the training cases, the cost of one engine step measured "
      "with the runtime on that model (one force and one Jacobian-vector product evaluation, "
      "median CPU time of repeated calls) beside step_cost's estimate (forces only, per-term "
      "costs from bench_runtime), and the engines whose export accepts the model. Reduced: the "
      "modal model of the most accurate kind (lowest natural modes plus the static responses of "
      "the training loads; its step: the reduced step plus the whole displacement field), "
      "its error the static response. Pareto: no other kind of the object is at most as costly "
      "(measured) and at most as wrong (worst held-out), and better in one.");
  md.paragraph("Machine: " + result.machine + ".");
  std::vector<std::vector<std::string>> rows;
  for (const FrontierObject& o : result.objects)
    for (const FrontierRow& r : o.rows) {
      if (!r.failure.empty()) {
        rows.push_back({o.name, r.kind.name, "failed: " + r.failure, "-", "-", "-", "-", "-", "-",
                        "-", num(r.seconds)});
        continue;
      }
      rows.push_back({o.name, r.kind.name, r.model,
                      num(r.worst_validation) + " (" + r.worst_case + ")", num(r.worst_fitted),
                      num(r.measured_step_us) + " (" + num(r.measured_min_us) + "-" +
                          num(r.measured_max_us) + ")",
                      num(r.estimated_step_us), num(r.measured_step_us / r.estimated_step_us),
                      engines_cell(r.engines), r.pareto ? "**yes**" : "", num(r.seconds)});
    }
  md.table({"object", "kind", "model (chosen within the kind)", "worst held-out %e_rms (case)",
            "worst fitted", "step [us] measured (min-max)", "estimate [us]", "measured / estimate",
            "engines", "Pareto", "time [s]"},
           rows);
  std::vector<std::string> published;
  for (const FrontierObject& o : result.objects)
    published.push_back(o.name + ": [S15] fitted-case %e_rms " + num(o.published_e_rms) + ", " +
                        std::to_string(o.training_cases) + " training and " +
                        std::to_string(o.validation_cases) + " validation cases, " +
                        num(o.seconds) + " s" +
                        (o.complete ? "" : " (INCOMPLETE: the run stopped before its last kind)"));
  md.bullets(published);
  if (!figure.empty())
    md.paragraph("![Worst held-out %e_rms against the measured step cost](" + figure + ")");
  return md;
}

std::vector<std::string> frontier_output_files() {
  return {"report.json", "report.md", kFigure};
}

void write_frontier_outputs(const std::filesystem::path& out_dir, const FrontierResult& result) {
  std::filesystem::create_directories(out_dir);
  std::vector<io::PlotSeries> series;
  std::vector<std::vector<bool>> pareto;
  for (const FrontierObject& o : result.objects) {
    io::PlotSeries s;
    s.name = o.name;
    pareto.emplace_back();
    for (const FrontierRow& r : o.rows) {
      if (!r.failure.empty()) continue;
      s.x.push_back(r.measured_step_us);
      s.y.push_back(r.worst_validation);
      pareto.back().push_back(r.pareto);
    }
    series.push_back(s);
  }
  io::PlotOptions plot;
  plot.title = "Cost against accuracy per model kind (filled and joined: Pareto-optimal)";
  plot.xlabel = "engine step, force + Jacobian-vector product [us, CPU, measured]";
  plot.ylabel = "worst held-out %e_rms";
  plot.log_y = true;
  plot.width = 1000;
  plot.height = 650;
  const bool figure = io::plot_frontier(out_dir / kFigure, series, pareto, plot);
  io::write_json_report(out_dir / "report.json", frontier_report_json(result));
  frontier_report_markdown(result, figure ? kFigure : "").write(out_dir / "report.md");
}

}  // namespace isospring::workflows
