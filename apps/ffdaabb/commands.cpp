#include "commands.h"

namespace ffd::cli {

namespace {
Action gSelected;
} // namespace

void registerCommands(CLI::App& app) {
    addMeshInfoCommand(app, gSelected);
    addRunCommand(app, gSelected);
    addBenchCommand(app, gSelected);
    addRenderCommands(app, gSelected);
    addSoakCommand(app, gSelected);
    addSettingsCommand(app, gSelected);
}

int runSelected(CLI::App&) {
    return gSelected ? gSelected() : 2;
}

} // namespace ffd::cli
