// `isospring eval IN --at u[,v[,w]] ...`: physical points (and first derivatives) of a patch.
#include <iomanip>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include "cli_util.hpp"
#include "command.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct EvalOptions {
  std::string input;
  std::vector<std::string> at;
  int patch = 0;
  bool derivs = false;
  bool json = false;
};

nurbs::Param parse_param(const std::string& text, const nurbs::Patch& patch) {
  const std::vector<double> values = parse_number_list(text, "--at");
  if (static_cast<int>(values.size()) != patch.param_dim())
    throw nurbs::InputError("--at " + text + ": the patch has parametric dimension " +
                            std::to_string(patch.param_dim()) + ", so give " +
                            std::to_string(patch.param_dim()) + " comma-separated parameters");
  nurbs::Param u{0, 0, 0};
  for (int d = 0; d < patch.param_dim(); ++d) {
    u[d] = values[static_cast<size_t>(d)];
    if (u[d] < patch.param_min(d) || u[d] > patch.param_max(d))
      throw nurbs::InputError("--at " + text + ": parameter " + std::to_string(u[d]) +
                              " lies outside [" + std::to_string(patch.param_min(d)) + ", " +
                              std::to_string(patch.param_max(d)) + "] in direction " +
                              std::to_string(d));
  }
  return u;
}

void setup_eval(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand("eval", "Evaluate patch points (and derivatives)");
  cmd->add_option("IN", options->input, "Patch file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--at", options->at, "Parameters u[,v[,w]]; repeat for several points")
      ->required();
  cmd->add_option("--patch", options->patch, "Patch index (default 0)");
  cmd->add_flag("--derivs", options->derivs, "Also print dX/du, dX/dv, dX/dw");
  cmd->add_flag("--json", options->json,
                "Print JSON instead: {\"points\": [{\"at\", \"point\", \"derivatives\"}]}, "
                "full precision");
  cmd->callback([options] {
    const auto patches = io::read_patch_file(options->input);
    if (options->patch < 0 || options->patch >= static_cast<int>(patches.size()))
      throw nurbs::InputError("--patch " + std::to_string(options->patch) + ": the file has " +
                              std::to_string(patches.size()) + " patches (0-based index)");
    const nurbs::Patch& patch = patches[static_cast<size_t>(options->patch)];
    std::cout << std::setprecision(17);
    nlohmann::json points = nlohmann::json::array();
    for (const std::string& text : options->at) {
      const nurbs::Param u = parse_param(text, patch);
      const nurbs::PatchDerivatives der = patch.derivatives(u, 1);
      // Control points or weights near the limits of a double (e.g. 1e308) overflow in the
      // rational sums; a failure beats printing inf or -nan as if it were a point.
      const bool finite = der.point.allFinite() &&
                          (!options->derivs || der.first.leftCols(patch.param_dim()).allFinite());
      if (!finite)
        throw std::runtime_error(options->input + ": patch " + std::to_string(options->patch) +
                                 " at " + text +
                                 ": the point or its derivatives overflow a double (not finite); "
                                 "check the control points and weights of the patch");
      if (options->json) {
        nlohmann::json entry = {
            {"at", std::vector<double>(u.begin(), u.begin() + patch.param_dim())},
            {"point", {der.point.x(), der.point.y(), der.point.z()}}};
        if (options->derivs)
          for (int d = 0; d < patch.param_dim(); ++d)
            entry["derivatives"].push_back({der.first(0, d), der.first(1, d), der.first(2, d)});
        points.push_back(entry);
        continue;
      }
      std::cout << text << ": " << der.point.x() << " " << der.point.y() << " " << der.point.z();
      if (options->derivs)
        for (int d = 0; d < patch.param_dim(); ++d)
          std::cout << " | d"
                    << "uvw"[d] << ": " << der.first(0, d) << " " << der.first(1, d) << " "
                    << der.first(2, d);
      std::cout << "\n";
    }
    if (options->json)
      std::cout << nlohmann::json{{"patch", options->patch}, {"points", points}}.dump(2) << "\n";
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(30, setup_eval);
}  // namespace isospring::apps
