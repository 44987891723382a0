// `isospring thesis -o OUTDIR [--quick]`: regenerates the [S15] chapter-5 tables beside the
// published numbers; the work is workflows::run_thesis (isospring/workflows/thesis_command.hpp).
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/thesis_command.hpp"

namespace isospring::apps {
namespace {

struct ThesisOptions {
  std::string output;
  bool quiet = false;
  workflows::ThesisCommandOptions run;
};

void run_thesis(const ThesisOptions& options) {
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
  cmd->add_flag("--generalisation-only", options->run.generalisation_only,
                "Only the generalisation table (load suite, cross-validated freedom)");
  cmd->add_option("--object", options->run.objects,
                  "Generalisation table: only this object (repeatable; default all six)")
      ->check(CLI::IsMember({"square", "circle", "ellipse", "cube", "torus", "coupled_spheroid"}));
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_thesis(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(95, setup_thesis);
}  // namespace isospring::apps
