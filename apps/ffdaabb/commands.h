// The subcommands of the ffdaabb CLI. Each cmd_*.cpp defines one add<Name>Command function that
// adds its subcommand (options bound to a settings struct) and sets the callback to run.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace ffd::cli {

inline constexpr const char* kVersion = "0.1.0";

/// The action of the subcommand the user picked; set by the subcommand's parse callback.
/// Returns the process exit status.
using Action = std::function<int()>;

void registerCommands(CLI::App& app);
int runSelected(CLI::App& app);

/// Called by each subcommand's file.
void addMeshInfoCommand(CLI::App& app, Action& action);

} // namespace ffd::cli
