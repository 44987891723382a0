// `isospring thesis -o OUTDIR [--quick]`: regenerates the [S15] chapter-5 tables beside the
// published numbers; the work is workflows::run_thesis (isospring/workflows/thesis_command.hpp).
#include <algorithm>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/frontier.hpp"
#include "isospring/workflows/thesis_command.hpp"

namespace isospring::apps {
namespace {

struct ThesisOptions {
  std::string output;
  bool quiet = false;
  bool frontier = false;
  std::vector<std::string> combine;  // --frontier --combine: report.json files of earlier runs
  std::vector<std::string> kinds;    // --frontier --kind: keys of kKindKeys
  workflows::ThesisCommandOptions run;
};

// --kind's keys, in the order of workflows::frontier_kinds().
const std::vector<std::string> kKindKeys = {"springs",  "volume",   "volume-shear", "points-1",
                                            "points-2", "points-3", "reduced"};

std::vector<workflows::FrontierKind> chosen_kinds(const std::vector<std::string>& keys) {
  const std::vector<workflows::FrontierKind> all = workflows::frontier_kinds();
  std::vector<workflows::FrontierKind> kinds;
  for (size_t k = 0; k < kKindKeys.size(); ++k)
    if (std::find(keys.begin(), keys.end(), kKindKeys[k]) != keys.end()) kinds.push_back(all[k]);
  return kinds;
}

// --frontier: the outputs are rewritten after every object, so a run stopped early keeps the
// objects that finished.
void run_frontier(const ThesisOptions& options) {
  const io::Progress progress("thesis", options.quiet);
  const std::filesystem::path out_dir =
      output_folder(options.output, {}, workflows::frontier_output_files());
  workflows::FrontierOptions run;
  run.objects = options.run.objects;
  run.quick = options.run.quick;
  run.kinds = chosen_kinds(options.kinds);
  run.on_object = [&](const workflows::FrontierResult& partial) {
    workflows::write_frontier_outputs(out_dir, partial);
  };
  workflows::FrontierResult result;
  if (!options.combine.empty()) {
    std::vector<workflows::FrontierResult> runs;
    for (const std::string& file : options.combine)
      runs.push_back(workflows::read_frontier_report(file));
    result = workflows::combine_frontier_results(runs);
  } else {
    result = workflows::run_frontier(run, progress);
  }
  workflows::write_frontier_outputs(out_dir, result);
  progress("wrote " + (out_dir / "report.md").string());
}

void run_thesis(const ThesisOptions& options) {
  if (!options.combine.empty() && !options.frontier)
    throw CLI::ValidationError("--combine", "only with --frontier");
  if (!options.kinds.empty() && !options.frontier)
    throw CLI::ValidationError("--kind", "only with --frontier");
  if (options.frontier) return run_frontier(options);
  const io::Progress progress("thesis", options.quiet);
  // Checked first: the tables take minutes, a folder that cannot be written must fail at once.
  const std::filesystem::path out_dir =
      output_folder(options.output, {}, {"report.json", "report.md"});
  const workflows::ThesisReport report = workflows::run_thesis(options.run, progress);
  io::write_json_report(out_dir / "report.json", report.json);
  report.markdown.write(out_dir / "report.md");
  progress("wrote " + (out_dir / "report.md").string());
}

void setup_thesis(CLI::App& app) {
  auto options = std::make_shared<ThesisOptions>();
  CLI::App* cmd = app.add_subcommand(
      "thesis",
      "Regenerate the [S15] chapter-5 NMSM tables (six objects) beside the published numbers");
  cmd->footer(
      "Writes OUTDIR/report.json and OUTDIR/report.md. Protocol: "
      "examples/thesis/README.md.");
  cmd->add_option("-o,--output", options->output, "Output folder (created if missing)")->required();
  cmd->add_flag("--quick", options->run.quick,
                "Skip the cube 6^3 and 9^3 of Table 5.4 and the cube's per-spring fit; fewer "
                "candidates and iterations in the generalisation table");
  CLI::Option* generalisation =
      cmd->add_flag("--generalisation-only", options->run.generalisation_only,
                    "Only the generalisation table (load suite, cross-validated freedom)");
  cmd->add_flag("--frontier", options->frontier,
                "Only the cost/accuracy frontier: per object and model kind, the worst held-out "
                "%e_rms, the engine step measured with the runtime, the engines, the Pareto set; "
                "writes OUTDIR/frontier.png too (docs/frontier.md)")
      ->excludes(generalisation);
  cmd->add_option("--combine", options->combine,
                  "With --frontier: no run; the report.json files of earlier frontier runs (e.g. "
                  "one object each) as one report and figure")
      ->check(CLI::ExistingFile);
  cmd->add_option("--object", options->run.objects,
                  "Generalisation table or frontier: only this object (repeatable; default all "
                  "six)")
      ->check(CLI::IsMember({"square", "circle", "ellipse", "cube", "torus", "coupled_spheroid"}));
  cmd->add_option("--kind", options->kinds,
                  "Frontier: only this model kind (repeatable; default all): springs, volume, "
                  "volume-shear, points-1, points-2, points-3 (strain points per direction), "
                  "reduced (of the most accurate kind run); --combine merges such runs by kind")
      ->check(CLI::IsMember(kKindKeys));
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_thesis(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(95, setup_thesis);
}  // namespace isospring::apps
