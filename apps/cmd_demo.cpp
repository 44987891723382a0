// `isospring demo`: the whole pipeline on a shipped part, into ./isospring-out/:
//   1. CAD -> NURBS      import a STEP part (examples/cad/block.step) as exact NURBS
//   2. refinement        k-refine it to the case's degrees and elements
//   3. IGA reference     linear elasticity, every load case (displacement, von Mises)
//   4. NMSM calibration  springs on the control net, stiffnesses fitted with Ceres
//   5. VTK               one .vtm for ParaView: exact Bezier geometry, fields, net, springs
//   6. exports           model.json, MuJoCo MJCF, SOFA scene; report.json and report.md
// The pipeline is workflows::run_demo (isospring/workflows/demo_command.hpp); this file finds the
// case and prints where the results are.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/demo_command.hpp"

namespace isospring::apps {
namespace {
namespace fs = std::filesystem;

struct DemoOptions {
  std::string case_file;
  std::string output = "isospring-out";
  bool quiet = false;
};

/// The shipped demo case: ./examples/demo/demo.json when run from the repository (as the README
/// does), else the copy in the source tree this program was built from.
fs::path default_case() {
  const fs::path local = fs::path("examples") / "demo" / "demo.json";
  if (fs::exists(local)) return local;
  return fs::path(ISOSPRING_SOURCE_DIR) / "examples" / "demo" / "demo.json";
}

void run_demo(const DemoOptions& options) {
  const io::Progress progress("demo", options.quiet);
  const fs::path case_path =
      options.case_file.empty() ? default_case() : fs::path(options.case_file);
  const fs::path out =
      output_folder(options.output, input_files(case_path), workflows::demo_output_files());
  const double total = workflows::run_demo(case_path, out, progress);
  if (options.quiet) return;  // --quiet: the report files say it all; nothing on stdout
  std::cout << "isospring demo finished in " << io::format_number(total, 3) << " s. Results in "
            << out.string() << "/:\n"
            << "  result.vtm        open in ParaView: paraview " << (out / "result.vtm").string()
            << "\n"
            << "  report.md         summary (report.json for scripts)\n"
            << "  model.json        calibrated spring model (isospring export converts it)\n"
            << "  model_mujoco.xml  MuJoCo MJCF; model_sofa.scn: SOFA scene\n";
}

void setup_demo(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "The whole pipeline on a shipped STEP part: import, refine, IGA reference, NMSM "
      "calibration, VTK, engine exports, report");
  cmd->add_option("-o,--output", options->output, "Output folder (default ./isospring-out)");
  cmd->add_option("--case", options->case_file,
                  "Run on another case file instead of examples/demo/demo.json");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines");
  cmd->callback([options] { run_demo(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(90, setup_demo);
}  // namespace isospring::apps
