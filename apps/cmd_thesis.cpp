// `isospring thesis -o OUTDIR [--quick]`: regenerates the [S15] chapter-5 tables that isospring
// can reproduce (square and cube: Tables 5.3, 5.4, 5.5, 5.6, 5.7) beside the published numbers.
// Protocol: fitting/thesis_experiments.hpp and examples/thesis/README.md.
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "command.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/fitting/thesis_experiments.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct ThesisOptions {
  std::string output;
  bool quick = false;
  bool quiet = false;
};

// The gamma values every grouped fit sweeps (Algorithm 5.1, from coarse to fine).
const std::vector<double> kGammaSweep = {0.8, 0.5, 0.2, 0.1, 0.05, 0.01, 0.001};

struct Row {
  std::string object, protocol;
  int net = 0, degree = 2;
  fitting::CalibrationResult result;
  double published_rms = 0, published_max = 0;
};

fitting::ThesisObject make_object(const std::string& name, int n, int degree) {
  return name == "square" ? fitting::thesis_square(n, degree) : fitting::thesis_cube(n, degree);
}

// The displacement fit of one object with the fitted case `fit_case` and a gamma sweep.
Row run(const std::string& name, int n, int degree, const std::string& fit_case,
        bool matrix_approach, const io::Progress& progress) {
  const fitting::ThesisObject object = make_object(name, n, degree);
  fitting::CalibrationSettings settings;
  settings.fit_cases = {fit_case};
  settings.holdout_cases = {"holdout_x", "holdout_v1"};
  settings.gamma_sweep = kGammaSweep;
  settings.matrix_approach = matrix_approach;
  progress(name + " " + std::to_string(n) +
           (object.problem.patches[0].param_dim() == 3 ? "^3" : "^2") + " degree " +
           std::to_string(degree) + ", fitted case " + fit_case);
  Row row{name,
          fit_case,
          n,
          degree,
          fitting::calibrate(object.problem, settings),
          object.published_e_rms,
          object.published_e_max};
  return row;
}

std::string num(double x) {
  return io::format_number(x, 3);
}
std::string published(double x) {
  return x > 0 ? num(x) : "-";
}

nlohmann::json row_json(const Row& r) {
  nlohmann::json j = {{"object", r.object},
                      {"net", r.net},
                      {"degree", r.degree},
                      {"fitted_case", r.protocol},
                      {"gamma", r.result.gamma},
                      {"groups", r.result.parameters},
                      {"springs", r.result.mesh.network.springs.size()},
                      {"percent_e_rms", r.result.fit[0].control.percent_e_rms},
                      {"percent_e_max", r.result.fit[0].control.percent_e_max},
                      {"fit_seconds", r.result.fit_seconds},
                      {"published_percent_e_rms", r.published_rms},
                      {"published_percent_e_max", r.published_max}};
  for (const auto& h : r.result.holdout)
    j["holdout"].push_back({{"id", h.id},
                            {"percent_e_rms", h.control.percent_e_rms},
                            {"percent_e_max", h.control.percent_e_max}});
  for (const auto& s : r.result.sweep)
    j["sweep"].push_back(
        {{"gamma", s.gamma}, {"groups", s.groups}, {"percent_e_rms", s.percent_e_rms}});
  for (const auto& m : r.result.matrix)
    j["matrix_approach"].push_back(
        {{"method", m.method},
         {"relative_frobenius_residual", m.fit.relative_residual},
         {"negative_springs", m.fit.negative_springs},
         {"percent_e_rms", m.solved ? m.fit_cases[0].control.percent_e_rms : NAN},
         {"percent_e_max", m.solved ? m.fit_cases[0].control.percent_e_max : NAN}});
  return j;
}

std::vector<std::string> error_cells(const Row& r) {
  return {num(r.result.fit[0].control.percent_e_rms), num(r.result.fit[0].control.percent_e_max),
          published(r.published_rms), published(r.published_max)};
}

std::string holdout_cell(const Row& r) {
  std::string text;
  for (const auto& h : r.result.holdout)
    text += (text.empty() ? "" : ", ") + num(h.control.percent_e_rms);
  return text;
}

void run_thesis(const ThesisOptions& options) {
  const io::Progress progress("thesis", options.quiet);
  const std::filesystem::path out_dir(options.output);
  if (std::filesystem::exists(out_dir) && !std::filesystem::is_directory(out_dir))
    throw nurbs::InputError("-o " + options.output +
                            ": exists and is not a folder; give a folder for the outputs");
  nlohmann::json report = io::report_header("thesis", ISOSPRING_VERSION, "");
  io::MarkdownReport md;
  md.heading(1, "isospring thesis: [S15] chapter 5 regenerated");
  md.paragraph(
      "Protocol: examples/thesis/README.md. Errors on the control points of the fitted load case; "
      "held-out cases (traction on u1 along x, on v1 along -y) show generalisation. Every grouped "
      "fit sweeps gamma over {0.8, 0.5, 0.2, 0.1, 0.05, 0.01, 0.001} and keeps the best. Circle, "
      "ellipse, torus and coupled spheroid are not reproduced (their supports and loads are not "
      "stated precisely enough in [S15]).");

  // Table 5.3 (square and cube), both load protocols.
  std::vector<std::vector<std::string>> rows53;
  for (const std::string name : {"square", "cube"})
    for (const std::string fit_case : {"fit", "fit_points"}) {
      const Row r = run(name, 6, 2, fit_case, true, progress);
      report["table_5_3"].push_back(row_json(r));
      auto cells = error_cells(r);
      cells.insert(cells.begin(),
                   {name, fit_case == "fit" ? "traction on u1" : "forces on u1 points",
                    std::to_string(r.result.parameters), num(r.result.gamma)});
      cells.push_back(holdout_cell(r));
      cells.push_back(num(r.result.fit_seconds));
      rows53.push_back(cells);
      // Table 5.6: the matrix approach on the same springs and grouping.
      if (fit_case == "fit_points")
        for (const auto& m : r.result.matrix)
          report["table_5_6"].push_back(
              {{"object", name},
               {"nmsm", row_json(r)["percent_e_rms"]},
               {"matrix_percent_e_rms", m.solved ? m.fit_cases[0].control.percent_e_rms : NAN},
               {"matrix_percent_e_max", m.solved ? m.fit_cases[0].control.percent_e_max : NAN},
               {"relative_frobenius_residual", m.fit.relative_residual}});
    }
  md.heading(2, "Table 5.3 (6x6 and 6^3 nets, degree 2)");
  md.table({"object", "load", "groups", "gamma", "%e_rms", "%e_max", "published %e_rms",
            "published %e_max", "held-out %e_rms", "fit [s]"},
           rows53);

  // Table 5.4: net resolution.
  std::vector<std::vector<std::string>> rows54;
  for (const std::string name : {"square", "cube"})
    for (int n : {3, 4, 6, 9}) {
      if (options.quick && name == "cube" && n == 9) continue;
      const Row r = run(name, n, 2, "fit_points", false, progress);
      report["table_5_4"].push_back(row_json(r));
      auto cells = error_cells(r);
      cells.insert(cells.begin(), {name, std::to_string(n), std::to_string(r.result.parameters)});
      rows54.push_back(cells);
    }
  md.heading(2, "Table 5.4 (net resolution, degree 2, forces on u1 points)");
  md.table({"object", "net", "groups", "%e_rms", "%e_max", "published %e_rms", "published %e_max"},
           rows54);

  // Table 5.5: the gamma sweep of the 6x6 / 6^3 fits (published for the curved objects only).
  std::vector<std::vector<std::string>> rows55;
  for (const auto& entry : report["table_5_3"])
    for (const auto& s : entry["sweep"])
      rows55.push_back({entry["object"].get<std::string>(), entry["fitted_case"].get<std::string>(),
                        num(s["gamma"].get<double>()), std::to_string(s["groups"].get<int>()),
                        num(s["percent_e_rms"].get<double>())});
  md.heading(2, "Table 5.5 (gamma sweep)");
  md.table({"object", "load", "gamma", "groups", "%e_rms"}, rows55);

  // Tables 5.6 (quadratic) and 5.7 (linear): NMSM vs matrix approach.
  std::vector<std::vector<std::string>> rows56;
  const std::map<std::string, std::array<double, 4>> published56 = {
      {"square", {1.14, 2.79, 47.57, 68.82}}, {"cube", {1.73, 7.44, 93.25, 190.79}}};
  const std::map<std::string, std::array<double, 4>> published57 = {
      {"square", {1.19, 2.55, 9.86, 17.73}}, {"cube", {2.34, 11.33, 18.63, 28.65}}};
  for (int degree : {2, 1})
    for (const std::string name : {"square", "cube"}) {
      const Row r = degree == 2 ? Row{} : run(name, 6, 1, "fit_points", true, progress);
      const nlohmann::json* source = nullptr;
      nlohmann::json linear;
      if (degree == 2) {
        for (const auto& entry : report["table_5_3"])
          if (entry["object"] == name && entry["fitted_case"] == "fit_points") source = &entry;
      } else {
        linear = row_json(r);
        report["table_5_7"].push_back(linear);
        source = &linear;
      }
      const auto& p = (degree == 2 ? published56 : published57).at(name);
      for (const auto& m : (*source)["matrix_approach"])
        rows56.push_back({name, std::to_string(degree), num((*source)["percent_e_rms"]),
                          num((*source)["percent_e_max"]), m["method"].get<std::string>(),
                          m["percent_e_rms"].is_null() ? "singular" : num(m["percent_e_rms"]),
                          m["percent_e_max"].is_null() ? "singular" : num(m["percent_e_max"]),
                          num(p[0]) + " / " + num(p[1]), num(p[2]) + " / " + num(p[3])});
    }
  md.heading(2, "Tables 5.6 / 5.7 (displacement objective vs matrix approach)");
  md.table({"object", "degree", "NMSM %e_rms", "NMSM %e_max", "matrix fit", "matrix %e_rms",
            "matrix %e_max", "published NMSM", "published matrix"},
           rows56);

  io::write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  progress("wrote " + (out_dir / "report.md").string());
}

void setup_thesis(CLI::App& app) {
  auto options = std::make_shared<ThesisOptions>();
  CLI::App* cmd = app.add_subcommand(
      "thesis",
      "Regenerate the [S15] chapter-5 NMSM tables (square, cube) beside the published "
      "numbers");
  cmd->footer(
      "Writes OUTDIR/report.json and OUTDIR/report.md. Protocol: "
      "examples/thesis/README.md.");
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("--quick", options->quick, "Skip the largest net (cube 9^3)");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_thesis(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(95, setup_thesis);
}  // namespace isospring::apps
