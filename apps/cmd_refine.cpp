// `isospring refine IN -o OUT`: exact h-, p- and k-refinement of every patch in a patch file.
// Order of operations: degree elevation first, then explicit knot insertion, then uniform
// splitting (elevating before splitting is k-refinement: maximal continuity). The work is
// workflows::run_refine and workflows::refine_report (isospring/workflows/refine_command.hpp).
#include <iostream>
#include <memory>

#include "cli_checks.hpp"
#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/workflows/refine_command.hpp"

namespace isospring::apps {
namespace {

struct RefineOptions {
  std::string output;
  double max_memory_gb = 0;  // 0: the available memory
  bool quiet = false;
  workflows::RefineCommandOptions run;
};

void run_refine(RefineOptions options) {
  check_output_file(options.output, {options.run.input});
  const MemoryLimit limit = memory_limit(options.max_memory_gb);
  options.run.memory_limit_bytes = limit.bytes;
  options.run.memory_source = limit.source;
  const workflows::RefineCommandResult r =
      workflows::run_refine(io::read_patch_file(options.run.input), options.run);
  io::write_patch_file(options.output, r.after);
  FileReport report("refine", options.run.input, options.output);
  workflows::refine_report(r, options.run, options.output, report.json, report.markdown);
  report.write();
  size_t points = 0;
  int elements = 0;
  for (const auto& p : r.after) {
    points += static_cast<size_t>(p.num_points());
    elements += p.num_elements();
  }
  if (!options.quiet)
    std::cout << "wrote " << options.output << ": " << r.after.size() << " patches, " << points
              << " control points, " << elements << " elements\n";
}

void setup_refine(CLI::App& app) {
  auto options = std::make_shared<RefineOptions>();
  CLI::App* cmd = app.add_subcommand(
      "refine", "Refine a patch file exactly (degree elevation, knot insertion, uniform h)");
  cmd->add_option("IN", options->run.input, "Input patch file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Output patch file")->required();
  cmd->add_option("--h", options->run.h, "Split every knot span into N equal spans")
      ->check(kPositive);
  cmd->add_option("--elevate", options->run.elevate,
                  "Raise the degree by T in all directions, or T_u T_v [T_w] per direction")
      ->check(kNonNegative);
  cmd->add_option("--insert", options->run.insert,
                  "Insert knots: DIRECTION=KNOTS, e.g. --insert u=0.3,0.3 --insert v=0.5 "
                  "(repeat a value to raise its multiplicity)");
  cmd->add_option("--max-memory", options->max_memory_gb,
                  "Refuse (exit 1) a refinement needing more than this many GB (default: the "
                  "available memory)")
      ->check(kPositive);
  cmd->add_flag("-q,--quiet", options->quiet, "Do not print the \"wrote ...\" line");
  cmd->footer("Order: --elevate, then --insert, then --h (k-refinement keeps C^(p-1)).");
  cmd->callback([options] { run_refine(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(20, setup_refine);
}  // namespace isospring::apps
