// The `isospring` command-line program.
//
// Exit codes (stable, for scripts):
//   0  success
//   1  bad input: a file, field or value is wrong (the message names it and the fix), an output
//      that cannot be written or would overwrite an input, a case too large for the memory
//   2  usage error: unknown subcommand or option, missing argument
//   3  the computation failed (e.g. a fit did not converge, a solve overflowed); nothing wrong
//      was written
//   4  internal error (a bug: please report it with the command line)
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <utility>
#include <vector>

#include "command.hpp"
#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {
std::vector<std::pair<int, CommandSetup>>& registry() {
  static std::vector<std::pair<int, CommandSetup>> commands;
  return commands;
}
}  // namespace

CommandRegistrar::CommandRegistrar(int order, CommandSetup setup) {
  registry().emplace_back(order, setup);
}

void add_registered_commands(CLI::App& app) {
  auto commands = registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, setup] : commands) setup(app);
}

}  // namespace isospring::apps

int main(int argc, char** argv) {
  // OMP_WAIT_POLICY=passive unless the user chose a policy (docs/performance.md): CHOLMOD's
  // OpenMP threads then sleep instead of spinning at barriers on a loaded machine. libgomp reads
  // it before main, so this re-executes the program once with it set.
  isospring::analysis::restart_with_passive_threads(argv);
  CLI::App app{
      "isospring: from a CAD part to a calibrated NURBS mass-spring model.\n"
      "Pipeline: CAD -> NURBS -> refinement -> IGA reference -> NMSM calibration ->\n"
      "measured-data loop -> export. Run `isospring demo` for the whole pipeline on a\n"
      "shipped part, or `isospring COMMAND --help` for one step.",
      "isospring"};
  app.set_version_flag("--version", std::string("isospring ") + ISOSPRING_VERSION);
  app.require_subcommand(1);
  isospring::apps::add_registered_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const isospring::nurbs::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory; try a coarser discretization\n";
    return 3;
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return 4;
  }
  return 0;
}
