// The subcommands of the ffdaabb CLI. Each cmd_*.cpp defines one add<Name>Command function that
// adds its subcommand (options bound to a settings struct) and sets the action to run.
#pragma once

#include "ffdaabb/scene.h"

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace ffd::cli {

inline constexpr const char* kVersion = "0.1.0";

/// The action of the subcommand the user picked; set by the subcommand's parse callback.
/// Returns the process exit status.
using Action = std::function<int()>;

void registerCommands(CLI::App& app);
int runSelected(CLI::App& app);

void addMeshInfoCommand(CLI::App& app, Action& action);
void addRunCommand(CLI::App& app, Action& action);
void addBenchCommand(CLI::App& app, Action& action);
void addRenderCommands(CLI::App& app, Action& action);
void addSoakCommand(CLI::App& app, Action& action);
void addSettingsCommand(CLI::App& app, Action& action);

} // namespace ffd::cli
