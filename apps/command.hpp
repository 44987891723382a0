#pragma once
// Subcommands of the `isospring` program register themselves here, one file each (cmd_*.cpp), so
// adding a command never touches main.cpp.
//
// A subcommand's callback reports bad input by throwing nurbs::InputError (exit status 1); CLI11
// reports usage errors (exit status 2). See main.cpp for the full list of exit codes.
#include <CLI/CLI.hpp>
#include <functional>

namespace isospring::apps {

/// Adds one subcommand (its options and callback) to the top-level app.
using CommandSetup = void (*)(CLI::App& app);

/// Registers a subcommand; `order` sorts `--help` in pipeline order (10 info ... 90 demo).
struct CommandRegistrar {
  CommandRegistrar(int order, CommandSetup setup);
};

/// Calls every registered setup in order.
void add_registered_commands(CLI::App& app);

}  // namespace isospring::apps

#define ISOSPRING_REGISTER_COMMAND(order, setup) \
  static const ::isospring::apps::CommandRegistrar isospring_registrar_##setup(order, setup)
