// `isospring eval IN --at u[,v[,w]] ...`: physical points (and first derivatives) of a patch.
// The work is workflows::run_eval, workflows::eval_text and workflows::eval_json
// (isospring/workflows/eval_command.hpp).
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/workflows/eval_command.hpp"

namespace isospring::apps {
namespace {

struct EvalOptions {
  workflows::EvalCommandOptions run;
  bool json = false;
};

void setup_eval(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand("eval", "Evaluate patch points (and derivatives)");
  cmd->add_option("IN", options->run.input, "Patch file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--at", options->run.at, "Parameters u[,v[,w]]; repeat for several points")
      ->required();
  cmd->add_option("--patch", options->run.patch, "Patch index (default 0)");
  cmd->add_flag("--derivs", options->run.derivatives, "Also print dX/du, dX/dv, dX/dw");
  cmd->add_flag("--json", options->json,
                "Print JSON instead: {\"points\": [{\"at\", \"point\", \"derivatives\"}]}, "
                "full precision");
  cmd->callback([options] {
    const workflows::EvalCommandResult r =
        workflows::run_eval(io::read_patch_file(options->run.input), options->run);
    if (options->json)
      std::cout << workflows::eval_json(r).dump(2) << "\n";
    else
      std::cout << workflows::eval_text(r);
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(30, setup_eval);
}  // namespace isospring::apps
